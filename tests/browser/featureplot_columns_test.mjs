// The Plots page's reading of GET /api/v1/jobs?format=csv (web/js/featureplot.js parseRunsCsv)
// and the axes' extents (web/js/plot.js) in plain node, no browser: cells as the server writes
// them (numbers as JSON, text quoted when it holds a comma or a quote, a formula's text behind
// '), missing and empty cells, a CRLF line, a column that is not numeric, R/S^2; and value
// ranges and extents over more values than a spread call can take (the server's CSV holds up to
// 200 000 rows).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { parseRunsCsv } from '../../web/js/featureplot.js';
import { linearExtent, logExtent, valueRange } from '../../web/js/plot.js';
import { stressRatio } from '../../web/js/physics.js';

const CSV = [
  'id,S,R,phi,state,status,class,label,band_speed_ratio,human_label,preset',
  '1,0.001,1e-05,0.4,succeeded,ok,a,a,1.25,,fast',
  '2,0.01,0.001,0.4,succeeded,ok,c,b,,"\'=HYPERLINK(""x""), y",default',
  '3,0.1,0.1,0.3,failed,,,,-2e-07,b',
  '4,0.02,1e-05,0.5,queued\r',
  '',
].join('\n');

test('the CSV becomes columns: numbers, texts, empty and missing cells, quotes, CRLF', () => {
  const d = parseRunsCsv(CSV);
  assert.equal(d.n, 4);
  assert.deepEqual(d.names, ['id', 'S', 'R', 'phi', 'state', 'status', 'class', 'label', 'band_speed_ratio', 'human_label', 'preset']);
  assert.deepEqual([...d.numeric.id], [1, 2, 3, 4]);
  assert.deepEqual([...d.numeric.phi], [0.4, 0.4, 0.3, 0.5]);
  assert.deepEqual([...d.numeric.band_speed_ratio], [1.25, NaN, -2e-7, NaN]);
  assert.deepEqual(d.text.state, ['succeeded', 'succeeded', 'failed', 'queued']);
  assert.deepEqual(d.text.status, ['ok', 'ok', '', '']);
  assert.deepEqual(d.text.class, ['a', 'c', '', '']);
  assert.deepEqual(d.text.human_label, ['', '\'=HYPERLINK("x"), y', 'b', '']);
  assert.deepEqual(d.text.preset, ['fast', 'default', '', '']);
  assert.equal(d.numeric.state, undefined, 'a text column is no number column');
  const S = [0.001, 0.01, 0.1, 0.02], R = [1e-5, 1e-3, 0.1, 1e-5];
  assert.deepEqual([...d.numeric.R_S2], S.map((s, i) => stressRatio(s, R[i])));
});

test('a column with a cell that is not a number is no number column', () => {
  const d = parseRunsCsv('id,seed,runner_up\n1,7,x\n2,seven,y\n');
  assert.deepEqual([...d.numeric.id], [1, 2]);
  assert.equal(d.numeric.seed, null);
  assert.equal(d.numeric.runner_up, undefined);
  assert.deepEqual(d.text.runner_up, ['x', 'y']);
  assert.equal('R_S2' in d.numeric, false, 'no S and R, no R/S^2');
});

test('no rows: the header alone, and nothing at all', () => {
  const d = parseRunsCsv('id,S,R\n');
  assert.equal(d.n, 0);
  assert.deepEqual([...d.numeric.R_S2], []);
  assert.deepEqual(parseRunsCsv(''), { n: 0, names: [], numeric: {}, text: {} });
});

test('extents over 300 000 values (more than a spread call takes)', () => {
  const v = Array.from({ length: 300000 }, (_, i) => (i % 7 === 0 ? NaN : 1 + (i % 1000)));
  assert.deepEqual(linearExtent(v, [0, 1]), [1 - 999 * 0.05, 1000 + 999 * 0.05]);
  const [lo, hi] = logExtent(v, [0.1, 10]);
  assert.ok(lo < 1 && hi > 1000 && lo > 0.5 && hi < 2000, `${lo} ${hi}`);
  assert.deepEqual(valueRange(v), [1, 1000]);
  assert.deepEqual(valueRange([-3, 0, 2, NaN, -Infinity], true), [2, 2], 'only values > 0');
  assert.deepEqual(valueRange([-3, 0, 2, NaN, -Infinity]), [-3, 2]);
  assert.equal(valueRange([0, -1], true), null);
  assert.deepEqual(linearExtent([NaN, Infinity], [0, 1]), [0, 1]);
  assert.deepEqual(linearExtent([2, 2], [0, 1]), [1.8, 2.2].map((x, i) => x + (i ? 1 : -1) * 0.4 * 0.05));
});
