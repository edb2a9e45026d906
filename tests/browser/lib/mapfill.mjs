// A phase map of known classes for the browser tests: a 5 x 5 log grid sweep over the paper's
// box (S in [1e-3, 1e-1], R in [1e-5, 1e-1]) at phi = 0.4 labelled by a fixed field through the
// worker API (labelled.mjs), and a second sweep at one of its points with other numerics (two
// runs at one place). One run is labelled with confidence 0.05, one is left unclassified with its
// runner-up, N_r and c_b/V kept.
import { completeAll } from './labelled.mjs';

export const PHI = 0.4;
export const GRID = { name: 'regions grid', phi: PHI, S: { min: 1e-3, max: 1e-1, n: 5, scale: 'log' }, R: { min: 1e-5, max: 1e-1, n: 5, scale: 'log' }, numerics: { preset: 'fast', cells_per_unit: 5, eps_end: 0.04 } };
// The run of the grid's point (S 1e-2, R 1e-3) again at 6 cells per unit cell.
export const TWIN = { name: 'twin', S: 1e-2, R: 1e-3, phi: PHI, numerics: { preset: 'fast', cells_per_unit: 6, eps_end: 0.04 } };
export const DOUBTFUL = { S: 1e-1, R: 1e-2 };   // labelled c with confidence 0.05 (runner-up f)
export const UNCLASSIFIED = { S: 1e-3, R: 1e-1 }; // no class; runner-up f, N_r 0, c_b/V 0.03

const near = (a, b) => Math.abs(Math.log10(a / b)) < 1e-6;

// The field: (f) buckling from R = 0.1, (e) explosive at S = 0.1 below R = 1e-3, (a) where
// R < 10 S^2 (the band does not reflect), (b) elsewhere, (c) at S >= 0.03 between.
export function field(S, R) {
  if (R >= 0.05) return 'f';
  if (S >= 0.05 && R < 1e-3) return 'e';
  if (S >= 0.05) return 'c';
  return R < 10 * S * S ? 'a' : 'b';
}

const RUNNER = { a: 'b', b: 'a', c: 'b', e: 'c', f: 'b' };

export function verdict(scene) {
  const { S, R } = scene;
  if (near(S, UNCLASSIFIED.S) && near(R, UNCLASSIFIED.R)) return { class: null, confidence: null, runner_up: 'f', n_reflections: 0, band_speed_ratio: 0.03 };
  const c = field(S, R);
  const confidence = near(S, DOUBTFUL.S) && near(R, DOUBTFUL.R) ? 0.05 : 0.97;
  const bands = c === 'a' || c === 'b';
  return { class: c, confidence, runner_up: confidence < 0.5 ? 'f' : RUNNER[c], n_reflections: c === 'b' ? 2 : bands ? 0 : null, band_speed_ratio: bands ? (c === 'a' ? 1.67 : 2.5) : null };
}

// Creates both sweeps on the harness's server and labels every job; returns the runs completed.
export async function fillMap(h) {
  for (const body of [GRID, TWIN]) {
    const r = await h.api('/sweeps', body);
    if (r.status !== 201) throw new Error(`sweep ${body.name} -> ${r.status} ${JSON.stringify(r.json)}`);
  }
  return completeAll(h.url, verdict);
}
