// The sweeps page's adaptive mode in real headless Chromium against a real compaction-server and
// compaction-worker: the form switches between grid and adaptive, counts the initial grid against
// the budget, refuses what an adaptive sweep cannot take next to the field (its own rules and the
// server's), submits the adaptive body, and the list shows the sweep growing within its budget
// until it is done. Screenshots of the form in both modes and of the list go to
// $BROWSER_ARTIFACTS_DIR.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { Harness, artifactsDir, waitFor } from './lib/harness.mjs';

async function shot(page, name) {
  await page.evaluate(() => window.scrollTo(0, 0)); // the sticky header stays at the top
  const path = join(artifactsDir(), `${name}.png`);
  await page.screenshot({ path, fullPage: true });
  console.log(`# screenshot ${path}`);
}

async function fillForm(page, v) {
  for (const [id, value] of Object.entries(v)) {
    const el = page.locator(`#f-${id}`);
    if ((await el.evaluate((e) => e.tagName)) === 'SELECT') await el.selectOption(value);
    else await el.fill(value);
  }
}

const text = (page, id) => page.locator(`#${id}`).innerText();

// The box of tests/e2e/adaptive_sweep_test.py: S from 0.02 to 0.1 and R from 1e-4 to 1e-1 cross
// several classes even in tiny runs (pseudo-1D, 5 cells per unit cell, to eps = 0.04).
const BOX = { 's-min': '0.02', 's-max': '0.1', 's-n': '2', 'r-min': '1e-4', 'r-max': '1e-1', 'r-n': '3', phi: '0.4', res: '0.1', budget: '16', 'in-flight': '3' };
const TINY = { preset: 'fast', cpu: '5', 'eps-end': '0.04' };

test('an adaptive sweep submitted through the form grows within its budget, which the list shows', { timeout: 280000 }, async () => {
  const h = new Harness('adaptive');
  try {
    await h.startServer();
    h.startWorker('w1');
    const page = await h.browser();
    await page.goto(`${h.url}/#/sweeps`);
    await page.locator('#f-preset option[value="fast"]').waitFor({ state: 'attached' }); // presets loaded
    await waitFor(async () => /25\s*jobs\s*=\s*5 S × 5 R × 1 φ/.test(await text(page, 'job-count')), { what: 'the grid count' });
    assert.equal(await page.locator('#f-budget').isVisible(), false, 'no budget in grid mode');
    await shot(page, '10-sweep-form-grid');

    // --- Adaptive mode: the spacing goes, the refinement fields come, the count is the initial grid's.
    await page.locator('#f-mode-adaptive').check();
    await waitFor(async () => /25\s*jobs to start, at most 200\s*initial grid 5 S × 5 R/.test(await text(page, 'job-count')), { what: 'the adaptive count' });
    assert.equal(await page.locator('#f-s-scale').isVisible(), false, 'no spacing in adaptive mode');
    for (const id of ['res', 'budget', 'in-flight']) assert.equal(await page.locator(`#f-${id}`).isVisible(), true, `${id} shown`);
    // Empty fields take the server's defaults (GET /limits, adaptive), shown as their placeholders.
    assert.equal(await page.locator('#f-res').inputValue(), '');
    assert.equal(await page.locator('#f-res').getAttribute('placeholder'), '0.125');
    assert.equal(await page.locator('#f-budget').getAttribute('placeholder'), '200');
    assert.equal(await page.locator('label[for="f-s-n"]').innerText(), 'initial points');
    await shot(page, '11-sweep-form-adaptive');

    // --- Refused next to the field by the form: a list of phi, one initial point, a budget below the grid.
    await fillForm(page, { name: 'adaptive browser', phi: '0.3, 0.4', 's-n': '1' });
    await page.locator('#submit-sweep').click();
    await waitFor(async () => /one φ/.test(await text(page, 'err-phi')) && /≥ 2/.test(await text(page, 'err-s-n')), { what: 'the phi and initial points errors' });
    assert.match(await text(page, 'form-message'), /fix the fields/);
    await fillForm(page, { phi: '0.4', 's-n': '2', 'r-n': '3', budget: '5' });
    await waitFor(async () => /initial grid's 6 runs/.test(await text(page, 'err-budget')), { what: 'the budget error' });
    assert.equal(await page.locator('#f-budget').getAttribute('aria-invalid'), 'true');
    await shot(page, '12-sweep-form-adaptive-invalid');
    assert.equal((await h.api('/sweeps')).json.total, 0, 'an invalid form must not create a sweep');

    // --- Refused by the server (a resolution finer than 1/64 decade): shown at the resolution field.
    await page.locator('details.advanced summary').first().click();
    await fillForm(page, { ...BOX, ...TINY, res: '0.001' });
    assert.equal(await page.locator('.f.invalid').count(), 0, 'the form itself lets it through');
    await page.locator('#submit-sweep').click();
    await waitFor(async () => /1\/64 decade/.test(await text(page, 'err-res')), { what: 'the server\'s resolution error at the field' });
    assert.match(await text(page, 'form-message'), /refused the sweep \(422\)/);
    assert.equal((await h.api('/sweeps')).json.total, 0, 'a refused sweep is not created');

    // --- A valid adaptive sweep: 2 x 3 to start, at most 16 runs.
    await fillForm(page, { res: BOX.res });
    await waitFor(async () => /6\s*jobs to start, at most 16/.test(await text(page, 'job-count')), { what: 'the count of the valid sweep' });
    await page.locator('#submit-sweep').click();
    await waitFor(async () => /Sweep #1 created with 6 jobs/.test(await text(page, 'form-message')), { what: 'the created message' });
    const created = (await h.api('/sweeps/1')).json;
    assert.deepEqual(created.request.adaptive, {
      S: { min: 0.02, max: 0.1 }, R: { min: 1e-4, max: 1e-1 }, initial: { S: 2, R: 3 }, resolution_decades: 0.1, budget: 16, in_flight: 3,
    });
    assert.equal(created.request.phi, 0.4);
    assert.deepEqual(created.request.numerics, { preset: 'fast', cells_per_unit: 5, eps_end: 0.04 });

    // --- The list: the total only grows, never past the budget, until the sweep is done.
    const row = page.locator('tr[data-sweep="1"]');
    const totals = [];
    const final = await waitFor(async () => {
      const s = (await h.api('/sweeps/1')).json;
      totals.push(s.counts.total);
      assert.ok(s.counts.total <= 16, `never beyond the budget: ${JSON.stringify(s.counts)}`);
      return s.state === 'done' ? s : null;
    }, { timeoutMs: 240000, intervalMs: 500, what: 'the adaptive sweep to finish' });
    assert.deepEqual(totals, [...totals].sort((a, b) => a - b), 'the total only grows');
    const total = final.counts.total;
    assert.ok(total >= 6, `the initial grid at least: ${total}`);
    await waitFor(async () => new RegExp(`^done · ${final.counts.succeeded} done.* · ${total} of at most 16 runs$`).test((await row.locator('td').nth(2).innerText()).trim()), { what: `the list row with ${total} of at most 16 runs` });
    assert.equal(await row.locator('.budget').getAttribute('data-budget'), '16');
    assert.match(await row.locator('td').nth(1).innerText(), /adaptive from 2 S × 3 R/);
    const jobs = (await h.api('/sweeps/1/export?format=json')).json.jobs;
    assert.equal(jobs.length, total, 'the export lists every job');
    const initialLabels = new Set(jobs.slice(0, 6).map((j) => j.result?.class ?? null));
    if (initialLabels.size > 1) assert.ok(total > 6, `the initial labels differ (${[...initialLabels]}), so the sweep grew`);
    console.log(`# adaptive sweep: ${total} runs, initial labels ${[...initialLabels]}`);
    await shot(page, '13-sweeps-adaptive');

    // --- Back to grid mode: the same S and R fields count a grid again.
    await page.locator('#f-mode-grid').check();
    await waitFor(async () => /6\s*jobs\s*=\s*2 S × 3 R × 1 φ/.test(await text(page, 'job-count')), { what: 'the grid count again' });
    assert.equal(await page.locator('#f-s-scale').isVisible(), true);
    assert.equal(await page.locator('#f-budget').isVisible(), false);

    assert.deepEqual(h.pageErrors.filter((e) => !/422/.test(e)), [], 'no errors in the page besides the refused request');
  } catch (e) {
    for (const [k, v] of Object.entries(h.logs)) if (v) console.log(`# ${k} log tail:\n${v.slice(-3000)}`);
    throw e;
  } finally {
    await h.close();
  }
});
