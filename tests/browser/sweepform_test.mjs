// The sweep form's rules (web/js/sweepform.js) in plain node: what the browser shows next to each
// field, and the job count before submitting; what the server says of the same bodies (the
// estimate's refusals, a sweep's phi values, the adaptive defaults).
// The limits come from a real compaction-server (GET /api/v1/limits), as in the dashboard.
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { validateSweep as validateWith, validateAdaptive as validateAdaptiveWith, formFieldOf } from '../../web/js/sweepform.js';
import { Harness } from './lib/harness.mjs';

const harness = new Harness('sweepform');
let limits = null;
before(async () => {
  await harness.startServer();
  const r = await harness.api('/limits');
  assert.equal(r.status, 200);
  limits = r.json;
});
after(() => harness.close());
const validateSweep = (v) => validateWith(v, limits);
const validateAdaptive = (v) => validateAdaptiveWith(v, limits);

const base = { name: 'x', sMin: '1e-3', sMax: '1e-1', sN: '3', sScale: 'log', rMin: '1e-5', rMax: '1e-1', rN: '5', rScale: 'log', phi: '0.4', preset: 'fast', cpu: '', epsEnd: '', snapshots: '', priority: '0', attempts: '3' };

test('a valid grid counts S x R x phi jobs and builds the request body', () => {
  const r = validateSweep({ ...base, phi: '0.3, 0.4' });
  assert.equal(r.ok, true, JSON.stringify(r.errors));
  assert.equal(r.count, 30);
  assert.deepEqual(r.body.S, { min: 1e-3, max: 1e-1, n: 3, scale: 'log' });
  assert.deepEqual(r.body.phi, [0.3, 0.4]);
  assert.deepEqual(r.body.numerics, { preset: 'fast' });
});

test('S min above S max is reported at S max', () => {
  const r = validateSweep({ ...base, sMin: '0.5', sMax: '0.1' });
  assert.match(r.errors['s-max'], /max must be ≥ min/);
});

test('S and R outside (0, 1) are reported at the field', () => {
  assert.match(validateSweep({ ...base, sMin: '0' }).errors['s-min'], /\(0, 1\)/);
  assert.match(validateSweep({ ...base, rMax: '1.5' }).errors['r-max'], /\(0, 1\)/);
  assert.match(validateSweep({ ...base, sMin: 'abc' }).errors['s-min'], /number/);
});

test('phi outside [0.2, 0.8], bad counts and too coarse grids are refused', async () => {
  assert.match(validateSweep({ ...base, phi: '0.9' }).errors.phi, /\[0.2, 0.8\] \(the model is meant for 0.25 to 0.75\)/);
  assert.ok(validateSweep({ ...base, sN: '0' }).errors['s-n']);
  assert.ok(validateSweep({ ...base, rN: '2.5' }).errors['r-n']);
  // A grid too coarse for a phi: the server's estimate says so, naming the field the form shows.
  const coarse = validateSweep({ ...base, cpu: '4' });
  assert.equal(coarse.ok, true, JSON.stringify(coarse.errors));
  const refused = await harness.api('/sweeps/estimate', coarse.body);
  assert.equal(refused.status, 422, JSON.stringify(refused.json));
  assert.equal(formFieldOf(refused.json.error.field), 'cpu');
  assert.match(refused.json.error.message, /too coarse for phi = 0.4/);
  assert.equal((await harness.api('/sweeps/estimate', validateSweep({ ...base, cpu: '5' }).body)).status, 200);
  assert.match(validateSweep({ ...base, cps: '0.5' }).errors.cps, /a number in \[1, 50\]/);
  assert.deepEqual(validateSweep({ ...base, cps: '6' }).body.numerics, { preset: 'fast', cells_per_strut: 6 });
  assert.ok(validateSweep({ ...base, epsEnd: '0.97' }).errors['eps-end']);
  assert.ok(validateSweep({ ...base, priority: '5000' }).errors.priority);
  assert.ok(validateSweep({ ...base, sN: '100', rN: '100' }).errors.count);
  assert.ok(validateSweep({ ...base, name: '  ' }).errors.name);
});

test('server error fields map onto the form', () => {
  assert.equal(formFieldOf('S.min'), 's-min');
  assert.equal(formFieldOf('R.max'), 'r-max');
  assert.equal(formFieldOf('S'), 's-min');
  assert.equal(formFieldOf('phi[1]'), 'phi');
  assert.equal(formFieldOf('numerics.cells_per_unit'), 'cpu');
  assert.equal(formFieldOf('numerics.cells_per_strut'), 'cps');
  assert.equal(formFieldOf('numerics.eps_end'), 'eps-end');
  assert.equal(formFieldOf('bogus'), null);
});

// The adaptive form's fields: the same names, S and R points being the initial grid's.
const adaptiveBase = { ...base, sN: '5', rN: '5', resolution: '0.125', budget: '200', inFlight: '' };

test('a valid adaptive sweep counts its initial grid and builds the adaptive body', () => {
  const r = validateAdaptive(adaptiveBase);
  assert.equal(r.ok, true, JSON.stringify(r.errors));
  assert.equal(r.count, 25);
  assert.equal(r.budget, 200);
  assert.deepEqual(r.body, {
    name: 'x', phi: 0.4, numerics: { preset: 'fast' }, priority: 0, max_attempts: 3,
    adaptive: { S: { min: 1e-3, max: 1e-1 }, R: { min: 1e-5, max: 1e-1 }, initial: { S: 5, R: 5 }, resolution_decades: 0.125, budget: 200 },
  });
  assert.equal(validateAdaptive({ ...adaptiveBase, inFlight: '4' }).body.adaptive.in_flight, 4);
});

test('empty resolution and budget take the form defaults of 0.125 decades and 200 runs', () => {
  const r = validateAdaptive({ ...adaptiveBase, resolution: ' ', budget: '' });
  assert.equal(r.ok, true, JSON.stringify(r.errors));
  assert.equal(r.body.adaptive.resolution_decades, 0.125);
  assert.equal(r.body.adaptive.budget, 200);
});

test('an adaptive sweep refuses a list of phi, an empty box and an initial axis of one point', async () => {
  assert.match(validateAdaptive({ ...adaptiveBase, phi: '0.3, 0.4' }).errors.phi, /one φ/);
  assert.match(validateAdaptive({ ...adaptiveBase, phi: '0.9' }).errors.phi, /\[0.2, 0.8\]/);
  assert.match(validateAdaptive({ ...adaptiveBase, sMin: '0.1', sMax: '0.1' }).errors['s-max'], /max must be > min/);
  assert.match(validateAdaptive({ ...adaptiveBase, rMin: '0' }).errors['r-min'], /\(0, 1\)/);
  assert.match(validateAdaptive({ ...adaptiveBase, sN: '1' }).errors['s-n'], /≥ 2/);
  assert.ok(validateAdaptive({ ...adaptiveBase, rN: '2.5' }).errors['r-n']);
  // The grid too coarse for the phi: the server's estimate names it.
  const coarse = await harness.api('/sweeps/estimate', validateAdaptive({ ...adaptiveBase, cpu: '4' }).body);
  assert.equal(coarse.status, 422, JSON.stringify(coarse.json));
  assert.equal(formFieldOf(coarse.json.error.field), 'cpu');
});

test('the budget holds the initial grid and stays within the server limit; resolution and in flight are checked', () => {
  assert.match(validateAdaptive({ ...adaptiveBase, budget: '24' }).errors.budget, /initial grid's 25 runs/);
  assert.equal(validateAdaptive({ ...adaptiveBase, budget: '25' }).ok, true);
  const max = limits.sweep.max_points;
  assert.match(validateAdaptive({ ...adaptiveBase, budget: String(max + 1) }).errors.budget, new RegExp(`to ${max}$`));
  assert.ok(validateAdaptive({ ...adaptiveBase, budget: '30.5' }).errors.budget);
  assert.ok(validateAdaptive({ ...adaptiveBase, resolution: '0' }).errors.res);
  assert.ok(validateAdaptive({ ...adaptiveBase, resolution: 'fine' }).errors.res);
  assert.ok(validateAdaptive({ ...adaptiveBase, inFlight: '0' }).errors['in-flight']);
  assert.match(validateAdaptive({ ...adaptiveBase, budget: '30', inFlight: '31' }).errors['in-flight'], /1 to 30/);
  assert.ok(validateAdaptive({ ...adaptiveBase, sN: String(max), rN: '2' }).errors.count);
});

test('the server\'s adaptive error fields map onto the form', () => {
  assert.equal(formFieldOf('adaptive.S.min'), 's-min');
  assert.equal(formFieldOf('adaptive.R.max'), 'r-max');
  assert.equal(formFieldOf('adaptive.S'), 's-min');
  assert.equal(formFieldOf('adaptive.initial.S'), 's-n');
  assert.equal(formFieldOf('adaptive.initial.R'), 'r-n');
  assert.equal(formFieldOf('adaptive.resolution_decades'), 'res');
  assert.equal(formFieldOf('adaptive.budget'), 'budget');
  assert.equal(formFieldOf('adaptive.in_flight'), 'in-flight');
  assert.equal(formFieldOf('adaptive'), null);
});

test('the server refuses what the form leaves to it at the fields the form maps', async () => {
  const ok = validateAdaptive({ ...adaptiveBase, resolution: '0.01' });
  assert.equal(ok.ok, true, 'a resolution finer than 1/64 decade is the server\'s to refuse');
  const r = await harness.api('/sweeps', ok.body);
  assert.equal(r.status, 422, JSON.stringify(r.json));
  assert.equal(formFieldOf(r.json.error.field), 'res');
});

test('a random structure with seeds runs each point once per seed; the form refuses what the planner refuses', async () => {
  const random = { ...base, preset: 'default', structure: 'random' };
  const r = validateSweep({ ...random, seeds: '1, 2, 3' });
  assert.equal(r.ok, true, JSON.stringify(r.errors));
  assert.equal(r.count, 45); // 3 S x 5 R x 1 phi x 3 seeds
  assert.deepEqual(r.body.numerics, { preset: 'default', structure: 'random', seeds: [1, 2, 3] });
  assert.deepEqual(validateSweep({ ...random, seeds: '7' }).body.numerics, { preset: 'default', structure: 'random', seed: 7 });
  assert.deepEqual(validateSweep({ ...random, seeds: '' }).body.numerics, { preset: 'default', structure: 'random' });
  assert.deepEqual(validateSweep({ ...base, structure: 'regular' }).body.numerics, { preset: 'fast' });
  assert.match(validateSweep({ ...base, seeds: '1, 2' }).errors.seeds, /random structure/);
  assert.match(validateSweep({ ...random, seeds: '1, -2' }).errors.seeds, /whole numbers/);
  assert.match(validateSweep({ ...random, seeds: '1, 1.5' }).errors.seeds, /whole numbers/);
  assert.match(validateSweep({ ...random, seeds: '4, 4' }).errors.seeds, /twice/);
  const many = Array.from({ length: limits.sweep.max_seeds + 1 }, (_, i) => i).join(',');
  assert.match(validateSweep({ ...random, seeds: many }).errors.seeds, new RegExp(`at most ${limits.sweep.max_seeds}`));
  assert.match(validateAdaptive({ ...adaptiveBase, structure: 'random', seeds: '1, 2' }).errors.seeds, /one seed/);
  assert.equal(formFieldOf('numerics.structure'), 'structure');
  assert.equal(formFieldOf('numerics.seed'), 'seeds');
  assert.equal(formFieldOf('numerics.seeds[1]'), 'seeds');
  // The server plans the form's body: 45 runs, each with its structure and seed.
  const ok = await harness.api('/sweeps', { ...r.body, name: 'random seeds', numerics: { ...r.body.numerics, eps_end: 0.01 } });
  assert.equal(ok.status, 201, JSON.stringify(ok.json));
  const jobs = await harness.api(`/jobs?sweep=${ok.json.id}&limit=100`);
  assert.equal(jobs.json.jobs.length, 45);
  assert.deepEqual([...new Set(jobs.json.jobs.map((j) => `${j.scene.structure}/${j.scene.seed}`))].sort(), ['random/1', 'random/2', 'random/3']);
  // The fast preset leaves a random structure's thinnest strut under a grid cell: the server names the field the form maps.
  const coarse = await harness.api('/sweeps', { ...r.body, numerics: { ...r.body.numerics, preset: 'fast' } });
  assert.equal(coarse.status, 422, JSON.stringify(coarse.json));
  assert.equal(formFieldOf(coarse.json.error.field), 'cps');
});

test('the movie interval is 0 or in the range of /limits, sent as numerics.movie_d_eps; one below d_eps is refused by the server at the field', async () => {
  const m = limits.scene.movie_d_eps;
  assert.deepEqual([m.lo, m.hi, m.none, m.default], [0.001, 0.5, 0, 0.02]);
  assert.deepEqual(validateSweep({ ...base, movie: '0.05' }).body.numerics, { preset: 'fast', movie_d_eps: 0.05 });
  assert.deepEqual(validateSweep({ ...base, movie: '0' }).body.numerics, { preset: 'fast', movie_d_eps: 0 });
  assert.deepEqual(validateSweep({ ...base, movie: '' }).body.numerics, { preset: 'fast' });
  assert.match(validateSweep({ ...base, movie: '0.7' }).errors.movie, /\[0\.001, 0\.5\]/);
  assert.ok(validateSweep({ ...base, movie: 'often' }).errors.movie);
  // 0.001 is in the range but below the frame interval d_eps = 0.002: the scene's rule.
  const r = validateSweep({ ...base, movie: '0.001' });
  assert.equal(r.ok, true, JSON.stringify(r.errors));
  const refused = await harness.api('/sweeps', r.body);
  assert.equal(refused.status, 422, JSON.stringify(refused.json));
  assert.equal(refused.json.error.field, 'numerics.movie_d_eps');
  assert.match(refused.json.error.message, /d_eps/);
  assert.equal(formFieldOf(refused.json.error.field), 'movie');
});

test('a sweep lists the solid fractions the planner made of its request', async () => {
  const grid = await harness.api('/sweeps', validateSweep({ ...base, name: 'two phis', phi: '0.3, 0.4' }).body);
  assert.equal(grid.status, 201, JSON.stringify(grid.json));
  assert.deepEqual(grid.json.phis, [0.3, 0.4]);
  const points = await harness.api('/sweeps', { name: 'points', points: [{ S: 0.1, R: 0.1, phi: 0.35 }] });
  assert.equal(points.status, 201, JSON.stringify(points.json));
  assert.deepEqual(points.json.phis, [0.35]);
});

test('an adaptive sweep without resolution or budget takes the server\'s defaults', async () => {
  const r = validateAdaptive({ ...adaptiveBase, resolution: '', budget: '' });
  assert.equal(r.ok, true, JSON.stringify(r.errors));
  assert.equal(r.body.adaptive.resolution_decades, limits.adaptive.resolution_decades);
  assert.equal(r.body.adaptive.budget, limits.adaptive.budget);
  const body = { name: 'defaults', phi: 0.4, adaptive: { S: { min: 3e-3, max: 3e-2 }, R: { min: 1e-5, max: 1e-2 } } };
  const est = await harness.api('/sweeps/estimate', body);
  assert.equal(est.status, 200, JSON.stringify(est.json));
  assert.equal(est.json.jobs, limits.adaptive.initial.S * limits.adaptive.initial.R);
});

test('replicates run each point n times with a perturbation: counted, sent as replicates, estimated with every run', async () => {
  const rep = limits.replicates;
  assert.deepEqual([rep.max_n, rep.perturbation.lo, rep.perturbation.hi], [100, 0, 0.5]);
  const r = validateSweep({ ...base, repN: '3', repPert: '0.01' });
  assert.equal(r.ok, true, JSON.stringify(r.errors));
  assert.equal(r.count, 45); // 3 S x 5 R x 1 phi x 3 replicates
  assert.equal(r.replicates, 3);
  assert.deepEqual(r.body.replicates, { n: 3, perturbation: 0.01 });
  assert.deepEqual(r.body.numerics, { preset: 'fast' }, 'the perturbation has one home: replicates');
  assert.equal(validateSweep(base).body.replicates, undefined, 'no replicates without the fields');
  // The server's estimate counts every replicate, as the form does.
  const est = await harness.api('/sweeps/estimate', r.body);
  assert.equal(est.status, 200, JSON.stringify(est.json));
  assert.equal(est.json.jobs, 45);
  const one = await harness.api('/sweeps/estimate', validateSweep(base).body);
  assert.ok(Math.abs(est.json.cpu_seconds - 3 * one.json.cpu_seconds) < 1e-6 * est.json.cpu_seconds, `${est.json.cpu_seconds} is three times ${one.json.cpu_seconds}`);
  // A random structure draws its voids from the seed: replicates without a perturbation.
  const random = validateSweep({ ...base, preset: 'default', structure: 'random', repN: '2' });
  assert.equal(random.ok, true, JSON.stringify(random.errors));
  assert.deepEqual(random.body.replicates, { n: 2 });
  // Adaptive: the initial grid is one run a point (the planner spends the replicates from the
  // budget where the map asks for them), as the server counts it; the budget counts runs.
  const a = validateAdaptive({ ...adaptiveBase, budget: '', repN: '2', repPert: '0.01' });
  assert.equal(a.ok, true, JSON.stringify(a.errors));
  assert.equal(a.count, 25);
  assert.equal(a.replicates, 2);
  assert.equal(a.body.adaptive.budget, 200);
  assert.deepEqual(a.body.replicates, { n: 2, perturbation: 0.01 });
  assert.equal((await harness.api('/sweeps/estimate', a.body)).json.jobs, 25);
  const low = { ...adaptiveBase, budget: '20', repN: '2', repPert: '0.01' };
  assert.match(validateAdaptive(low).errors.budget, /initial grid's 25 runs/);
  const refused = await harness.api('/sweeps/estimate', { ...a.body, adaptive: { ...a.body.adaptive, budget: 20 } });
  assert.equal(refused.status, 422, JSON.stringify(refused.json));
  assert.equal(formFieldOf(refused.json.error.field), 'budget');
});

test('the form refuses replicates outside the ranges of /limits; the planner the rules that span fields, at the replicates fields', async () => {
  const max = limits.replicates.max_n;
  assert.match(validateSweep({ ...base, repN: '0', repPert: '0.01' }).errors['rep-n'], new RegExp(`1 to ${max}`));
  assert.match(validateSweep({ ...base, repN: String(max + 1), repPert: '0.01' }).errors['rep-n'], new RegExp(`1 to ${max}`));
  assert.ok(validateSweep({ ...base, repN: '2.5', repPert: '0.01' }).errors['rep-n']);
  assert.match(validateSweep({ ...base, repPert: '0.01' }).errors['rep-n'], /how many/);
  assert.match(validateSweep({ ...base, repN: '3', repPert: '0.7' }).errors['rep-pert'], /\[0, 0\.5\]/);
  assert.equal(validateSweep({ ...base, repN: '1' }).ok, true, 'one run per point needs no perturbation');
  assert.ok(validateSweep({ ...base, sN: '40', rN: '40', repN: '50', repPert: '0.01' }).errors.count, 'points x replicates against the sweep limit');
  // A regular structure without a perturbation, and replicates beside seeds, span fields (and a
  // preset may carry a perturbation): the form lets them through to the planner, which names
  // the field; the page shows it there from the estimate's 422.
  const spanning = [
    [{ ...base, repN: '3' }, 'rep-pert', /is required: replicates of a regular structure/],
    [{ ...base, repN: '3', repPert: '0' }, 'rep-pert', /is required/],
    [{ ...base, preset: 'default', structure: 'random', seeds: '1, 2', repN: '2' }, 'seeds', /not both/],
  ];
  for (const [values, field, message] of spanning) {
    const r = validateSweep(values);
    assert.equal(r.ok, true, JSON.stringify(r.errors));
    const res = await harness.api('/sweeps/estimate', r.body);
    assert.equal(res.status, 422, `${JSON.stringify(r.body.replicates)}: ${JSON.stringify(res.json)}`);
    assert.equal(formFieldOf(res.json.error.field), field, `${res.json.error.field} goes to ${field}`);
    assert.match(res.json.error.message, message);
  }
  // What the server says of the bodies the form refuses, at the field the form maps.
  const body = validateSweep(base).body;
  for (const [replicates, field] of [[{ n: 0, perturbation: 0.01 }, 'rep-n'], [{ n: 3, perturbation: 0.7 }, 'rep-pert']]) {
    const res = await harness.api('/sweeps/estimate', { ...body, replicates });
    assert.equal(res.status, 422, `${JSON.stringify(replicates)}: ${JSON.stringify(res.json)}`);
    assert.equal(formFieldOf(res.json.error.field), field, `${res.json.error.field} goes to ${field}`);
  }
  assert.equal(formFieldOf('replicates'), 'rep-n');
  assert.equal(formFieldOf('replicates.n'), 'rep-n');
  assert.equal(formFieldOf('replicates.perturbation'), 'rep-pert');
});
