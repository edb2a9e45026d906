// The phase map's view and numerics in real headless Chromium against a real compaction-server
// that imported the committed maps (as scripts/main.sh does): the adaptive Fig. 2 sweep (200
// runs at the default preset), the scan around example (c) at 1/20 decade (155 runs, 6 of them
// the Fig. 2 map's own) and its 7 reference-preset runs at places of the scan. Checks: the default
// numerics show one point per place, the finest (a reference run where there is one), and the
// caption says which; "all resolutions" shows both; the dense scan's markers stay apart; the
// wheel zooms about the cursor (the point under it stays under it, its tooltip too) and writes the
// view into the URL, a drag pans, a reload restores the view, reset restores the points' extent;
// the adaptive sweep shows its plan's state and the points its planner added; at 390 x 844 the
// page is no wider than the screen. Screenshots at 1440 x 900 and 390 x 844.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { Harness, REPO, artifactsDir, canvasBox, waitFor } from './lib/harness.mjs';
import { completeAll } from './lib/labelled.mjs';

const PHI = 0.4;
const EXPORTS = ['sweep-2', 'example-c', 'example-c-reference'].map((n) => join(REPO, 'studies', 'phase_map', 'results', `${n}.export.json`));

async function shot(page, name) {
  const path = join(artifactsDir(), `${name}.png`);
  await page.screenshot({ path, fullPage: true });
  console.log(`# screenshot ${path}`);
}

const mapState = (page) => page.evaluate(() => window.__dashboard?.phaseMap ?? null);
const placeOf = (p) => `${p.S.toPrecision(10)}|${p.R.toPrecision(10)}`;
const hash = (page) => decodeURIComponent(new URL(page.url()).hash);

// The render after `since` (window.__dashboard.renderedAt), once it satisfies ok.
async function nextRender(page, since, ok = () => true, what = 'a new render') {
  return waitFor(async () => {
    const at = await page.evaluate(() => window.__dashboard?.renderedAt ?? 0);
    if (at <= since) return null;
    const s = await mapState(page);
    return s && ok(s) ? { ...s, at } : null;
  }, { timeoutMs: 15000, what });
}
const renderedAt = (page) => page.evaluate(() => window.__dashboard?.renderedAt ?? 0);

test('the phase map zooms and pans, keeps its view in the URL and shows the finest run per point', { timeout: 200000 }, async () => {
  const h = new Harness('map-zoom');
  try {
    await h.startServer();
    for (const f of EXPORTS) {
      const res = await fetch(`${h.url}/api/v1/imports`, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: readFileSync(f) });
      assert.equal(res.status, 200, `${f}: ${await res.text()}`);
    }
    const answer = (await h.api(`/phase-map?phi=${PHI}`)).json;
    const { summaries } = answer;
    const places = new Map(); // place -> its points
    for (const s of summaries) places.set(placeOf(s), [...(places.get(placeOf(s)) || []), s]);
    const twins = [...places.values()].filter((g) => g.some((s) => s.cells_per_unit === 40));
    assert.equal(answer.points.length, 200 + 155 - 6 + 7, 'the three imports: 6 scan runs are the map\'s own');
    assert.equal(twins.length, 7, 'the 7 reference runs sit at places of the scan');
    for (const g of twins) assert.deepEqual(g.map((s) => s.cells_per_unit).sort((a, b) => a - b), [20, 40], 'a default and a reference point');
    // A seventh run of the map in the scan differs from the map's in the 12th digit of R
    // (0.0056234132519 and 0.00562341325191): two computations, one place, one resolution.
    const doubles = [...places.values()].filter((g) => g.length > 1 && g.every((s) => s.cells_per_unit === 20));
    assert.equal(doubles.length, 1);
    const finest = summaries.length - 7; // the reference runs' places show no default run

    const page = await h.browser({ width: 1440, height: 900 });
    await page.goto(`${h.url}/#/map?phi=${PHI}&regions=0`);
    // --- Default numerics: one point per place, the finest; the caption says which.
    const m = await waitFor(async () => {
      const s = await mapState(page);
      return s && s.count === finest ? s : null;
    }, { timeoutMs: 20000, what: `${finest} points, one resolution per place` });
    assert.equal(m.numerics, 'finest');
    for (const g of twins) {
      const drawn = m.points.filter((p) => g.some((s) => s.point_id === p.point_id));
      assert.equal(drawn.length, 1, 'one marker at a place with two resolutions');
      assert.equal(drawn[0].cells_per_unit, 40, 'the finer one');
    }
    const caption = await page.locator('#map-numerics').innerText();
    assert.equal(caption, `finest run per point: 4.5 cells across a strut at ${finest - 7} points, 9 at 7 points · 7 coarser points not shown (numerics: all resolutions)`);
    assert.equal(await page.locator('#map-cpu').inputValue(), 'finest');
    assert.doesNotMatch(hash(page), /cpu=/, 'the default keeps no cpu in the URL');
    // The scan's markers (1/20 decade apart) do not cover each other.
    const scan = m.points.filter((p) => Math.abs(Math.log10(summaries.find((s) => s.point_id === p.point_id).S) + 1.4) < 0.11);
    assert.ok(scan.length >= 100, `${scan.length} points of the scan`);
    // Each marker's radius is read from its spacing: clear of its neighbours, never below 2.4 px.
    const clear = scan.filter((p) => scan.every((q) => q === p || Math.hypot(p.x - q.x, p.y - q.y) >= p.r + q.r - 0.01));
    assert.ok(clear.length >= 0.95 * scan.length, `${clear.length} of ${scan.length} scan markers clear of the others`);
    assert.ok(scan.every((p) => p.r >= 2.4), `radii ${Math.min(...scan.map((p) => p.r))} to ${Math.max(...scan.map((p) => p.r))}`);
    assert.ok(m.points.some((p) => p.r === m.radius) && scan.some((p) => p.r < m.radius), 'sparse points keep the full radius, dense ones less');
    await shot(page, 'map-zoom-01-finest-1440x900');

    // --- All resolutions: both runs at the seven places.
    let since = await renderedAt(page);
    await page.locator('#map-cpu').selectOption('all');
    const all = await nextRender(page, since, (s) => s.count === summaries.length, 'every point');
    assert.match(hash(page), /cpu=all/);
    assert.match(await page.locator('#map-numerics').innerText(), new RegExp(`^all resolutions: 4.5 cells across a strut at ${summaries.length - 7} points, 9 at 7 points$`));
    for (const g of twins) assert.equal(all.points.filter((p) => g.some((s) => s.point_id === p.point_id)).length, 2);
    since = await renderedAt(page);
    await page.locator('#map-cpu').selectOption('finest');
    await nextRender(page, since, (s) => s.count === finest, 'one resolution per place again');

    // --- Wheel: zoom about the cursor. The point under it stays under it, with its tooltip.
    const st = await mapState(page);
    const target = st.points.find((p) => p.cells_per_unit === 40); // a reference run
    const box = await canvasBox(page, '#map-plot canvas');
    const cx = box.x + target.x, cy = box.y + target.y;
    await page.mouse.move(cx, cy);
    since = await renderedAt(page);
    await page.mouse.wheel(0, -400); // in: e^(-0.6), 0.55 of the span
    const z = await nextRender(page, since, (s) => s.zoomed, 'the zoomed map');
    const span = (v) => [v.S[1] - v.S[0], v.R[1] - v.R[0]];
    const [s0, r0] = span(st.view), [s1, r1] = span(z.view);
    assert.ok(s1 < 0.7 * s0 && r1 < 0.7 * r0, `spans ${s0.toFixed(3)} x ${r0.toFixed(3)} -> ${s1.toFixed(3)} x ${r1.toFixed(3)} decades`);
    assert.ok(Math.abs(s1 / s0 - r1 / r0) < 0.01, 'both axes zoom alike');
    const zt = z.points.find((p) => p.point_id === target.point_id);
    assert.ok(Math.hypot(zt.x - target.x, zt.y - target.y) < 1.5, `the point under the cursor moved from (${target.x}, ${target.y}) to (${zt.x}, ${zt.y})`);
    assert.ok(z.radius >= st.radius, 'markers do not shrink when zoomed in');
    const url = hash(page);
    const q = new URLSearchParams(url.split('?')[1]);
    assert.deepEqual(q.get('S').split(',').map(Number), z.view.S.map((v) => Number(v.toFixed(4))), `the URL ${url} holds the view's S`);
    assert.deepEqual(q.get('R').split(',').map(Number), z.view.R.map((v) => Number(v.toFixed(4))), 'and its R');
    await page.mouse.move(cx + 1, cy);
    await page.locator('#tooltip:not([hidden])').waitFor();
    assert.match(await page.locator('#tooltip').innerText(), new RegExp(`run ${target.job_id}\\b`), 'the tooltip of the same run');
    assert.ok(z.count < st.count, `${z.count} of ${st.count} points in the view`);
    assert.match(await page.locator('#map-summary').innerText(), new RegExp(`${z.count} in the view`));
    await shot(page, 'map-zoom-02-zoomed-1440x900');
    // The SVG export is the view: the markers in it, the note naming it.
    await page.mouse.move(0, 0);
    const [dl] = await Promise.all([page.waitForEvent('download'), page.locator('#map-export-svg').click()]);
    assert.equal(dl.suggestedFilename(), `phase-map-phi${PHI}-zoomed.svg`);
    const svg = await page.evaluate((text) => {
      const doc = new DOMParser().parseFromString(text, 'image/svg+xml');
      return { markers: doc.querySelectorAll('[data-layer="markers"] > g').length, legend: [...doc.querySelectorAll('[data-layer="legend"] text')].map((t) => t.textContent) };
    }, readFileSync(await dl.path(), 'utf8'));
    const zNow = await mapState(page);
    assert.equal(svg.markers, zNow.count, 'the export holds the view\'s markers');
    assert.ok(svg.legend.some((t) => t.startsWith(`view: log10 S ${zNow.view.S.map((v) => Number(v.toFixed(4))).join(' to ')}`)), svg.legend.join(' | '));

    // --- Drag: pan by (120, -60) px; the view moves the other way by as many decades.
    const zoomed = z.view;
    since = await renderedAt(page);
    const [px, py] = [box.x + box.width / 2, box.y + box.height / 2];
    await page.mouse.move(px, py);
    await page.mouse.down();
    for (let k = 1; k <= 6; k++) await page.mouse.move(px + 20 * k, py - 10 * k);
    await page.mouse.up();
    const d = await nextRender(page, since, (s) => Math.abs(s.view.S[0] - zoomed.S[0]) > 1e-3, 'the panned map');
    await page.waitForTimeout(300);
    const panned = (await mapState(page)).view;
    const dS = -120 / d.area.width * s1, dR = -60 / d.area.height * r1;
    assert.ok(Math.abs(panned.S[0] - zoomed.S[0] - dS) < 2e-3 && Math.abs(panned.R[0] - zoomed.R[0] - dR) < 2e-3,
      `panned by ${(panned.S[0] - zoomed.S[0]).toFixed(4)}, ${(panned.R[0] - zoomed.R[0]).toFixed(4)} decades, expected ${dS.toFixed(4)}, ${dR.toFixed(4)}`);
    assert.ok(Math.abs(span(panned)[0] - s1) < 2e-3, 'a pan keeps the span');
    assert.match(hash(page), /^#\/map\?/, 'a drag opens no run');

    // --- A reload shows the same view.
    await page.reload();
    const back = await waitFor(async () => { const s = await mapState(page); return s?.zoomed && s.count > 0 ? s : null; }, { timeoutMs: 15000, what: 'the map after a reload' });
    for (const k of ['S', 'R']) for (const i of [0, 1]) assert.ok(Math.abs(back.view[k][i] - panned[k][i]) < 2e-4, `${k}[${i}] ${back.view[k][i]} after the reload, ${panned[k][i]} before`);
    assert.equal(await page.locator('#map-cpu').inputValue(), 'finest');

    // --- Reset: every point again, the URL without a view.
    since = await renderedAt(page);
    await page.locator('#map-reset').click();
    const reset = await nextRender(page, since, (s) => !s.zoomed, 'the reset map');
    assert.equal(reset.count, finest);
    for (const k of ['S', 'R']) for (const i of [0, 1]) assert.ok(Math.abs(reset.view[k][i] - st.view[k][i]) < 1e-6, 'the points\' extent again');
    assert.doesNotMatch(hash(page), /[?&](S|R)=/);
    assert.ok(await page.locator('#map-reset').isDisabled());

    // --- The adaptive sweep: its plan's state and the points its planner added.
    const sweeps = (await h.api('/sweeps')).json.sweeps;
    const adaptive = sweeps.find((s) => s.request.adaptive);
    const plan = (await h.api(`/sweeps/${adaptive.id}/plan`)).json;
    since = await renderedAt(page);
    await page.locator('#map-sweep').selectOption(String(adaptive.id));
    const a = await nextRender(page, since, (s) => s.count === 200 && s.points.some((p) => p.added), 'the adaptive sweep with its added points');
    const added = a.points.filter((p) => p.added).length;
    assert.equal(200 - added, 25, 'the 5 x 5 initial grid is not marked');
    const planText = await page.locator('#map-plan').innerText();
    assert.match(planText, new RegExp(`^adaptive plan: ${plan.state.replace('_', ' ')} · ${plan.runs.done + plan.runs.pending} of ${plan.runs.budget} runs`));
    assert.match(planText, new RegExp(`${added} points added by the planner \\(dot at upper right\\), 25 of the initial grid`));
    assert.match(planText, /CPU-hours/);
    assert.ok(await page.locator('#map-keys li[data-key="added"]').count() === 1, 'the key of the added points');
    await shot(page, 'map-zoom-03-adaptive-1440x900');

    // --- A phone: the page is no wider than the screen; zoom in there too.
    await page.setViewportSize({ width: 390, height: 844 });
    await page.waitForTimeout(500);
    const widths = await page.evaluate(() => ({ doc: document.documentElement.scrollWidth, vw: window.innerWidth }));
    assert.ok(widths.doc <= widths.vw, `scrollWidth ${widths.doc} > ${widths.vw}`);
    await shot(page, 'map-zoom-04-adaptive-390x844');
    await page.goto(`${h.url}/#/map?phi=${PHI}&regions=0&S=-1.5,-1.2&R=-2.5,-1`);
    await waitFor(async () => { const s = await mapState(page); return s?.zoomed && s.count > 0; }, { what: 'the zoomed map on a phone' });
    await page.waitForTimeout(300);
    const phone = await page.evaluate(() => ({ doc: document.documentElement.scrollWidth, vw: window.innerWidth }));
    assert.ok(phone.doc <= phone.vw, `zoomed: scrollWidth ${phone.doc} > ${phone.vw}`);
    await shot(page, 'map-zoom-05-zoomed-390x844');
    // Two fingers spread apart zoom in about their middle (touch through the DevTools protocol).
    const cdp = await page.context().newCDPSession(page);
    await cdp.send('Emulation.setTouchEmulationEnabled', { enabled: true, maxTouchPoints: 5 });
    const before = await mapState(page);
    const tb = await canvasBox(page, '#map-plot canvas');
    const [mx, my] = [tb.x + tb.width / 2, tb.y + tb.height / 2];
    const fingers = (d) => [{ x: mx - d, y: my, id: 1 }, { x: mx + d, y: my, id: 2 }];
    since = await renderedAt(page);
    await cdp.send('Input.dispatchTouchEvent', { type: 'touchStart', touchPoints: fingers(30) });
    for (const d of [40, 50, 60]) await cdp.send('Input.dispatchTouchEvent', { type: 'touchMove', touchPoints: fingers(d) });
    await cdp.send('Input.dispatchTouchEvent', { type: 'touchEnd', touchPoints: [] });
    const pinched = await nextRender(page, since, (s) => span(s.view)[0] < 0.6 * span(before.view)[0], 'the pinched map');
    const mid = (v) => [(v.S[0] + v.S[1]) / 2, (v.R[0] + v.R[1]) / 2];
    assert.ok(Math.abs(mid(pinched.view)[0] - mid(before.view)[0]) < 0.01 * span(before.view)[0], 'zoomed about the fingers\' middle');
    await cdp.send('Emulation.setTouchEmulationEnabled', { enabled: false });
    await page.setViewportSize({ width: 1440, height: 900 });
    await page.waitForTimeout(400);
    await shot(page, 'map-zoom-06-zoomed-scan-1440x900');

    // A plain click on a marker still opens its run (a drag only captures the pointer once it moves).
    const one = await mapState(page);
    const mark = one.points.find((p) => p.r >= 4 && p.x > 20 && p.y > 20 && p.x < one.area.width - 20 && p.y < one.area.height - 20);
    const cbox = await canvasBox(page, '#map-plot canvas');
    await page.mouse.click(cbox.x + mark.x, cbox.y + mark.y);
    await waitFor(async () => hash(page) === `#/run/${mark.job_id}`, { what: `the run page of ${mark.job_id} after a click` });

    assert.deepEqual(h.pageErrors, [], 'no errors in the page');
  } catch (e) {
    for (const [k, v] of Object.entries(h.logs)) if (v) console.log(`# ${k} log tail:\n${v.slice(-3000)}`);
    throw e;
  } finally {
    await h.close();
  }
});

// The column: the 2D map by default, the 3D one when chosen (the server draws one geometry at a
// time), in the URL across a reload. A 2D and a 3D run at one place, labelled through the worker
// API: each map shows its own, with its own class.
test('the phase map draws one geometry at a time and the column choice picks it', { timeout: 120000 }, async () => {
  const h = new Harness('map-geometry');
  try {
    await h.startServer();
    const point = { S: 1e-2, R: 1e-3, phi: PHI };
    const ids = [];
    for (const [name, geometry] of [['2d', undefined], ['3d', 'pseudo1d_3d']]) {
      const r = await h.api('/sweeps', { name, points: [point], numerics: { cells_per_unit: 8, eps_end: 0.01, ...(geometry ? { geometry } : {}) } });
      assert.equal(r.status, 201, JSON.stringify(r.json));
      ids.push((await h.api(`/jobs?sweep=${r.json.id}`)).json.jobs[0].id);
    }
    const [id2, id3] = ids;
    const byGeometry = (scene) => ({ class: scene.geometry === 'pseudo1d_3d' ? 'b' : 'a', confidence: 0.9, runner_up: 'c', n_reflections: 1, band_speed_ratio: 2 });
    assert.equal(await completeAll(h.url, byGeometry), 2);

    const page = await h.browser({ width: 1440, height: 900 });
    await page.goto(`${h.url}/#/map?phi=${PHI}&regions=0`);
    const shown = (ids) => waitFor(async () => {
      const s = await mapState(page);
      return s && JSON.stringify(s.points.map((p) => p.job_id)) === JSON.stringify(ids) ? s : null;
    }, { timeoutMs: 15000, what: `the map of runs ${ids}` });
    const m2 = await shown([id2]);
    assert.equal(m2.points[0].cat, 'a', 'the 2D run by default');
    await page.selectOption('#map-geometry', 'pseudo1d_3d');
    const m3 = await shown([id3]);
    assert.equal(m3.points[0].cat, 'b', 'the 3D run once the 3D column is chosen');
    assert.match(hash(page), /geometry=pseudo1d_3d/);
    await page.reload();
    await shown([id3]);
    assert.equal(await page.inputValue('#map-geometry'), 'pseudo1d_3d', 'the choice survives a reload');
    await page.selectOption('#map-geometry', '');
    await shown([id2]);
    assert.doesNotMatch(hash(page), /geometry=/);
    assert.deepEqual(h.pageErrors, [], 'no errors in the page');
  } catch (e) {
    for (const [k, v] of Object.entries(h.logs)) if (v) console.log(`# ${k} log tail:\n${v.slice(-3000)}`);
    throw e;
  } finally {
    await h.close();
  }
});
