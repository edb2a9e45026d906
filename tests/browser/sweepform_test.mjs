// The sweep form's rules (web/js/sweepform.js) and the planner's grid (web/js/sweepmath.js) in
// plain node: what the browser shows next to each field, and the job count before submitting.
// The limits come from a real compaction-server (GET /api/v1/limits), as in the dashboard.
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { validateSweep as validateWith, formFieldOf, coarsestCellsPerUnit } from '../../web/js/sweepform.js';
import { expandAxis, sweepPhis } from '../../web/js/sweepmath.js';
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

test('phi outside [0.2, 0.8], bad counts and too coarse grids are refused', () => {
  assert.match(validateSweep({ ...base, phi: '0.9' }).errors.phi, /\[0.2, 0.8\]/);
  assert.ok(validateSweep({ ...base, sN: '0' }).errors['s-n']);
  assert.ok(validateSweep({ ...base, rN: '2.5' }).errors['r-n']);
  assert.match(validateSweep({ ...base, cpu: '4' }).errors.cpu, /too coarse for φ = 0.4/);
  assert.equal(validateSweep({ ...base, cpu: '5' }).ok, true);
  assert.match(validateSweep({ ...base, cps: '0.5' }).errors.cps, /a number in \[1, 50\]/);
  assert.deepEqual(validateSweep({ ...base, cps: '6' }).body.numerics, { preset: 'fast', cells_per_strut: 6 });
  assert.equal(coarsestCellsPerUnit(0.4), 5); // strut 0.225 of a cell side: 5 cells give 1.13
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

test('grids match the planner: log spacing, ends exact, 12 significant digits', () => {
  assert.deepEqual(expandAxis({ min: 1e-3, max: 1e-1, n: 3, scale: 'log' }), [1e-3, 1e-2, 1e-1]);
  assert.deepEqual(expandAxis({ min: 0.3, max: 0.5, n: 3, scale: 'linear' }), [0.3, 0.4, 0.5]);
  assert.deepEqual(expandAxis({ min: 0.4, max: 0.9, n: 1 }), [0.4]);
  assert.deepEqual(sweepPhis({ points: [{ S: 0.1, R: 0.1, phi: 0.35 }] }), [0.35]);
  assert.deepEqual(sweepPhis({ phi: [0.3, 0.4] }), [0.3, 0.4]);
});
