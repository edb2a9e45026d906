// The adaptive sweep's plan page (#/plan?sweep=ID, web/js/pages/plan.js) in real headless Chromium
// against a real compaction-server: an adaptive sweep with two levels of numerics, two replicates
// and a CPU-hour budget created through POST /api/v1/sweeps at tiny numerics, its results posted
// one at a time through the real worker API by lib/labelled.mjs (no simulation), a class boundary
// at R = 3e-3.
// Every number the page shows (each carries data-k, its path in the plan's JSON) equals
// GET /sweeps/{id}/plan's: state, resolved, runs and CPU-hours against the budgets, each level's
// points, robust points, runs, CPU-hours and next runs, the lattice, each candidate's S, R, level,
// replicate, weight (value), why and CPU seconds, each S column's points, boundaries, bracket,
// resolution and finest level; the state's words are mapplan.js's for it. The
// page follows each result as it arrives (polled with If-None-Match: 304s while nothing changes) and
// stops asking once unmounted; the sweeps list's "plan" link and the map caption's link lead to
// it, a candidate's link leads to the map around its point, the limit select lists fewer; an unknown
// id, a grid sweep and a missing id get their messages; 390 x 844 without sideways scroll; no
// JavaScript errors. Screenshots at 1440 x 900 and 390 x 844 go to $BROWSER_ARTIFACTS_DIR.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { Harness, WEB_DIR, artifactsDir, waitFor } from './lib/harness.mjs';
import { completeAll } from './lib/labelled.mjs';

const { PLAN_STATES } = await import(join(WEB_DIR, 'js', 'mapplan.js'));

const PHI = 0.4;
const ADAPTIVE = {
  name: 'plan page', phi: PHI, numerics: { preset: 'fast', eps_end: 0.04 },
  adaptive: {
    S: { min: 0.02, max: 0.1 }, R: { min: 1e-4, max: 1e-1 }, initial: { S: 3, R: 3 }, resolution_decades: 0.3, budget: 40, in_flight: 1,
    levels: [{ cells_per_unit: 5 }, { cells_per_unit: 6 }],
  },
  replicates: { n: 2, perturbation: 0.01 },
};
const GRID = { name: 'one point', S: 0.05, R: 1e-3, phi: PHI, numerics: { preset: 'fast', cells_per_unit: 5, eps_end: 0.04 } };
// The labels: a below R = 3e-3, b above (the initial grid's R 1e-4 | 3.2e-3, 0.1 disagree). On
// this field the sweep ends resolved after about 33 runs, its candidates on the way ranked for
// every reason but "unsure" (map, replicate, level, follow).
const verdict = (scene) => (scene.R < 3e-3
  ? { class: 'a', confidence: 0.9, runner_up: 'b', n_reflections: 0, band_speed_ratio: 1.67 }
  : { class: 'b', confidence: 0.9, runner_up: 'a', n_reflections: 2, band_speed_ratio: 2.5 });

async function shot(page, name) {
  await page.evaluate(() => window.scrollTo(0, 0));
  const path = join(artifactsDir(), `${name}.png`);
  await page.screenshot({ path, fullPage: true });
  console.log(`# screenshot ${path}`);
}

const at = (obj, path) => path.split('.').reduce((o, k) => (o === null || o === undefined ? undefined : o[k]), obj);
// A number as the page writes it (format.js sci: three significant digits, "3.12×10-4" in text).
const parsed = (t) => Number(t.replace(/,/g, '').replace('×10', 'e').replace('−', '-'));
const sig3 = (v) => Number(v.toPrecision(3));

// Compares every data-k of the page with the plan; returns nothing or throws naming the first
// difference. The keys the page must show are checked to be there.
async function matches(page, plan) {
  const shown = await page.$$eval('#pn-body [data-k]', (els) => els.map((e) => [e.dataset.k, e.innerText.trim()]));
  const keys = new Set(shown.map(([k]) => k));
  const want = ['state', 'resolved', 'replicates', 'runs.done', 'runs.pending', 'runs.budget', 'runs.budget_left', 'cpu_hours.spent', 'candidates_total',
    'lattice.step_S_decades', 'lattice.step_R_decades', 'lattice.S', 'lattice.R', 'lattice.points', 'lattice.runs'];
  if (plan.cpu_hours.budget !== null) want.push('cpu_hours.budget', 'cpu_hours.budget_left');
  plan.levels.forEach((_, i) => want.push(...['cells_per_unit', 'points', 'robust', 'runs.done', 'runs.pending', 'cpu_hours.done', 'cpu_hours.pending', 'next.runs', 'next.cpu_hours'].map((k) => `levels.${i}.${k}`)));
  plan.candidates.forEach((_, i) => want.push(...['S', 'R', 'level', 'replicate', 'why', 'value', 'cpu_seconds'].map((k) => `candidates.${i}.${k}`)));
  plan.columns.forEach((c, i) => want.push(...['S', 'points', 'boundaries', 'resolved', 'finest_level', ...(c.bracket_decades === null ? [] : ['bracket_decades'])].map((k) => `columns.${i}.${k}`)));
  assert.equal(await page.locator('#pn-body tr[data-column]').count(), plan.columns.length, 'one row an S column');
  for (const k of want) assert.ok(keys.has(k), `the page shows ${k}`);
  assert.equal(await page.locator('#pn-body tr[data-rank]').count(), plan.candidates.length, 'one row a candidate');
  for (const [k, text] of shown) {
    const v = at(plan, k);
    assert.notEqual(v, undefined, `${k} is in the plan`);
    if (typeof v === 'boolean') assert.equal(text, v ? 'resolved' : 'not resolved', k);
    else if (typeof v === 'string') assert.equal(text, v.replace('_', ' '), k);
    else if (Number.isInteger(v) && !k.includes('cpu') && !k.includes('value') && !k.includes('step')) assert.equal(parsed(text), v, `${k}: "${text}" against ${v}`);
    else assert.equal(parsed(text), sig3(v), `${k}: "${text}" against ${v}`);
  }
  assert.equal(await page.locator('.pn-state-text').innerText(), PLAN_STATES[plan.state].text, 'the state in words');
  const share = `${Math.round((100 * (plan.runs.done + plan.runs.pending)) / plan.lattice.runs)} %`;
  assert.equal(await page.locator('[data-derived="share"]').innerText(), share);
  const runsBar = page.locator('[data-budget="runs"] [role="progressbar"]');
  assert.equal(await runsBar.getAttribute('aria-valuenow'), String(plan.runs.done + plan.runs.pending));
  assert.equal(await runsBar.getAttribute('aria-valuemax'), String(plan.runs.budget));
  if (plan.cpu_hours.budget !== null) {
    assert.equal(Number(await page.locator('[data-budget="cpu"] [role="progressbar"]').getAttribute('aria-valuemax')), plan.cpu_hours.budget);
  }
}

// Waits until the page shows the API's plan (asked at each try with the page's limit).
async function showsPlan(h, page, id, limit = 20, what = 'the page to show the plan') {
  let plan;
  await waitFor(async () => {
    plan = (await h.api(`/sweeps/${id}/plan?limit=${limit}`)).json;
    await matches(page, plan);
    return true;
  }, { timeoutMs: 12000, intervalMs: 300, what });
  return plan;
}

test('the plan page shows the plan\'s every number, follows results, and links to and from the list and the map', { timeout: 200000 }, async () => {
  const h = new Harness('plan-page');
  try {
    await h.startServer();
    // The CPU-hour budget: ten times the initial grid's at the first level, by the server's estimate.
    const est = (await h.api('/sweeps/estimate', ADAPTIVE)).json;
    assert.ok(est.cpu_hours > 0, JSON.stringify(est));
    const body = { ...ADAPTIVE, adaptive: { ...ADAPTIVE.adaptive, budget_cpu_hours: Number((est.cpu_hours * 10).toPrecision(6)) } };
    const created = await h.api('/sweeps', body);
    assert.equal(created.status, 201, JSON.stringify(created.json));
    const id = created.json.id;
    const grid = await h.api('/sweeps', GRID);
    assert.equal(grid.status, 201, JSON.stringify(grid.json));
    assert.equal((await h.api(`/sweeps/${grid.json.id}/cancel`, {})).status, 200);

    // The API's answer carries an ETag and is a 304 to it while nothing changes.
    const first = await fetch(`${h.url}/api/v1/sweeps/${id}/plan?limit=20`);
    const etag = first.headers.get('ETag');
    assert.ok(etag, 'the plan has an ETag');
    assert.equal((await fetch(`${h.url}/api/v1/sweeps/${id}/plan?limit=20`, { headers: { 'If-None-Match': etag } })).status, 304);
    assert.equal((await h.api(`/sweeps/${grid.json.id}/plan`)).status, 409, 'a grid sweep has no plan');

    const page = await h.browser({ width: 1440, height: 900 });
    const planAsks = [];
    page.on('response', (r) => { if (/\/api\/v1\/sweeps\/\d+\/plan/.test(r.url())) planAsks.push({ url: r.url(), status: r.status(), at: Date.now() }); });

    // --- From the sweeps list: the adaptive sweep's row links to its plan, the grid sweep's does not.
    await page.goto(`${h.url}/#/sweeps`);
    const row = page.locator(`tr[data-sweep="${id}"]`);
    await row.locator('a.plan-link').waitFor();
    await page.locator(`tr[data-sweep="${grid.json.id}"]`).waitFor();
    assert.equal(await page.locator(`tr[data-sweep="${grid.json.id}"] a.plan-link`).count(), 0, 'no plan link for a grid sweep');
    await row.locator('a.plan-link').click();
    await waitFor(async () => (await page.evaluate(() => location.hash)) === `#/plan?sweep=${id}`, { what: 'the plan page\'s address' });
    assert.equal(await page.locator('.nav a.active').getAttribute('data-page'), 'sweeps');
    let plan = await showsPlan(h, page, id, 20, 'the initial plan');
    assert.equal(plan.state, 'running');
    assert.equal(plan.runs.pending, 9, 'the 3 x 3 initial grid queued');
    assert.equal(plan.levels.length, 2);
    assert.match(await page.locator('#pn-name').innerText(), /plan page/);
    await shot(page, 'plan-01-initial-1440x900');

    // --- A result arrives: the page shows the new plan without a reload.
    assert.equal(await completeAll(h.url, verdict, { most: 1 }), 1);
    plan = await showsPlan(h, page, id, 20, 'the plan after one result');
    assert.equal(plan.runs.done, 1);
    // Nothing changes now: the page's asks are answered 304.
    const since = Date.now();
    await waitFor(() => planAsks.some((a) => a.at > since && a.status === 304), { timeoutMs: 8000, what: 'a 304 to the page\'s poll' });

    // --- The initial grid done: the planner ranks candidates; each is shown with its weight and why.
    assert.equal(await completeAll(h.url, verdict, { most: 8 }), 8);
    plan = await showsPlan(h, page, id, 20, 'the plan with candidates');
    assert.ok(plan.candidates.length > 0, `candidates after the initial grid: ${JSON.stringify(plan)}`);
    console.log(`# after the initial grid: ${plan.state}, ${plan.candidates_total} candidates, whys ${[...new Set(plan.candidates.map((c) => c.why))]}`);
    await shot(page, 'plan-02-candidates-1440x900');

    // The limit: 10 listed at most, in the URL, the same as the API's limit=10.
    if (plan.candidates_total > 1) {
      await page.locator('#pn-limit').selectOption('10');
      await waitFor(async () => /limit=10/.test(await page.evaluate(() => location.hash)), { what: 'limit=10 in the address' });
      await showsPlan(h, page, id, 10, 'the plan with 10 candidates at most');
      await page.locator('#pn-limit').selectOption('20');
      await showsPlan(h, page, id, 20, 'the plan with 20 candidates at most');
    }

    // A candidate's link: the map at the sweep's phi, filtered to the sweep, centred on its point.
    const c0 = plan.candidates[0];
    const href = await page.locator('tr[data-rank="0"] a.pn-map').getAttribute('href');
    const q = new URLSearchParams(href.split('?')[1]);
    assert.equal(Number(q.get('phi')), PHI);
    assert.equal(q.get('sweep'), String(id));
    const mid = (s) => s.split(',').map(Number).reduce((a, b) => a + b) / 2;
    assert.ok(Math.abs(mid(q.get('S')) - Math.log10(c0.S)) < 1e-3 && Math.abs(mid(q.get('R')) - Math.log10(c0.R)) < 1e-3, `the view centred on the candidate: ${href}`);
    await page.locator('tr[data-rank="0"] a.pn-map').click();
    await page.locator('#map-plot canvas').waitFor();
    await waitFor(async () => (await page.locator('#map-sweep').inputValue()) === String(id), { what: 'the map filtered to the sweep' });
    await waitFor(async () => /log10 S/.test(await page.locator('#map-view-text').innerText()), { what: 'the map\'s view from the link' });

    // --- From the map's plan caption back to the plan page.
    const caption = page.locator('#map-plan a.plan-link');
    await caption.waitFor();
    assert.equal(await caption.getAttribute('href'), `#/plan?sweep=${id}`);
    await caption.click();
    await waitFor(async () => (await page.evaluate(() => location.hash)) === `#/plan?sweep=${id}`, { what: 'the plan page from the map' });
    plan = await showsPlan(h, page, id, 20, 'the plan from the map');

    // --- One result at a time to the end: the page follows each, and shows every reason the
    // planner ranks a run for on this field, then the final state in words.
    const whys = new Set();
    for (let step = 0; step < 40 && !PLAN_STATES[plan.state].done; step++) {
      assert.equal(await completeAll(h.url, verdict, { most: 1 }), 1, `a run queued at step ${step}: ${JSON.stringify(plan.runs)}`);
      plan = await showsPlan(h, page, id, 20, `the plan after result ${plan.runs.done + 1}`);
      for (const w of await page.$$eval('[data-k$=".why"]', (els) => els.map((e) => e.innerText))) whys.add(w);
    }
    assert.equal(plan.state, 'resolved', `the field's boundary resolved: ${JSON.stringify(plan)}`);
    assert.ok(plan.runs.done <= 40, 'within the runs budget');
    for (const w of ['map', 'replicate', 'level']) assert.ok(whys.has(w), `a candidate for "${w}" shown on the way (${[...whys]})`);
    assert.ok(plan.levels[1].runs.done > 0 && plan.levels[1].robust > 0, 'the finer level ran, with robust points');
    console.log(`# final: ${plan.state}, candidates shown on the way for ${[...whys]}, ${plan.runs.done} runs, ${plan.cpu_hours.spent} of ${plan.cpu_hours.budget} CPU-hours, levels ${JSON.stringify(plan.levels.map((l) => [l.points, l.robust, l.runs.done]))}`);
    assert.ok(plan.levels[0].runs.done >= 9, 'the initial grid at level 0');
    // A resolved plan: every S column of a point brackets the boundary within the finest R step.
    assert.ok(plan.columns.length >= 3, `the initial grid's three S at least: ${JSON.stringify(plan.columns)}`);
    for (const c of plan.columns) assert.ok(c.resolved && (c.bracket_decades === null || c.bracket_decades <= plan.lattice.step_R_decades + 1e-9), JSON.stringify(c));
    assert.match(await page.locator('#pn-columns-count').innerText(), /all resolved/);
    await shot(page, 'plan-03-final-1440x900');

    // --- Unmounted, the page asks no more.
    await page.goto(`${h.url}/#/sweeps`);
    await row.waitFor();
    const left = Date.now();
    await page.waitForTimeout(3500);
    assert.deepEqual(planAsks.filter((a) => a.at > left + 200), [], 'no plan asked after leaving the page');

    // --- An unknown id, a grid sweep, no id.
    await page.goto(`${h.url}/#/plan?sweep=999`);
    await waitFor(async () => /No sweep #999 on this server/.test(await page.locator('#pn-problem').innerText()), { what: 'the unknown id\'s message' });
    await page.goto(`${h.url}/#/plan?sweep=${grid.json.id}`);
    await waitFor(async () => new RegExp(`Sweep #${grid.json.id} \\(one point\\) is not adaptive`).test(await page.locator('#pn-problem').innerText()), { what: 'the grid sweep\'s message' });
    await shot(page, 'plan-04-grid-sweep-1440x900');
    await page.goto(`${h.url}/#/plan`);
    await waitFor(async () => /No sweep given/.test(await page.locator('#pn-problem').innerText()), { what: 'the missing id\'s message' });

    // --- A phone: no sideways scroll; the tables scroll in their own boxes.
    await page.setViewportSize({ width: 390, height: 844 });
    await page.goto(`${h.url}/#/plan?sweep=${id}`);
    await showsPlan(h, page, id, 20, 'the plan on a phone');
    const w = await page.evaluate(() => ({ scroll: document.documentElement.scrollWidth, window: window.innerWidth }));
    assert.ok(w.scroll <= w.window, `no sideways scroll at 390 px: ${JSON.stringify(w)}`);
    await shot(page, 'plan-05-final-390x844');

    // The only errors: the browser's notes of the 404 and 409 asked on purpose.
    assert.deepEqual(h.pageErrors.filter((e) => !/status of (404|409)/.test(e)), [], 'no JavaScript errors');
  } catch (e) {
    for (const [k, v] of Object.entries(h.logs)) if (v) console.log(`# ${k} log tail:\n${v.slice(-3000)}`);
    throw e;
  } finally {
    await h.close();
  }
});
