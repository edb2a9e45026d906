// The dashboard in real headless Chromium against a real compaction-server and compaction-worker
// on a temporary database: the sweep form (job count, field validation, submit), the phase map
// filling up live with the right count, looks and colours, hover and click, the run page's
// space-time map, stress plot and snapshot, the band-speed and sweeps pages. Screenshots of each
// page go to $BROWSER_ARTIFACTS_DIR (default: <tmp>/compaction-browser-artifacts).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { Harness, artifactsDir, canvasBox, waitFor } from './lib/harness.mjs';

// Tiny runs (about 0.1 s each): pseudo-1D, 5 cells per unit cell, to eps = 0.04.
const TINY = { cpu: '5', epsEnd: '0.04', snapshots: '0.02' };
// The Okabe-Ito colours of js/classes.js and the look of a done, unclassified point.
const EXPECTED = { a: '#0072B2', b: '#56B4E9', c: '#009E73', d: '#E69F00', e: '#D55E00', f: '#CC79A7', unclassified: '#8a8f98' };
const hexRgb = (h) => [1, 3, 5].map((i) => parseInt(h.slice(i, i + 2), 16));

async function shot(page, name) {
  const path = join(artifactsDir(), `${name}.png`);
  await page.screenshot({ path, fullPage: true });
  console.log(`# screenshot ${path}`);
}

// The phase-map hook the page keeps for tests (window.__dashboard.phaseMap).
const mapState = (page) => page.evaluate(() => window.__dashboard?.phaseMap ?? null);

async function fillForm(page, v) {
  for (const [id, value] of Object.entries(v)) {
    const el = page.locator(`#f-${id}`);
    if ((await el.evaluate((e) => e.tagName)) === 'SELECT') await el.selectOption(value);
    else await el.fill(value);
  }
}

test('a sweep submitted through the form fills the phase map live; its runs render', { timeout: 240000 }, async () => {
  const h = new Harness('dashboard');
  try {
    await h.startServer();
    h.startWorker('w1');
    const page = await h.browser();
    await page.goto(`${h.url}/#/sweeps`);
    await page.locator('#sweep-form').waitFor();
    await page.locator('#f-preset option[value="fast"]').waitFor({ state: 'attached' }); // presets loaded

    // --- The form: job count before submitting, invalid ranges rejected next to the field.
    await page.locator('details.advanced summary').first().click();
    await fillForm(page, { name: 'browser test', 's-min': '0.03', 's-max': '0.1', 's-n': '2', 'r-min': '1e-4', 'r-max': '1e-2', 'r-n': '2', phi: '0.4', preset: 'fast', cpu: TINY.cpu, 'eps-end': TINY.epsEnd, snapshots: TINY.snapshots });
    assert.equal(await page.locator('#job-count').getAttribute('data-count'), '4');
    assert.match(await page.locator('#job-count').innerText(), /4\s*jobs\s*=\s*2 S × 2 R × 1 φ/);

    await fillForm(page, { 's-min': '0.5', 's-max': '0.1' });
    await page.locator('#submit-sweep').click();
    await waitFor(async () => /max must be ≥ min/.test(await page.locator('#err-s-max').innerText()), { what: 'the S max error' });
    assert.equal(await page.locator('#f-s-max').getAttribute('aria-invalid'), 'true');
    assert.match(await page.locator('#form-message').innerText(), /fix the fields/);
    await fillForm(page, { 's-min': '1.5' });
    await waitFor(async () => /must be in \(0, 1\)/.test(await page.locator('#err-s-min').innerText()), { what: 'the S min error' });
    await fillForm(page, { 'r-n': '0', phi: '0.9' });
    await waitFor(async () => (await page.locator('#err-r-n').innerText()).length > 0 && /\[0.2, 0.8\]/.test(await page.locator('#err-phi').innerText()), { what: 'the R points and phi errors' });
    await shot(page, '01-sweep-form-invalid');
    // A grid too coarse for its phi: the server's estimate says so once the rest is valid, at
    // the field it names.
    await fillForm(page, { 's-min': '0.03', 's-max': '0.1', 'r-n': '2', cpu: '3', phi: '0.4' });
    await waitFor(async () => /too coarse/.test(await page.locator('#err-cpu').innerText()), { what: 'the cells-per-unit error' });
    assert.equal((await h.api('/sweeps')).json.total, 0, 'an invalid form must not create a sweep');

    // --- A valid 2 x 2 sweep.
    await fillForm(page, { 's-min': '0.03', 's-max': '0.1', 'r-n': '2', cpu: TINY.cpu });
    assert.equal(await page.locator('.f.invalid').count(), 0, 'no field left invalid');
    await page.locator('#submit-sweep').click();
    await waitFor(async () => /Sweep #1 created with 4 jobs/.test(await page.locator('#form-message').innerText()), { timeoutMs: 10000, what: 'the created message' });
    await page.locator('#form-message a').click(); // "Watch it on the phase map"
    await page.waitForURL(/#\/map\?phi=0.4&sweep=1/);

    // --- The map shows the four points, done (unclassified until the classifier lands, or
    // labelled), with the colour of their category at their centre.
    const done = await waitFor(async () => {
      const m = await mapState(page);
      return m && m.count === 4 && m.points.every((p) => p.cat in EXPECTED || p.cat === 'unstable') ? m : null;
    }, { timeoutMs: 90000, intervalMs: 250, what: 'four finished points on the map' });
    const legendTotal = await page.locator('#map-legend li[data-cat]').evaluateAll((lis) => lis.reduce((a, li) => a + Number(li.dataset.count), 0));
    assert.equal(legendTotal, 4, 'legend counts add up to the points');
    for (const p of done.points.filter((q) => q.cat in EXPECTED)) {
      const rgb = await page.evaluate(({ x, y }) => {
        const c = document.querySelector('#map-plot canvas');
        const dpr = c.width / c.clientWidth;
        return Array.from(c.getContext('2d').getImageData(Math.round(x * dpr), Math.round(y * dpr), 1, 1).data.slice(0, 3));
      }, p);
      // A label is faded towards white by its confidence (p.fade, confidenceFade in classes.js).
      const want = hexRgb(EXPECTED[p.cat]).map((v) => Math.round(v + (255 - v) * (p.fade || 0)));
      assert.ok(rgb.every((v, i) => Math.abs(v - want[i]) <= 12), `point of run ${p.job_id} (${p.cat}) drawn ${rgb}, expected ${want}`);
    }
    await shot(page, '02-phase-map-done');

    // --- Live: with the worker stopped, a new sweep's point appears queued without a reload,
    // then turns done when a worker runs it.
    await page.evaluate(() => { window.__noReload = true; });
    h.procs[1].kill('SIGTERM'); // the worker w1
    await waitFor(() => h.procs[1].exitCode !== null || h.procs[1].signalCode !== null, { what: 'worker exit' });
    await page.locator('#map-sweep').selectOption(''); // all sweeps at phi 0.4
    const extra = await h.api('/sweeps', { name: 'live', S: 0.05, R: 3e-3, phi: 0.4, numerics: { preset: 'fast', cells_per_unit: 5, eps_end: 0.04 } });
    assert.equal(extra.status, 201, JSON.stringify(extra.json));
    const queued = await waitFor(async () => {
      const m = await mapState(page);
      return m && m.count === 5 && m.counts.queued === 1 ? m : null;
    }, { timeoutMs: 15000, what: 'the new point, queued, on the map' });
    assert.ok(queued.points.some((p) => p.cat === 'queued'));
    assert.equal(await page.locator('#map-legend li[data-cat="queued"]').getAttribute('data-count'), '1');
    await shot(page, '03-phase-map-queued');
    // Nothing changes while no worker runs: the polls ask with If-None-Match and get 304s,
    // and the map stays as it was.
    const statuses = [];
    const onResponse = (r) => { if (r.url().includes('/api/v1/phase-map?')) statuses.push(r.status()); };
    page.on('response', onResponse);
    await waitFor(() => statuses.filter((s) => s === 304).length >= 2, { timeoutMs: 15000, what: 'two 304 answers to the map\'s polls' });
    page.off('response', onResponse);
    assert.ok(statuses.every((s) => s === 200 || s === 304), `poll statuses: ${statuses}`);
    const still = await mapState(page);
    assert.equal(still.count, 5);
    assert.equal(still.counts.queued, 1);
    h.startWorker('w2');
    await waitFor(async () => {
      const m = await mapState(page);
      return m && m.count === 5 && !m.counts.queued && !m.counts.running;
    }, { timeoutMs: 60000, intervalMs: 250, what: 'the new point done' });
    assert.equal(await page.evaluate(() => window.__noReload), true, 'the page was not reloaded');

    // --- Hover shows the run's numbers; click opens it.
    const target = (await mapState(page)).points[0];
    const box = await canvasBox(page, '#map-plot canvas');
    await page.mouse.move(box.x + target.x, box.y + target.y);
    await page.locator('#tooltip:not([hidden])').waitFor();
    const tip = await page.locator('#tooltip').innerText();
    assert.match(tip, new RegExp(`run ${target.job_id}`));
    for (const k of ['S', 'R', 'class', 'confidence', 'N', 'c']) assert.match(tip, new RegExp(`^${k}`, 'm'));
    await shot(page, '04-phase-map-hover');
    await page.mouse.click(box.x + target.x, box.y + target.y);
    await page.waitForURL(new RegExp(`#/run/${target.job_id}$`));

    // --- Run detail: the space-time map from spacetime.npy, the stress plot, the snapshot.
    const st = page.locator('#st-canvas');
    await st.waitFor({ timeout: 15000 });
    const stInfo = await st.evaluate((c) => {
      const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
      const colours = new Set();
      let lit = 0;
      for (let i = 0; i < d.length; i += 4) {
        if (d[i] + d[i + 1] + d[i + 2] > 60) lit++;
        colours.add((d[i] << 16) | (d[i + 1] << 8) | d[i + 2]);
      }
      return { w: c.width, h: c.height, cw: c.clientWidth, ch: c.clientHeight, lit, colours: colours.size, frames: Number(c.dataset.frames), rows: Number(c.dataset.rows) };
    });
    assert.ok(stInfo.cw >= 400 && stInfo.ch >= 300, `space-time canvas ${stInfo.cw} x ${stInfo.ch}`);
    assert.equal(stInfo.w, Math.round(stInfo.cw * (await page.evaluate(() => devicePixelRatio))));
    assert.equal(stInfo.frames, 20, 'eps_end 0.04 / d_eps 0.002 = 20 frames');
    assert.ok(stInfo.rows > 100, `rows ${stInfo.rows}`);
    assert.ok(stInfo.lit > 200 && stInfo.colours > 8, `space-time map content: ${stInfo.lit} lit pixels, ${stInfo.colours} colours`);
    // Every frame drawn: on the linear axis (the log axis, the default, leaves a gap where a plate
    // carries less than 1e-3 q_y, as the bottom one does before the elastic wave reaches it).
    await page.locator('#stress-fig button[data-scale="linear"]').click();
    const stress = await page.locator('#stress-svg[data-scale="linear"]').evaluate((svg) => {
      const r = svg.getBoundingClientRect();
      const paths = [...svg.parentElement.querySelectorAll('path[data-series]')];
      return { w: r.width, h: r.height, series: paths.map((p) => ({ s: p.dataset.series, n: (p.getAttribute('d').match(/L/g) || []).length, len: p.getTotalLength() })) };
    });
    assert.ok(stress.w >= 400 && stress.h >= 300, `stress plot ${stress.w} x ${stress.h}`);
    assert.deepEqual(stress.series.map((s) => s.s).sort(), ['bottom', 'top']);
    for (const s of stress.series) assert.ok(s.n >= 20 && s.len > 100, `stress series ${s.s}: ${s.n} segments, length ${s.len}`);
    // The snapshot is drawn from its particles (snapshot_*.npy) on a canvas of its own.
    const snap = await page.locator('#snap-canvas').evaluate((c) => {
      const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
      const colours = new Set();
      for (let i = 0; i < d.length; i += 4) colours.add((d[i] << 16) | (d[i + 1] << 8) | d[i + 2]);
      return { w: c.width, h: c.height, cw: c.clientWidth, colours: colours.size };
    });
    assert.ok(snap.w > 10 && snap.h > 10 && snap.cw > 10 && snap.colours > 4, `snapshot ${JSON.stringify(snap)}`);
    assert.ok(await page.locator('#files-box a[href$="spacetime.npy"]').count() === 1, 'download link of spacetime.npy');
    assert.match(await page.locator('#state-box').innerText(), /succeeded/);
    await shot(page, '05-run-detail');

    // --- Band speed and sweeps pages render (no labels yet: the band plot may be empty).
    await page.goto(`${h.url}/#/bands?phi=0.4`);
    await page.locator('#bands-plot canvas').waitFor();
    await shot(page, '06-band-speed');
    await page.goto(`${h.url}/#/sweeps`);
    const row = page.locator('tr[data-sweep="1"]');
    await row.waitFor();
    await waitFor(async () => /done · 4 done of 4/.test(await row.innerText()), { what: 'sweep 1 done in the list' });
    assert.equal(await row.locator('a', { hasText: 'CSV' }).getAttribute('href'), '/api/v1/sweeps/1/export?format=csv');
    const csv = await page.evaluate(async () => (await fetch('/api/v1/sweeps/1/export?format=csv')).text());
    assert.equal(csv.trim().split('\n').length, 5, 'CSV export: a header and four jobs');
    await shot(page, '07-sweeps');

    assert.deepEqual(h.pageErrors.filter((e) => !/422/.test(e)), [], 'no errors in the page besides the estimate that refused the coarse grid');
  } catch (e) {
    for (const [k, v] of Object.entries(h.logs)) if (v) console.log(`# ${k} log tail:\n${v.slice(-3000)}`);
    throw e;
  } finally {
    await h.close();
  }
});

test('with a submit token on the server, the form asks for it and then submits', { timeout: 90000 }, async () => {
  const h = new Harness('token');
  try {
    await h.startServer(['--submit-token', 'sesame']);
    const page = await h.browser();
    await page.goto(`${h.url}/#/sweeps`);
    await page.locator('#f-preset option[value="fast"]').waitFor({ state: 'attached' });
    await fillForm(page, { name: 'token test', 's-n': '1', 'r-n': '1', preset: 'fast' });
    await page.locator('#submit-sweep').click();
    await waitFor(async () => /needs a submit token/.test(await page.locator('#err-token').innerText()), { what: 'the token error' });
    assert.match(await page.locator('#form-message').innerText(), /Not allowed \(401\)/);
    await page.locator('#f-token').fill('wrong');
    await page.locator('#submit-sweep').click();
    await waitFor(async () => /refused/.test(await page.locator('#err-token').innerText()), { what: 'the wrong-token error' });
    await shot(page, '08-sweep-form-token');
    await page.locator('#f-token').fill('sesame');
    await page.locator('#submit-sweep').click();
    await waitFor(async () => /Sweep #1 created with 1 jobs/.test(await page.locator('#form-message').innerText()), { what: 'the created message' });
    assert.equal(await page.evaluate(() => localStorage.getItem('compaction.submitToken')), 'sesame', 'the token is kept in this browser');
    assert.equal(await page.locator('#err-token').innerText(), '');
    // Cancel from the list uses the stored token.
    page.once('dialog', (d) => d.accept());
    await page.locator('tr[data-sweep="1"] button.cancel').click();
    await waitFor(async () => /Sweep #1 cancelled/.test(await page.locator('#form-message').innerText()), { what: 'the cancel message' });
    await waitFor(async () => (await h.api('/sweeps/1')).json.state === 'cancelled', { what: 'sweep 1 cancelled on the server' });
    assert.deepEqual(h.pageErrors.filter((e) => !/401|403/.test(e)), [], 'no errors in the page besides the refused requests');
  } finally {
    await h.close();
  }
});
