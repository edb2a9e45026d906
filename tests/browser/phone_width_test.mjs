// Every page of the dashboard on a phone (issue 49, item 6): at 390 x 844 each route of
// web/js/main.js (#/map, #/run/ID of a local run with results and of an imported run, #/runs,
// alone and with its Columns fold open, #/compare, #/plots, #/bands, #/sweeps with the form's
// advanced parts open, #/labels, #/plan of an adaptive sweep left queued) renders with the
// document no wider than the window, no element's right edge past the window except inside a
// box that scrolls sideways itself (overflow-x auto or scroll; the offender is named), and every
// nav link visible inside the window and clickable. Data: the committed studies/phase_map/results/sweep-2.export.json
// through POST /imports (as scripts/main.sh does), a local sweep completed through the worker API
// (lib/labelled.mjs) and a second one queued (progress in the sweeps list). Screenshots of every
// page at 390 x 844 and of the sweeps page at 1440 x 900 go to $BROWSER_ARTIFACTS_DIR.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { Harness, REPO, artifactsDir, waitFor } from './lib/harness.mjs';
import { completeAll } from './lib/labelled.mjs';

const EXPORT = join(REPO, 'studies', 'phase_map', 'results', 'sweep-2.export.json');
const SWEEP = {
  name: 'phone width test', S: { min: 1e-3, max: 1e-1, n: 3, scale: 'log' }, R: { min: 1e-4, max: 1e-2, n: 2, scale: 'log' }, phi: 0.4,
  numerics: { preset: 'fast', cells_per_unit: 5, eps_end: 0.1 },
};
// An adaptive sweep over the same box, left queued: its plan page (#/plan).
const ADAPTIVE = { S: { min: 1e-3, max: 1e-1 }, R: { min: 1e-4, max: 1e-2 }, initial: { S: 2, R: 2 }, resolution_decades: 0.5, budget: 6 };

async function shot(page, name) {
  const path = join(artifactsDir(), `${name}.png`);
  await page.screenshot({ path, fullPage: true });
  console.log(`screenshot: ${path}`);
}

// The page has rendered: no "loading…" left in it, and a moment for its figures.
async function settle(page) {
  await waitFor(async () => !/loading…/.test(await page.locator('#page').innerText()), { timeoutMs: 15000, what: 'the page to load' });
  await page.waitForTimeout(600);
}

// No sideways scroll; no element sticking out past the window unless a box between it and the
// page scrolls sideways itself.
async function fits(page, name) {
  const r = await page.evaluate(() => {
    const W = window.innerWidth;
    const scrolls = (el) => { for (let p = el.parentElement; p; p = p.parentElement) { const o = getComputedStyle(p).overflowX; if (o === 'auto' || o === 'scroll') return true; } return false; };
    const out = [];
    for (const el of document.body.querySelectorAll('*')) {
      const b = el.getBoundingClientRect();
      if (b.width === 0 || b.height === 0 || getComputedStyle(el).visibility === 'hidden') continue;
      if (b.right > W + 0.5 && !scrolls(el)) {
        const id = el.id ? `#${el.id}` : '';
        const cls = typeof el.className === 'string' && el.className ? `.${el.className.trim().split(/\s+/).join('.')}` : '';
        out.push(`${el.tagName.toLowerCase()}${id}${cls} right ${Math.round(b.right)}`);
      }
    }
    return { scroll: document.documentElement.scrollWidth, window: W, out };
  });
  assert.ok(r.scroll <= r.window, `${name}: the page scrolls sideways (${r.scroll} > ${r.window}): ${r.out.slice(0, 8).join('; ')}`);
  assert.deepEqual(r.out.slice(0, 8), [], `${name}: elements past the window's right edge`);
}

// Every nav link is visible inside the window and a click on it opens its page.
async function navReachable(page, name) {
  const links = page.locator('.nav a');
  const n = await links.count();
  assert.ok(n >= 5, `${name}: ${n} nav links`);
  const W = await page.evaluate(() => window.innerWidth);
  for (let i = 0; i < n; i++) {
    const a = links.nth(i);
    await a.scrollIntoViewIfNeeded();
    assert.ok(await a.isVisible(), `${name}: nav link ${i} hidden`);
    const b = await a.boundingBox();
    assert.ok(b && b.x >= 0 && b.x + b.width <= W + 0.5, `${name}: nav link ${await a.innerText()} outside the window: ${JSON.stringify(b)}`);
    await a.click({ trial: true }); // clickable there: nothing covers it
  }
}

test('every page at 390 x 844: no sideways scroll, nothing past the edge, the nav reachable', { timeout: 200000 }, async () => {
  const h = new Harness('phone-width');
  try {
    await h.startServer();
    const res = await fetch(`${h.url}/api/v1/imports`, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: readFileSync(EXPORT) });
    assert.ok(res.ok, `import -> ${res.status} ${await res.text()}`);
    const local = await h.api('/sweeps', SWEEP);
    assert.equal(local.status, 201, JSON.stringify(local.json));
    const done = await completeAll(h.url, (scene) => (scene.S < 0.01
      ? { class: 'c', confidence: 0.9, runner_up: 'f', n_reflections: 0, band_speed_ratio: null }
      : { class: 'a', confidence: 0.8, runner_up: 'b', n_reflections: 1, band_speed_ratio: 1.7 }));
    assert.equal(done, 6);
    const queued = await h.api('/sweeps', { ...SWEEP, name: 'phone width test, queued', phi: 0.5 });
    assert.equal(queued.status, 201, JSON.stringify(queued.json));
    const adaptive = await h.api('/sweeps', { name: 'phone width test, adaptive', phi: 0.5, numerics: SWEEP.numerics, adaptive: ADAPTIVE });
    assert.equal(adaptive.status, 201, JSON.stringify(adaptive.json));
    const localRun = (await h.api(`/jobs?sweep=${local.json.id}&state=succeeded&limit=1`)).json.jobs[0].id;
    const imported = (await h.api('/sweeps')).json.sweeps.find((s) => s.imported);
    const importedRun = (await h.api(`/jobs?sweep=${imported.id}&limit=1`)).json.jobs[0].id;

    const page = await h.browser({ width: 390, height: 844 });
    const pages = [
      ['map', '#/map', () => page.waitForSelector('#map-plot canvas')],
      ['run-local', `#/run/${localRun}`, () => page.waitForSelector('#class-box .class-main, #class-box .features-box')],
      ['run-imported', `#/run/${importedRun}`, () => page.waitForSelector('#run-import:not([hidden])')],
      ['runs', '#/runs', () => page.waitForSelector('table.rt tbody tr')],
      ['runs-columns', '#/runs', async () => { // the choice of columns open
        await page.waitForSelector('table.rt tbody tr');
        await page.locator('#rt-cols > summary').click();
        await page.locator('#rt-cols-list input[data-col="coherence"]').waitFor();
      }],
      ['compare', `#/compare?ids=${localRun},${importedRun}`, () => page.locator('#cmp-table').waitFor()],
      ['plots', '#/plots', () => page.waitForSelector('#pl-plot canvas')],
      ['bands', '#/bands', () => page.waitForTimeout(300)],
      ['sweeps', '#/sweeps', async () => {
        await page.locator(`tr[data-sweep="${queued.json.id}"]`).waitFor();
        await page.locator(`tr[data-sweep="${local.json.id}"] .progress`).waitFor();
        for (const d of await page.locator('details.advanced').all()) await d.evaluate((e) => { e.open = true; });
      }],
      ['labels', '#/labels', () => page.locator('table.audit').waitFor()],
      ['plan', `#/plan?sweep=${adaptive.json.id}`, () => page.locator('#pn-body table.pn-levels').waitFor()],
    ];
    const failures = [];
    for (const [name, hash, ready] of pages) {
      await page.goto(`${h.url}/${hash}`);
      await ready();
      await settle(page);
      await shot(page, `phone-${name}-390`);
      try { await fits(page, name); await navReachable(page, name); } catch (e) { failures.push(e.message); }
    }
    assert.deepEqual(failures, []);

    // The sweeps page on a desktop keeps its two columns and its whole table.
    await page.setViewportSize({ width: 1440, height: 900 });
    await page.goto(`${h.url}/#/sweeps`);
    await page.locator(`tr[data-sweep="${queued.json.id}"]`).waitFor();
    await settle(page);
    await shot(page, 'phone-sweeps-1440');
    await fits(page, 'sweeps at 1440');
    await page.goto(`${h.url}/#/labels`);
    await page.locator('table.audit').waitFor();
    await settle(page);
    await shot(page, 'phone-labels-1440');
    await fits(page, 'labels at 1440');
    assert.deepEqual(h.pageErrors, []);
  } finally {
    await h.close();
  }
});
