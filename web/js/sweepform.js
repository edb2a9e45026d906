// Validation of the sweep form, without the DOM (tests/browser/sweepform_test.mjs runs it in
// node). The limits are the server's own (GET /api/v1/limits: the planner's rules and the
// scene's ranges), so a person sees the problem next to the field before submitting; the
// server still validates everything.
import { expandAxis } from './sweepmath.js';

const num = (s) => (typeof s === 'string' && s.trim() !== '' ? Number(s) : NaN);
const isInt = (v) => Number.isInteger(v);

// The engine requires at least one grid cell across each hole and each strut.
export function coarsestCellsPerUnit(phi) {
  const s = Math.sqrt(1 - phi);
  return Math.ceil(Math.max(1 / s, 1 / (1 - s)) - 1e-12);
}

// "[0.2, 0.8]" or "(0, 1)", as the server writes a range.
const show = (r) => `${r.open ? '(' : '['}${r.lo}, ${r.hi}${r.open ? ')' : ']'}`;
const inside = (r, x) => (r.open ? x > r.lo && x < r.hi : x >= r.lo && x <= r.hi);

function axis(v, key, name, range, maxPoints, errors) {
  const lo = num(v[`${key}Min`]), hi = num(v[`${key}Max`]), n = num(v[`${key}N`]);
  const scale = v[`${key}Scale`] === 'linear' ? 'linear' : 'log';
  const f = (s) => `${key}-${s}`;
  if (!Number.isFinite(lo)) errors[f('min')] = `${name} min must be a number`;
  else if (!inside(range, lo)) errors[f('min')] = `${name} must be in ${show(range)}, got ${lo}`;
  if (!Number.isFinite(hi)) errors[f('max')] = `${name} max must be a number`;
  else if (!inside(range, hi)) errors[f('max')] = `${name} must be in ${show(range)}, got ${hi}`;
  else if (Number.isFinite(lo) && lo > hi) errors[f('max')] = `max must be ≥ min (${lo})`;
  if (!isInt(n) || n < 1) errors[f('n')] = 'a whole number ≥ 1';
  else if (n > maxPoints) errors[f('n')] = `at most ${maxPoints}`;
  return { min: lo, max: hi, n, scale };
}

// values: strings of the form fields; limits: the server's GET /api/v1/limits.
// Returns {errors: {fieldId: message}, body, count, dims}.
export function validateSweep(v, limits) {
  const { sweep, scene } = limits;
  const errors = {};
  const name = (v.name || '').trim();
  if (!name) errors.name = 'give the sweep a name';
  else if (new TextEncoder().encode(name).length > sweep.name_max_bytes) errors.name = `at most ${sweep.name_max_bytes} bytes`;
  const S = axis(v, 's', 'S', scene.S, sweep.max_points, errors);
  const R = axis(v, 'r', 'R', scene.R, sweep.max_points, errors);
  const phiText = (v.phi || '').trim();
  const phis = phiText.split(/[\s,;]+/).filter(Boolean).map(Number);
  if (!phis.length) errors.phi = 'one or more values, e.g. 0.4 or 0.3, 0.4';
  else if (phis.some((p) => !Number.isFinite(p))) errors.phi = 'numbers separated by commas';
  else if (phis.some((p) => !inside(scene.phi, p))) errors.phi = `φ must be in ${show(scene.phi)} (the model is meant for 0.25 to 0.75)`;
  else if (new Set(phis).size !== phis.length) errors.phi = 'a value is listed twice';

  const numerics = { preset: v.preset || 'default' };
  if ((v.cps || '').trim() !== '') {
    // Whether the grid it gives fits at each phi is the server's to say (it names the field).
    const c = num(v.cps), range = scene.cells_per_strut;
    if (!Number.isFinite(c) || !inside(range, c)) errors.cps = `a number in ${show(range)}`;
    else numerics.cells_per_strut = c;
  }
  if ((v.cpu || '').trim() !== '') {
    const c = num(v.cpu);
    const cells = scene.cells_per_unit;
    if (!isInt(c) || !inside(cells, c)) errors.cpu = `a whole number from ${cells.lo} to ${cells.hi}`;
    else {
      const bad = phis.filter((p) => Number.isFinite(p) && inside(scene.phi, p) && c < coarsestCellsPerUnit(p));
      if (bad.length) errors.cpu = `too coarse for φ = ${bad[0]}: needs ≥ ${coarsestCellsPerUnit(bad[0])} so that holes and struts span a cell`;
      numerics.cells_per_unit = c;
    }
  }
  if ((v.epsEnd || '').trim() !== '') {
    const e = num(v.epsEnd);
    if (!Number.isFinite(e) || e >= scene.eps_end.hi) errors['eps-end'] = `a strain below ${scene.eps_end.hi} (≤ 0 or empty: until fully dense)`;
    else numerics.eps_end = e;
  }
  if ((v.snapshots || '').trim() !== '') {
    const s = v.snapshots.split(/[\s,;]+/).filter(Boolean).map(Number);
    if (s.some((x) => !Number.isFinite(x) || !inside(scene.snapshot_eps, x))) errors.snapshots = `strains in ${show(scene.snapshot_eps)}, separated by commas`;
    else if (s.length > scene.max_snapshots) errors.snapshots = `at most ${scene.max_snapshots} snapshots`;
    else numerics.snapshot_eps = s;
  }
  const pr = sweep.priority, at = sweep.max_attempts;
  const priority = (v.priority || '').trim() === '' ? pr.default : num(v.priority);
  if (!isInt(priority) || priority < pr.lo || priority > pr.hi) errors.priority = `a whole number from ${pr.lo} to ${pr.hi}`;
  const attempts = (v.attempts || '').trim() === '' ? at.default : num(v.attempts);
  if (!isInt(attempts) || attempts < at.lo || attempts > at.hi) errors.attempts = `a whole number from ${at.lo} to ${at.hi}`;

  const nS = errors['s-n'] ? 0 : S.n, nR = errors['r-n'] ? 0 : R.n;
  const nPhi = errors.phi ? 0 : phis.length;
  const count = nS * nR * nPhi;
  if (count > sweep.max_points && !errors['s-n'] && !errors['r-n']) errors.count = `${count} jobs exceed the server's limit of ${sweep.max_points} per sweep`;
  const body = {
    name,
    S: { min: S.min, max: S.max, n: S.n, scale: S.scale },
    R: { min: R.min, max: R.max, n: R.n, scale: R.scale },
    phi: phis.length === 1 ? phis[0] : phis,
    numerics,
    priority,
    max_attempts: attempts,
  };
  return { errors, body, count, dims: [nS, nR, nPhi], ok: Object.keys(errors).length === 0 };
}

// Where a server error's field ("S.min", "phi[1]", "numerics.eps_end", ...) goes in the form.
export function formFieldOf(serverField) {
  const f = serverField || '';
  const m = /^(S|R)(?:\.(min|max|n|scale))?/.exec(f);
  if (m) return `${m[1].toLowerCase()}-${m[2] === 'scale' ? 'scale' : m[2] || 'min'}`;
  if (/^phi/.test(f) || /^points.*phi/.test(f)) return 'phi';
  if (f === 'numerics.cells_per_unit') return 'cpu';
  if (f === 'numerics.cells_per_strut') return 'cps';
  if (f === 'numerics.eps_end') return 'eps-end';
  if (f === 'numerics.snapshot_eps' || f.startsWith('numerics.snapshot_eps')) return 'snapshots';
  if (f === 'numerics.preset' || f === 'numerics') return 'preset';
  if (f === 'name' || f === 'priority') return f;
  if (f === 'max_attempts') return 'attempts';
  return null;
}

export { expandAxis };
