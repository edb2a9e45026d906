// Replicates on the dashboard (docs/replicates.md) in real headless Chromium against a real
// compaction-server: the map draws a point, not a run. First with real compaction-workers: a
// sweep with replicates (n 3, perturbation 0.01, tiny numerics) goes through the form (its count
// and the server's refusal at the field), the map shows one marker per point while the queue
// fills it in (a worker that stops after two runs leaves a point with a replicate pending: not
// robust, its dashed ring when it has a label), then with the server's share and robustness;
// the tooltip lists the point's runs, the run page its siblings, and "robust only" hides the
// points that are not. Then with labels decided per seed through the worker API
// (lib/labelled.mjs): a split point's pie shows its classes, a point that is not robust its
// dashed ring, a pinned tooltip's link opens a run, the band-speed page puts a point at its
// replicates' mean with a bar of their standard deviation, and the export draws each point once.
// Screenshots at 1440 x 900 and 390 x 844 go to $BROWSER_ARTIFACTS_DIR.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { Harness, artifactsDir, canvasBox, waitFor, WEB_DIR } from './lib/harness.mjs';
import { completeAll } from './lib/labelled.mjs';

const { CLASSES } = await import(join(WEB_DIR, 'js', 'classes.js'));
const { UNSETTLED_DASHES, pieOf, unsettledRadius } = await import(join(WEB_DIR, 'js', 'points.js'));

const hexRgb = (h) => [1, 3, 5].map((i) => parseInt(h.slice(i, i + 2), 16));
const close = (a, b, tol) => b.every((v, i) => Math.abs(a[i] - v) <= tol);
const near = (a, b) => Math.abs(Math.log10(a / b)) < 1e-6;

async function shot(page, name, fullPage = true) {
  await page.evaluate(() => window.scrollTo(0, 0));
  const path = join(artifactsDir(), `${name}.png`);
  await page.screenshot({ path, fullPage });
  console.log(`# screenshot ${path}`);
}

// The page at a phone's and a desktop's size, each a screenshot of the whole page. The map and
// band pages redraw 150 ms after a resize; a run page draws its figures for the width it loads
// at, so it is loaded again at each size (ready: selectors of what shows it is drawn).
async function shotsAtSizes(page, name, ready = []) {
  for (const [w, hgt] of [[390, 844], [1440, 900]]) {
    await page.setViewportSize({ width: w, height: hgt });
    if (ready.length) {
      await page.reload();
      for (const sel of ready) await page.locator(sel).first().waitFor();
    }
    await page.waitForTimeout(400);
    await shot(page, `${name}-${w}x${hgt}`);
  }
}

async function fillForm(page, v) {
  for (const [id, value] of Object.entries(v)) {
    const el = page.locator(`#f-${id}`);
    if ((await el.evaluate((e) => e.tagName)) === 'SELECT') await el.selectOption(value);
    else await el.fill(value);
  }
}

const mapState = (page) => page.evaluate(() => window.__dashboard?.phaseMap ?? null);
// To the map again: a change of the hash keeps the page's window, so the last map's render is
// forgotten first, and mapState waits for the new one.
async function gotoMap(page, url) {
  await page.evaluate(() => { if (window.__dashboard) delete window.__dashboard.phaseMap; });
  await page.goto(url);
}
// The map canvas's pixels (r, g, b) of the n x n square centred at (x, y), each as it shows over
// the white plot area (the canvas is transparent where nothing is drawn).
const pixels = (page, x, y, n) => page.evaluate(({ x, y, n }) => {
  const c = document.querySelector('#map-plot canvas');
  const dpr = c.width / c.clientWidth;
  const h = (n - 1) / 2;
  const d = c.getContext('2d').getImageData(Math.round(x * dpr) - h, Math.round(y * dpr) - h, n, n).data;
  const out = [];
  for (let i = 0; i < d.length; i += 4) out.push([0, 1, 2].map((k) => Math.round((d[i + k] * d[i + 3] + 255 * (255 - d[i + 3])) / 255)));
  return out;
}, { x, y, n });
const pixel = async (page, x, y) => (await pixels(page, x, y, 1))[0];
// The darkest pixel of the 3 x 3 around (x, y), by the sum of its channels.
const darkest = async (page, x, y) => (await pixels(page, x, y, 3)).reduce((a, p) => (p[0] + p[1] + p[2] < a[0] + a[1] + a[2] ? p : a));
// The ink of an unsettled point's dashed ring (#1d2433, antialiased over white: each channel
// well below every class colour's brightest).
const inky = (rgb) => rgb[0] < 125 && rgb[1] < 130 && rgb[2] < 140;
// Where a point's dashed ring would be: the middle of its first dash (12 o'clock) and of the gap
// after it (one dash's angle clockwise), at the marker radius r.
function ringAt(p, r, side = -1) {
  const R = unsettledRadius(r), gap = Math.PI / UNSETTLED_DASHES;
  return { dash: [p.x, p.y + side * R], gap: [p.x + R * Math.sin(gap), p.y - R * Math.cos(gap)] };
}
// Whether the page drew a dashed ring around p: ink in the middle of a dash, none in a gap.
async function ringed(page, p, r) {
  const { dash, gap } = ringAt(p, r);
  const onDash = inky(await darkest(page, ...dash));
  if (onDash) assert.equal(inky(await pixel(page, ...gap)), false, `point ${p.point_id}: a gap in its ring`);
  return onDash;
}

// Tiny runs: pseudo-1D, 5 cells per unit cell, to eps = 0.03; 2 x 2 points, each 3 times.
const FORM = { name: 'replicates browser', 's-min': '0.02', 's-max': '0.1', 's-n': '2', 'r-min': '1e-4', 'r-max': '1e-2', 'r-n': '2', phi: '0.4', preset: 'fast', cpu: '5', 'eps-end': '0.03' };

test('a sweep with replicates through the form: one marker per point, its runs in the tooltip, siblings on the run page, robust only', { timeout: 280000 }, async () => {
  const h = new Harness('replicates');
  try {
    await h.startServer();
    const page = await h.browser({ width: 1440, height: 900 });
    // The form's copy of the limit widened (the server's own stays 100), so that the server's
    // refusal of n = 200 reaches the page and is shown at the field it names.
    await page.route('**/api/v1/limits', async (route) => {
      const res = await route.fetch();
      const limits = await res.json();
      assert.equal(limits.replicates.max_n, 100);
      route.fulfill({ response: res, json: { ...limits, replicates: { ...limits.replicates, max_n: 1000 } } });
    });
    await page.goto(`${h.url}/#/sweeps`);
    await page.locator('#f-preset option[value="fast"]').waitFor({ state: 'attached' });
    await page.locator('details.advanced summary').first().click();
    await fillForm(page, FORM);
    await waitFor(async () => (await page.locator('#job-count').getAttribute('data-count')) === '4', { what: 'the count without replicates' });

    // --- The planner's rule across fields, shown at the field it names (from the estimate's
    // 422): replicates of a regular structure need a perturbation.
    await fillForm(page, { 'rep-n': '3' });
    await waitFor(async () => /is required: replicates of a regular structure/.test(await page.locator('#err-rep-pert').innerText()), { what: 'the perturbation error' });
    assert.equal(await page.locator('#job-cost').getAttribute('data-cpu-seconds'), null, 'no estimate of a refused sweep');
    // --- The server's: n = 200 is over its limit, refused at the replicates' field.
    await fillForm(page, { 'rep-n': '200', 'rep-pert': '0.01' });
    assert.equal(await page.locator('#err-rep-pert').innerText(), '');
    await page.locator('#submit-sweep').click();
    await waitFor(async () => /must be in \[1, 100\]/.test(await page.locator('#err-rep-n').innerText()), { what: 'the server\'s error at the n field' });
    assert.equal(await page.locator('#f-rep-n').getAttribute('aria-invalid'), 'true');
    assert.equal((await h.api('/sweeps')).json.total, 0, 'a refused sweep is not created');

    // --- The valid sweep: 12 jobs, the server's estimate of them.
    await fillForm(page, { 'rep-n': '3' });
    await waitFor(async () => /12\s*jobs\s*=\s*2 S × 2 R × 1 φ × 3 replicates/.test(await page.locator('#job-count').innerText()), { what: 'the count with replicates' });
    assert.equal(await page.locator('#job-count').getAttribute('data-replicates'), '3');
    const est = (await h.api('/sweeps/estimate', { name: 'x', S: { min: 0.02, max: 0.1, n: 2, scale: 'log' }, R: { min: 1e-4, max: 1e-2, n: 2, scale: 'log' }, phi: 0.4, numerics: { preset: 'fast', cells_per_unit: 5, eps_end: 0.03 }, replicates: { n: 3, perturbation: 0.01 } })).json;
    assert.equal(est.jobs, 12);
    await waitFor(async () => Number(await page.locator('#job-cost').getAttribute('data-cpu-seconds')) === est.cpu_seconds, { what: 'the estimate of the 12 runs' });
    await shot(page, 'replicates-01-form');
    await page.locator('#submit-sweep').click();
    await waitFor(async () => /Sweep #1 created with 12 jobs \(3 replicates of each point\)/.test(await page.locator('#form-message').innerText()), { what: 'the created message' });
    assert.deepEqual((await h.api('/sweeps/1')).json.request.replicates, { n: 3, perturbation: 0.01 });
    await page.locator('#form-message a').click();
    await page.waitForURL(/#\/map\?phi=0.4&sweep=1/);

    // --- The map before any worker: four queued points, one marker each for their three runs.
    const queued = await waitFor(async () => { const s = await mapState(page); return s?.count === 4 ? s : null; }, { what: 'four queued points' });
    assert.deepEqual([queued.runs, queued.counts.queued], [12, 4]);
    assert.ok(queued.points.every((p) => p.jobs.length === 3 && !p.robust && !p.unsettled));
    // --- Filling in: a worker that stops after two runs leaves a point with a replicate pending.
    const first = h.startWorker('first', ['--max-jobs', '2']);
    await waitFor(() => first.exitCode === 0, { timeoutMs: 60000, what: 'the first worker to run two jobs and exit' });
    const partial = await waitFor(async () => {
      const s = await mapState(page);
      const a = (await h.api('/phase-map?phi=0.4&sweep=1')).json;
      return s && a.summaries.reduce((n, q) => n + q.finished, 0) === 2 && s.counts.queued !== 4 ? { s, a } : null;
    }, { timeoutMs: 15000, what: 'the map with two runs done' });
    assert.equal(partial.s.count, 4, 'one marker per point while it fills in');
    const started = partial.a.summaries.filter((q) => q.finished > 0);
    for (const q of started) {
      const p = partial.s.points.find((x) => x.point_id === q.point_id);
      assert.equal(q.robust, false, `point ${q.point_id}: ${q.finished} of 3 finished is not robust`);
      assert.equal(p.unsettled, q.label !== null, `point ${q.point_id}: its label, if any, drawn as unsettled`);
      if (q.label) assert.equal(p.cat, q.label, `point ${q.point_id}: drawn as the label of its finished runs`);
      assert.equal(await ringed(page, p, partial.s.radius), p.unsettled, `point ${q.point_id}: a dashed ring while not robust`);
    }
    const waiting = partial.s.points.find((x) => x.point_id === started[0].point_id);
    const box0 = await canvasBox(page, '#map-plot canvas');
    await page.mouse.move(box0.x + waiting.x, box0.y + waiting.y);
    await page.locator('#tooltip:not([hidden])').waitFor();
    assert.match(await page.locator('#tooltip').innerText(), new RegExp(`robust\\s+no: ${3 - started[0].finished} of 3 pending`));
    await shot(page, 'replicates-02-map-filling');
    await page.mouse.move(box0.x + 2, box0.y + 2);
    h.startWorker('w1');

    // --- The map: four points of three runs each, once every run finished.
    const m = await waitFor(async () => {
      const s = await mapState(page);
      return s && s.count === 4 && s.runs === 12 && !s.counts.queued && !s.counts.running ? s : null;
    }, { timeoutMs: 150000, intervalMs: 300, what: 'four finished points of 3 runs on the map' });
    const answer = (await h.api('/phase-map?phi=0.4&sweep=1')).json;
    assert.equal(answer.points.length, 12);
    assert.equal(answer.summaries.length, 4);
    for (const s of answer.summaries) {
      const p = m.points.find((q) => q.point_id === s.point_id);
      assert.ok(p, `point ${s.point_id} drawn`);
      assert.deepEqual(p.jobs, s.jobs, `point ${s.point_id}: its runs`);
      assert.equal(p.share, s.share, `point ${s.point_id}: its share`);
      assert.equal(p.robust, s.robust, `point ${s.point_id}: robust`);
      assert.equal(p.cat, s.label ?? p.cat, `point ${s.point_id}: drawn as its majority`);
      assert.equal(p.split !== null, s.share !== null && s.share < 1, `point ${s.point_id}: a pie only when its replicates split`);
    }
    assert.match(await page.locator('#map-summary').innerText(), /^4 points \(12 runs\) at φ = 0.4/);
    const legendTotal = await page.locator('#map-legend li[data-cat]').evaluateAll((lis) => lis.reduce((a, li) => a + Number(li.dataset.count), 0));
    assert.equal(legendTotal, 4, 'the legend counts points');
    assert.equal(await page.locator('#map-keys li[data-key="unsettled"]').count(), 1, 'the key of a point that is not robust');
    // A point with a label that is not robust has its dashed ring, a robust one (or one without a label) none.
    const robust = m.points.filter((p) => p.robust), other = m.points.filter((p) => !p.robust);
    assert.ok(robust.length > 0 && other.length > 0, `these tiny runs give robust and other points: ${JSON.stringify(answer.summaries.map((s) => [s.label, s.robust]))}`);
    for (const p of m.points) {
      assert.equal(p.unsettled, !p.robust && !!CLASSES[p.cat], `point ${p.point_id} (${p.cat}, robust ${p.robust})`);
      assert.equal(await ringed(page, p, m.radius), p.unsettled, `point ${p.point_id} (${p.cat}, robust ${p.robust}): a dashed ring when unsettled`);
    }
    await shotsAtSizes(page, 'replicates-03-map');

    // --- Hover: the point's runs, share and readings; a click pins it; its link opens a run.
    const target = (await mapState(page)).points.find((p) => p.point_id === robust[0].point_id); // where the last render put it
    const summary = answer.summaries.find((s) => s.point_id === target.point_id);
    const box = await canvasBox(page, '#map-plot canvas');
    await page.mouse.move(box.x + target.x, box.y + target.y);
    await page.locator('#tooltip:not([hidden])').waitFor();
    const tip = await page.locator('#tooltip').innerText();
    assert.match(tip, new RegExp(`point ${target.point_id} · 3 runs · robust`));
    assert.match(tip, /share\s+1\.00 \(3 of 3 labelled\)/);
    assert.match(tip, new RegExp(`classes\\s+${target.cat} 1\\.00`));
    if (summary.band_speed_ratio) assert.match(tip, new RegExp(`c\\s*b\\s*/\\s*V\\s+${summary.band_speed_ratio.mean.toFixed(3)} ± ${summary.band_speed_ratio.sd.toFixed(3)} \\(n = 3\\)`));
    assert.deepEqual(await page.locator('#tooltip .tt-run a').evaluateAll((as) => as.map((a) => a.getAttribute('href'))), target.jobs.map((j) => `#/run/${j}`));
    await page.mouse.click(box.x + target.x, box.y + target.y);
    await page.locator('#tooltip.pinned').waitFor();
    await shot(page, 'replicates-04-map-pinned');
    const second = target.jobs[1];
    await page.locator(`#tooltip a[data-job="${second}"]`).click();
    await page.waitForURL(new RegExp(`#/run/${second}$`));

    // --- The run page: its point's runs, a link to each sibling.
    const job = (await h.api(`/jobs/${second}`)).json;
    assert.deepEqual([...job.replicates].sort((a, b) => a - b), target.jobs.filter((j) => j !== second));
    const reps = page.locator('#run-replicates');
    await reps.waitFor();
    await waitFor(async () => (await reps.getAttribute('data-runs')) === '3', { what: 'the point\'s runs on the run page' });
    assert.equal(await reps.getAttribute('data-point'), String(job.point_id));
    const rtext = await reps.innerText();
    assert.match(rtext, new RegExp(`Replicate \\(seed ${job.scene.seed}, perturbation 0.01\\) of point ${job.point_id}: 3 runs`));
    assert.match(rtext, /robust/);
    assert.match(rtext, /the other 2 runs:/);
    assert.deepEqual(await reps.locator('.siblings a').evaluateAll((as) => as.map((a) => a.getAttribute('href'))), job.replicates.map((j) => `#/run/${j}`));
    await page.locator('#st-canvas, #st-img').first().waitFor({ timeout: 15000 });
    await shotsAtSizes(page, 'replicates-05-run', ['#run-replicates[data-runs="3"]', '#st-canvas', '#stress-svg']);
    await reps.locator(`.siblings a[data-job="${job.replicates[0]}"]`).click();
    await page.waitForURL(new RegExp(`#/run/${job.replicates[0]}$`));
    await waitFor(async () => (await page.locator(`#run-replicates .siblings a[data-job="${second}"]`).count()) === 1, { what: 'the sibling listing the run we came from' });

    // --- Robust only: the control hides the points that are not robust, in the URL too.
    await gotoMap(page, `${h.url}/#/map?phi=0.4&sweep=1`);
    const every = await waitFor(async () => { const s = await mapState(page); return s?.count === 4 ? s : null; }, { what: 'the map again' });
    await page.locator('#map-robust').check();
    const only = await waitFor(async () => { const s = await mapState(page); return s?.robustOnly ? s : null; }, { what: 'the robust-only map' });
    assert.equal(only.count, robust.length);
    assert.ok(only.points.every((p) => p.robust));
    assert.deepEqual(only.points.map((p) => p.point_id).sort(), robust.map((p) => p.point_id).sort());
    for (const p of only.points) {
      const q = every.points.find((x) => x.point_id === p.point_id);
      assert.deepEqual([p.x, p.y], [q.x, q.y], `point ${p.point_id} stays where it was: the axes span every point`);
    }
    assert.match(page.url(), /robust=1/);
    assert.match(await page.locator('#map-summary').innerText(), new RegExp(`robust only: ${other.length} other point`));
    await shot(page, 'replicates-06-map-robust-only');
    await page.reload();
    await waitFor(async () => { const s = await mapState(page); return s?.robustOnly && s.count === robust.length; }, { what: 'robust only from the URL' });
    assert.equal(await page.locator('#map-robust').isChecked(), true);
    await page.locator('#map-robust').uncheck();
    await waitFor(async () => { const s = await mapState(page); return s && !s.robustOnly && s.count === 4; }, { what: 'every point again' });
    assert.doesNotMatch(page.url(), /robust=/);

    assert.deepEqual(h.pageErrors.filter((e) => !/422/.test(e)), [], 'no errors in the page besides the refused request');
  } catch (e) {
    for (const [k, v] of Object.entries(h.logs)) if (v) console.log(`# ${k} log tail:\n${v.slice(-3000)}`);
    throw e;
  } finally {
    await h.close();
  }
});

// Labels decided per point and seed: A unanimous (a, robust), B split 3:1 (b over a), C a 2:2
// tie (c and f, equal confidences: the earlier letter), D three a and one unclassified (share 1,
// not robust); E and F one run each (no replicates), and the unperturbed run at A's place.
const PHI = 0.4;
const A = { S: 3e-3, R: 1e-4 }, B = { S: 1e-2, R: 1e-3 }, C = { S: 3e-2, R: 1e-2 }, D = { S: 3e-3, R: 1e-2 }, E = { S: 1e-2, R: 1e-4 }, F = { S: 3e-2, R: 1e-4 };
const NUMERICS = { preset: 'fast', cells_per_unit: 5, eps_end: 0.03 };
const at = (q, scene) => near(scene.S, q.S) && near(scene.R, q.R);
// c_b/V of a band run: a 1.6 + 0.1 seed, b 2.0 + 0.2 seed (so B's three b runs read 2.4 ± 0.2).
function verdict(scene) {
  const seed = scene.seed, perturbed = scene.perturbation > 0;
  const band = (c) => ({ class: c, confidence: 0.97, runner_up: c === 'a' ? 'b' : 'a', n_reflections: c === 'b' ? 2 : 0, band_speed_ratio: c === 'a' ? 1.6 + 0.1 * seed : 2.0 + 0.2 * seed });
  if (!perturbed) return band('a'); // E, F and A's unperturbed run
  if (at(A, scene)) return band('a');
  if (at(B, scene)) return band(seed === 4 ? 'a' : 'b');
  if (at(C, scene)) return { class: seed <= 2 ? 'c' : 'f', confidence: 0.9, runner_up: 'b', n_reflections: null, band_speed_ratio: null };
  if (at(D, scene)) return seed === 4 ? { class: null, confidence: 0, runner_up: 'b', n_reflections: 0, band_speed_ratio: null } : band('a');
  throw new Error(`unexpected scene ${JSON.stringify(scene)}`);
}

test('split points show a pie of their classes, points that are not robust a dashed ring; the pinned tooltip opens a run; bands at the replicates\' mean ± sd', { timeout: 150000 }, async () => {
  const h = new Harness('replicates-labelled');
  try {
    await h.startServer();
    const sweeps = [
      { name: 'replicated', points: [A, B, C, D].map((q) => ({ ...q, phi: PHI })), numerics: NUMERICS, replicates: { n: 4, perturbation: 0.01 } },
      { name: 'single', points: [A, E, F].map((q) => ({ ...q, phi: PHI })), numerics: NUMERICS },
    ];
    for (const body of sweeps) {
      const r = await h.api('/sweeps', body);
      assert.equal(r.status, 201, JSON.stringify(r.json));
    }
    assert.equal(await completeAll(h.url, verdict), 19, '4 points x 4 replicates and 3 single runs');
    const answer = (await h.api(`/phase-map?phi=${PHI}`)).json;
    const sum = (q, runs) => answer.summaries.find((s) => at(q, s) && s.runs === runs);
    const [sA, sB, sC, sD, sE, sA1] = [sum(A, 4), sum(B, 4), sum(C, 4), sum(D, 4), sum(E, 1), sum(A, 1)];
    assert.deepEqual([sA.label, sA.share, sA.robust], ['a', 1, true]);
    assert.deepEqual([sB.label, sB.share, sB.robust, sB.probabilities], ['b', 0.75, false, { a: 0.25, b: 0.75 }]);
    assert.deepEqual([sC.label, sC.share, sC.robust], ['c', 0.5, false]);
    assert.deepEqual([sD.label, sD.share, sD.robust, sD.labelled], ['a', 1, false, 3]);
    assert.ok(Math.abs(sB.band_speed_ratio.mean - 2.4) < 1e-9 && Math.abs(sB.band_speed_ratio.sd - 0.2) < 1e-9 && sB.band_speed_ratio.n === 3, JSON.stringify(sB.band_speed_ratio));

    const page = await h.browser({ width: 1440, height: 900 });
    await page.goto(`${h.url}/#/map?phi=${PHI}&regions=0`);
    await waitFor(async () => (await mapState(page))?.count === 7, { what: 'seven points on the map' });
    await shotsAtSizes(page, 'replicates-10-map-labelled');
    const m = await mapState(page);
    assert.equal(m.runs, 19);
    assert.match(await page.locator('#map-summary').innerText(), /^7 points \(19 runs\) at 6 places .* · 1 robust/);
    const drawn = (s) => m.points.find((p) => p.point_id === s.point_id);
    const [pA, pB, pC, pD, pE, pA1] = [sA, sB, sC, sD, sE, sA1].map(drawn);
    // The perturbed and the unperturbed runs at A's place are two points, set apart.
    assert.ok(Math.hypot(pA.x - pA1.x, pA.y - pA1.y) >= 2 * m.radius, 'A\'s two points do not cover each other');

    // B: a square of b with a pie inside, its quarter of a from 9 to 12 o'clock.
    assert.equal(pB.cat, 'b');
    assert.deepEqual(pB.split, [['b', 0.75], ['a', 0.25]]);
    const pieB = pieOf({ ...pB, r: m.radius }).pr;
    const aPart = await pixel(page, pB.x - 0.5 * pieB * Math.SQRT1_2, pB.y - 0.5 * pieB * Math.SQRT1_2);
    const bPart = await pixel(page, pB.x + 0.5 * pieB * Math.SQRT1_2, pB.y + 0.5 * pieB * Math.SQRT1_2);
    assert.ok(close(aPart, hexRgb(CLASSES.a.color), 40), `B's quarter of a is drawn ${aPart}`);
    assert.ok(close(bPart, hexRgb(CLASSES.b.color), 40), `B's b is drawn ${bPart}`);
    // C: a diamond of c, half of the pie (the left) f.
    assert.equal(pC.cat, 'c');
    const pieC = pieOf({ ...pC, r: m.radius }).pr;
    assert.ok(close(await pixel(page, pC.x - 0.5 * pieC, pC.y), hexRgb(CLASSES.f.color), 40), 'C\'s half of f');
    assert.ok(close(await pixel(page, pC.x + 0.5 * pieC, pC.y), hexRgb(CLASSES.c.color), 40), 'C\'s half of c');
    // B, C and D (one replicate unlabelled) are not robust: their dashed rings; A (robust) and the
    // single runs have none.
    for (const p of [pA, pB, pC, pD, pE]) {
      assert.equal(p.unsettled, [pB, pC, pD].includes(p), `point ${p.point_id}: unsettled`);
      assert.equal(await ringed(page, p, m.radius), p.unsettled, `point ${p.point_id}: a dashed ring only when not robust`);
    }
    // The unperturbed run beside A: no ring on its side away from A's.
    const away = Math.sign(pA1.y - pA.y) || 1;
    assert.equal(inky(await darkest(page, ...ringAt(pA1, m.radius, away).dash)), false, 'no ring around the unperturbed run');
    for (const p of [pA, pD, pE, pA1]) assert.equal(p.split, null);
    assert.ok(close(await pixel(page, pD.x, pD.y), hexRgb(CLASSES.a.color), 12), 'D is full a: no pie');
    // A single run looks as runs always did: share 1, not robust, its run's id.
    assert.deepEqual([pE.jobs.length, pE.share, pE.robust, pE.job_id], [1, 1, false, sE.jobs[0]]);

    // --- B's tooltip: share, classes, c_b/V mean ± sd (n) and its four runs; pinned, its a run opens.
    const box = await canvasBox(page, '#map-plot canvas');
    await page.mouse.move(box.x + pB.x, box.y + pB.y);
    await page.locator('#tooltip:not([hidden])').waitFor();
    const tip = await page.locator('#tooltip').innerText();
    assert.match(tip, new RegExp(`point ${sB.point_id} · 4 runs`));
    assert.doesNotMatch(tip, /robust$/m);
    assert.match(tip, /share\s+0\.75 \(3 of 4 labelled\)/);
    assert.match(tip, /classes\s+b 0\.75\s+a 0\.25/);
    assert.match(tip, /robust\s+no: they split/);
    assert.match(tip, /c\s*b\s*\/\s*V\s+2\.400 ± 0\.200 \(n = 3\)/);
    assert.match(tip, /N\s*r\s+2\.00 ± 0\.00 \(n = 3\)/);
    assert.equal(await page.locator('#tooltip .tt-run').count(), 4);
    await page.mouse.click(box.x + pB.x, box.y + pB.y);
    await page.locator('#tooltip.pinned').waitFor();
    await page.mouse.move(box.x + 5, box.y + 5); // away: a pinned tooltip stays
    await page.waitForTimeout(200);
    assert.equal(await page.locator('#tooltip.pinned').isVisible(), true);
    await shot(page, 'replicates-11-map-split-pinned');
    const aRun = sB.jobs[3]; // seed 4: the replicate labelled a
    assert.match(await page.locator(`#tooltip .tt-run:has(a[data-job="${aRun}"])`).innerText(), /run \d+ a$/);
    await page.keyboard.press('Escape');
    await waitFor(async () => !(await page.locator('#tooltip').isVisible()), { what: 'Escape to close the pinned tooltip' });
    await page.mouse.click(box.x + pB.x, box.y + pB.y);
    await page.locator(`#tooltip.pinned a[data-job="${aRun}"]`).click();
    await page.waitForURL(new RegExp(`#/run/${aRun}$`));
    const reps = page.locator('#run-replicates');
    await waitFor(async () => (await reps.getAttribute('data-runs')) === '4', { what: 'B\'s runs on the run page' });
    const rtext = await reps.innerText();
    assert.match(rtext, /b · reflecting band in 3 of 4 labelled/);
    assert.match(rtext, /share 0\.75/);
    assert.match(rtext, /not robust \(they split\)/);
    assert.equal(await reps.locator('.siblings a').count(), 3);
    await shotsAtSizes(page, 'replicates-12-run-split', ['#run-replicates[data-runs="4"]', '#stress-svg']);

    // --- Robust only: A alone.
    await gotoMap(page, `${h.url}/#/map?phi=${PHI}&regions=0&robust=1`);
    // (the page's first render, before its answer, draws nothing: wait for the one after)
    const only = await waitFor(async () => { const s = await mapState(page); return s?.robustOnly && s.count === 1 ? s : null; }, { what: 'robust only: one point' });
    assert.deepEqual(only.points.map((p) => p.point_id), [sA.point_id]);

    // --- The export: one marker per point, B's with its pie.
    await page.locator('#map-robust').uncheck();
    await waitFor(async () => (await mapState(page))?.count === 7, { what: 'every point again' });
    const [dl] = await Promise.all([page.waitForEvent('download'), page.locator('#map-export-svg').click()]);
    const svg = await page.evaluate((text) => {
      const doc = new DOMParser().parseFromString(text, 'image/svg+xml');
      const groups = [...doc.querySelectorAll('[data-layer="markers"] > g')];
      return { count: groups.length, paths: groups.map((g) => g.querySelectorAll('path').length), legend: [...doc.querySelectorAll('[data-layer="legend"] text')].map((t) => t.textContent) };
    }, readFileSync(await dl.path(), 'utf8'));
    assert.equal(svg.count, 7);
    assert.ok(svg.legend.some((t) => /not robust/.test(t)) && svg.legend.some((t) => /pie/.test(t)), 'the keys of a split point and one that is not robust');

    // --- Band speed: A, B, D and E, F and A's unperturbed run are bands; C is not. B at the mean
    // of its three b runs, 2.4, with a bar from 2.2 to 2.6 (their sd); E as its run.
    await page.goto(`${h.url}/#/bands?phi=${PHI}`);
    const bands = await waitFor(async () => {
      const b = await page.evaluate(() => window.__dashboard?.bands ?? null);
      return b && b.plotted.length === 6 ? b : null;
    }, { what: 'six bands plotted' });
    const plotted = (s) => bands.plotted.find((q) => q.point_id === s.point_id);
    const qB = plotted(sB);
    assert.deepEqual([qB.kind, qB.n], ['sd', 3]);
    assert.ok(Math.abs(qB.v - 2.4) < 1e-9 && Math.abs(qB.e - 0.2) < 1e-9, JSON.stringify(qB));
    const qE = plotted(sE);
    const runE = answer.points.find((p) => p.job_id === sE.jobs[0]);
    assert.deepEqual([qE.kind, qE.v, qE.e], ['run', runE.band_speed_ratio, runE.band_speed_error]);
    assert.equal(plotted(sC), undefined);
    const bar = await page.locator(`#bands-plot line.error-bar[data-point="${sB.point_id}"]`).evaluate((l) => ({ y1: Number(l.getAttribute('y1')), y2: Number(l.getAttribute('y2')), cls: l.getAttribute('class') }));
    const area = await page.locator('#bands-plot rect.plot-area').evaluate((r) => ({ y: Number(r.getAttribute('y')), h: Number(r.getAttribute('height')) }));
    const yOf = (v) => area.y + ((Math.log10(bands.yDomain[1]) - Math.log10(v)) / (Math.log10(bands.yDomain[1]) - Math.log10(bands.yDomain[0]))) * area.h;
    assert.ok(Math.abs(bar.y1 - yOf(2.6)) < 0.01 && Math.abs(bar.y2 - yOf(2.2)) < 0.01, `B's bar from 2.2 to 2.6: ${JSON.stringify(bar)}`);
    assert.match(bar.cls, /\bsd\b/);
    assert.match(await page.locator('#bands-summary').innerText(), /6 bands plotted of 7 points \(19 runs\) at φ = 0.4 · 3 replicate means ± sd/);
    await shotsAtSizes(page, 'replicates-13-bands');
    const again = await waitFor(async () => { const b = await page.evaluate(() => window.__dashboard.bands); return b.plotted.length === 6 ? b : null; }, { what: 'the bands at 1440 px again' });
    const qB2 = again.plotted.find((q) => q.point_id === sB.point_id);
    const bbox = await canvasBox(page, '#bands-plot canvas');
    await page.mouse.move(bbox.x + qB2.x, bbox.y + qB2.y);
    await page.locator('#tooltip:not([hidden])').waitFor();
    assert.match(await page.locator('#tooltip').innerText(), /point \d+ · 4 runs[\s\S]*fit\)\s+2\.400 ± 0\.200 \(n = 3\)/);
    await shot(page, 'replicates-14-bands-tooltip');

    assert.deepEqual(h.pageErrors, [], 'no errors in the page');
  } catch (e) {
    for (const [k, v] of Object.entries(h.logs)) if (v) console.log(`# ${k} log tail:\n${v.slice(-3000)}`);
    throw e;
  } finally {
    await h.close();
  }
});
