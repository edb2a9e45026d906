// Validation of the sweep form, without the DOM (tests/browser/sweepform_test.mjs runs it in
// node). The limits are the server's own (GET /api/v1/limits: the planner's rules, the scene's
// ranges, the model's phi and the adaptive defaults), so a person sees the problem next to the
// field before submitting. What depends on more than one field's range (a grid too coarse for
// a phi, an adaptive resolution against its initial step) is the server's to say: the page
// asks for the sweep's estimate as the form changes and shows its 422 at the field it names.

const num = (s) => (typeof s === 'string' && s.trim() !== '' ? Number(s) : NaN);
const isInt = (v) => Number.isInteger(v);

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

// The parts both kinds of sweep share: name, phi values, numerics over the preset, priority and
// attempts. Each writes its errors under the form's field ids.
function sweepName(v, sweep, errors) {
  const name = (v.name || '').trim();
  if (!name) errors.name = 'give the sweep a name';
  else if (new TextEncoder().encode(name).length > sweep.name_max_bytes) errors.name = `at most ${sweep.name_max_bytes} bytes`;
  return name;
}

function phiValues(v, limits, errors) {
  const { scene, model } = limits;
  const phis = (v.phi || '').trim().split(/[\s,;]+/).filter(Boolean).map(Number);
  if (!phis.length) errors.phi = 'one or more values, e.g. 0.4 or 0.3, 0.4';
  else if (phis.some((p) => !Number.isFinite(p))) errors.phi = 'numbers separated by commas';
  else if (phis.some((p) => !inside(scene.phi, p))) errors.phi = `φ must be in ${show(scene.phi)} (the model is meant for ${model.phi.lo} to ${model.phi.hi})`;
  else if (new Set(phis).size !== phis.length) errors.phi = 'a value is listed twice';
  return phis;
}

function numericsOf(v, scene, errors) {
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
    else numerics.cells_per_unit = c;
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
  if ((v.movie || '').trim() !== '' && scene.movie_d_eps) {
    const m = num(v.movie), r = scene.movie_d_eps;
    if (!(m === r.none || (Number.isFinite(m) && inside(r, m)))) errors.movie = `${r.none} (no movie) or a strain in ${show(r)}, at least the frame interval`;
    else numerics.movie_d_eps = m;
  }
  return numerics;
}

// The structure and its seeds: numerics.structure when random, numerics.seed for one seed and
// numerics.seeds for several (each point then runs once per seed; docs/service.md). Returns the
// runs per point. A regular structure (the form has no perturbation) takes no seeds: they would
// change nothing.
function structureOf(v, sweep, numerics, oneSeed, errors) {
  const random = v.structure === 'random';
  if (random) numerics.structure = 'random';
  const text = (v.seeds || '').trim();
  if (text === '') return 1;
  const seeds = text.split(/[\s,;]+/).filter(Boolean).map(Number);
  if (!random) errors.seeds = 'seeds draw random structures: choose the random structure, or leave this empty';
  else if (seeds.some((x) => !isInt(x) || x < 0 || x > Number.MAX_SAFE_INTEGER)) errors.seeds = 'whole numbers ≥ 0, separated by commas';
  else if (new Set(seeds).size !== seeds.length) errors.seeds = 'a seed is listed twice';
  else if (seeds.length > sweep.max_seeds) errors.seeds = `at most ${sweep.max_seeds} seeds`;
  else if (oneSeed && seeds.length > 1) errors.seeds = 'an adaptive sweep maps one structure: one seed';
  else if (seeds.length === 1) numerics.seed = seeds[0];
  else numerics.seeds = seeds;
  return errors.seeds ? 1 : seeds.length;
}

// Replicates (docs/replicates.md): n runs of each point with the seeds 1..n, the particles
// perturbed by a fraction of their spacing, in the ranges of GET /limits (replicates). Both
// fields empty: none. What spans fields is the planner's to say, at the field it names (through
// the estimate): a regular structure needs a perturbation (its own or its preset's), and
// replicates exclude a list of seeds. Returns the runs per point and the request's replicates
// (null without them).
function replicatesOf(v, limits, errors) {
  const nText = (v.repN || '').trim(), pText = (v.repPert || '').trim();
  if (nText === '' && pText === '') return { perPoint: 1, replicates: null };
  const rep = limits.replicates;
  if (!rep) { errors['rep-n'] = 'this server does not take replicates'; return { perPoint: 1, replicates: null }; }
  const n = num(nText);
  if (nText === '') errors['rep-n'] = 'how many runs of each point';
  else if (!isInt(n) || n < 1 || n > rep.max_n) errors['rep-n'] = `a whole number from 1 to ${rep.max_n}`;
  const replicates = { n };
  if (pText !== '') {
    const p = num(pText);
    if (!Number.isFinite(p) || !inside(rep.perturbation, p)) errors['rep-pert'] = `a fraction of the particle spacing in ${show(rep.perturbation)}`;
    else replicates.perturbation = p;
  }
  return { perPoint: errors['rep-n'] ? 1 : n, replicates };
}

// An empty field takes `dflt`; otherwise a whole number in [lo, hi].
function wholeIn(text, dflt, lo, hi, id, errors) {
  const n = (text || '').trim() === '' ? dflt : num(text);
  if (!isInt(n) || n < lo || n > hi) errors[id] = `a whole number from ${lo} to ${hi}`;
  return n;
}

function queueOf(v, sweep, errors) {
  const pr = sweep.priority, at = sweep.max_attempts;
  return {
    priority: wholeIn(v.priority, pr.default, pr.lo, pr.hi, 'priority', errors),
    max_attempts: wholeIn(v.attempts, at.default, at.lo, at.hi, 'attempts', errors),
  };
}

// values: strings of the form fields; limits: the server's GET /api/v1/limits.
// Returns {errors: {fieldId: message}, body, count (points x seeds x replicates), dims, seeds
// and replicates (runs per point of each)}.
export function validateSweep(v, limits) {
  const { sweep, scene } = limits;
  const errors = {};
  const name = sweepName(v, sweep, errors);
  const S = axis(v, 's', 'S', scene.S, sweep.max_points, errors);
  const R = axis(v, 'r', 'R', scene.R, sweep.max_points, errors);
  const phis = phiValues(v, limits, errors);
  const numerics = numericsOf(v, scene, errors);
  const seeds = structureOf(v, sweep, numerics, false, errors);
  const reps = replicatesOf(v, limits, errors);
  const queue = queueOf(v, sweep, errors);

  const nS = errors['s-n'] ? 0 : S.n, nR = errors['r-n'] ? 0 : R.n;
  const nPhi = errors.phi ? 0 : phis.length;
  const count = nS * nR * nPhi * seeds * reps.perPoint;
  if (count > sweep.max_points && !errors['s-n'] && !errors['r-n']) errors.count = `${count} jobs exceed the server's limit of ${sweep.max_points} per sweep`;
  const body = {
    name,
    S: { min: S.min, max: S.max, n: S.n, scale: S.scale },
    R: { min: R.min, max: R.max, n: R.n, scale: R.scale },
    phi: phis.length === 1 ? phis[0] : phis,
    numerics,
    ...(reps.replicates ? { replicates: reps.replicates } : {}),
    ...queue,
  };
  return { errors, body, count, dims: [nS, nR, nPhi], seeds, replicates: reps.perPoint, ok: Object.keys(errors).length === 0 };
}

// An axis of the adaptive box: min < max inside the scene's range (the box is planned on log10),
// and the initial grid's points on it, both ends included.
function box(v, key, name, range, errors) {
  const lo = num(v[`${key}Min`]), hi = num(v[`${key}Max`]), n = num(v[`${key}N`]);
  const f = (s) => `${key}-${s}`;
  if (!Number.isFinite(lo)) errors[f('min')] = `${name} min must be a number`;
  else if (!inside(range, lo)) errors[f('min')] = `${name} must be in ${show(range)}, got ${lo}`;
  if (!Number.isFinite(hi)) errors[f('max')] = `${name} max must be a number`;
  else if (!inside(range, hi)) errors[f('max')] = `${name} must be in ${show(range)}, got ${hi}`;
  else if (Number.isFinite(lo) && !(lo < hi)) errors[f('max')] = `max must be > min (${lo})`;
  if (!isInt(n) || n < 2) errors[f('n')] = 'a whole number ≥ 2 (both ends of the box)';
  return { min: lo, max: hi, n };
}

// An adaptive sweep at one phi: the box and initial grid in S and R, the finest step, the budget
// and the runs open at once. The same values as validateSweep besides; the server checks the
// rest (the resolution between 1/64 decade and the initial step) and names the field. With
// replicates the initial grid is still one run a point: the planner spends the others, up to n a
// point, where the map asks for them (docs/adaptive.md), and the budget and in flight count runs.
// Returns {errors, body, count (the initial grid's runs), budget, dims, replicates, ok}.
export function validateAdaptive(v, limits) {
  const { sweep, scene } = limits;
  const errors = {};
  const name = sweepName(v, sweep, errors);
  const S = box(v, 's', 'S', scene.S, errors);
  const R = box(v, 'r', 'R', scene.R, errors);
  const phis = phiValues(v, limits, errors);
  if (!errors.phi && phis.length > 1) errors.phi = `an adaptive sweep maps one φ, got ${phis.length}`;
  const numerics = numericsOf(v, scene, errors);
  structureOf(v, sweep, numerics, true, errors);
  const reps = replicatesOf(v, limits, errors);
  const queue = queueOf(v, sweep, errors);

  const nS = errors['s-n'] ? 0 : S.n, nR = errors['r-n'] ? 0 : R.n;
  const count = nS * nR;
  if (count > sweep.max_points) errors.count = `an initial grid of ${count} jobs exceeds the server's limit of ${sweep.max_points} per sweep`;

  // An empty field takes the server's default (GET /api/v1/limits, adaptive).
  const defaults = limits.adaptive;
  const res = (v.resolution || '').trim() === '' ? defaults.resolution_decades : num(v.resolution);
  if (!Number.isFinite(res) || !(res > 0)) errors.res = 'a number of decades > 0, e.g. 0.125';
  const budgetFloor = Math.max(count, 1);
  const budget = wholeIn(v.budget, Math.max(defaults.budget, count), budgetFloor, sweep.max_points, 'budget', errors);
  if (errors.budget && isInt(budget) && budget < count) errors.budget = `at least the initial grid's ${count} runs`;
  const adaptive = {
    S: { min: S.min, max: S.max },
    R: { min: R.min, max: R.max },
    initial: { S: S.n, R: R.n },
    resolution_decades: res,
    budget,
  };
  if ((v.inFlight || '').trim() !== '') {
    const hi = isInt(budget) && !errors.budget ? budget : sweep.max_points;
    adaptive.in_flight = wholeIn(v.inFlight, 0, 1, hi, 'in-flight', errors);
  }
  const body = { name, phi: phis[0], numerics, ...(reps.replicates ? { replicates: reps.replicates } : {}), ...queue, adaptive };
  return { errors, body, count, budget, dims: [nS, nR, errors.phi ? 0 : 1], replicates: reps.perPoint, ok: Object.keys(errors).length === 0 };
}

// Where a server error's field ("S.min", "adaptive.budget", "phi[1]", "numerics.eps_end", ...) goes in the form.
export function formFieldOf(serverField) {
  const f = serverField || '';
  if (f === 'replicates' || f.startsWith('replicates.n')) return 'rep-n';
  if (f.startsWith('replicates.perturbation')) return 'rep-pert';
  const a = /^adaptive\.(?:(S|R)(?:\.(min|max))?|initial\.(S|R)|(resolution_decades|budget|in_flight))/.exec(f);
  if (a) {
    if (a[1]) return `${a[1].toLowerCase()}-${a[2] || 'min'}`;
    if (a[3]) return `${a[3].toLowerCase()}-n`;
    return { resolution_decades: 'res', budget: 'budget', in_flight: 'in-flight' }[a[4]];
  }
  const m = /^(S|R)(?:\.(min|max|n|scale))?/.exec(f);
  if (m) return `${m[1].toLowerCase()}-${m[2] === 'scale' ? 'scale' : m[2] || 'min'}`;
  if (/^phi/.test(f) || /^points.*phi/.test(f)) return 'phi';
  if (f === 'numerics.cells_per_unit') return 'cpu';
  if (f === 'numerics.cells_per_strut') return 'cps';
  if (f === 'numerics.eps_end') return 'eps-end';
  if (f === 'numerics.movie_d_eps') return 'movie';
  if (f === 'numerics.snapshot_eps' || f.startsWith('numerics.snapshot_eps')) return 'snapshots';
  if (f === 'numerics.preset' || f === 'numerics') return 'preset';
  if (f === 'numerics.structure') return 'structure';
  if (f === 'numerics.seed' || f.startsWith('numerics.seeds')) return 'seeds';
  if (f === 'name' || f === 'priority') return f;
  if (f === 'max_attempts') return 'attempts';
  return null;
}

