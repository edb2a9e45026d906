// Quantities derived from the model (docs/engine.md, "Model"; Blatny et al., PRL 128, 228002, 2022).

// Strut aspect ratio of the square lattice at solid fraction phi: unit cell side L, hole side
// L sqrt(1 - phi), strut thickness t = L (1 - sqrt(1 - phi)), strut length L sqrt(1 - phi).
export function strutAspectRatio(phi) {
  const s = Math.sqrt(1 - phi);
  return (1 - s) / s;
}

// Buckling onset R_crit ~ pi^2 a^2 / 12 (Euler buckling of a clamped strut against yield).
export function bucklingR(phi) {
  const a = strutAspectRatio(phi);
  return (Math.PI * Math.PI * a * a) / 12;
}

// Speed of a non-reflecting band: c_b / V = 1 / (1 - phi) (mass balance, dense behind the front).
export function nonReflectingSpeed(phi) {
  return 1 / (1 - phi);
}

// q_y / (rho V^2) = R / S^2 (the band-speed plot's abscissa).
export function stressRatio(S, R) {
  return R / (S * S);
}
