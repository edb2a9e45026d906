// Definitions of the model the dashboard writes with (Blatny et al., PRL 128, 228002, 2022). What
// the model predicts from phi (the struts' aspect ratio, the buckling onset, the non-reflecting
// band's speed) is the engine's: the phase map's answer carries it (GET /api/v1/phase-map, model).

// q_y / (rho V^2) = R / S^2 (the band-speed plot's abscissa).
export function stressRatio(S, R) {
  return R / (S * S);
}
