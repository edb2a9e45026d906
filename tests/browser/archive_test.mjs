// A sweep's archive from the dashboard to another server (issue 49, item 7), in real headless
// Chromium against two real compaction-servers and a real compaction-worker: the sweeps list's
// "Archive" states the size of both forms before download (each equal to the bytes a GET then
// gives), the archive with the runs' files imported into an empty second server through
// POST /imports keeps every file byte for byte, and the imported run's page there draws the same
// space-time map (its colour scale and pixels) and stress plot as the source's page, says where it
// was computed and shows no "files not on this server" note. Screenshots to
// $BROWSER_ARTIFACTS_DIR.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { Harness, artifactsDir, waitFor } from './lib/harness.mjs';

// One tiny run (about 0.1 s): pseudo-1D, 5 cells per unit cell, to eps = 0.04, with snapshots,
// which the archive leaves out.
const SWEEP = { name: 'archived', S: 0.05, R: 3e-3, phi: 0.4, numerics: { preset: 'fast', cells_per_unit: 5, eps_end: 0.04, snapshot_eps: [0.02] } };
const TOKEN = 'archive-test-submit';

async function shot(page, name) {
  const path = join(artifactsDir(), `archive-${name}.png`);
  await page.screenshot({ path, fullPage: true });
  console.log(`# screenshot ${path}`);
}

// What the run page drew: the space-time canvas's size, frames and a digest of its pixels, its
// colour bar's ends, and the stress plot's series (their names and path data).
async function runPageFigures(page, url, id) {
  await page.goto(`${url}/#/run/${id}`);
  const st = page.locator('#st-canvas');
  await st.waitFor({ timeout: 15000 });
  await waitFor(() => st.evaluate((c) => Number(c.dataset.frames) > 0), { what: `run ${id}'s space-time map` });
  // The plot's series are drawn beside its SVG (the axes), in the same figure.
  await waitFor(() => page.evaluate(() => document.querySelector('#stress-svg')?.parentElement.querySelectorAll('path[data-series]').length === 2),
    { what: `run ${id}'s two stress series` });
  return page.evaluate(() => {
    const c = document.querySelector('#st-canvas');
    const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let sum = 0;
    let lit = 0;
    for (let i = 0; i < d.length; i += 4) {
      sum = (sum * 31 + d[i] * 3 + d[i + 1] * 5 + d[i + 2] * 7) % 1000000007;
      if (d[i] + d[i + 1] + d[i + 2] > 60) lit++;
    }
    const series = [...document.querySelector('#stress-svg').parentElement.querySelectorAll('path[data-series]')].map((p) => [p.dataset.series, p.getAttribute('d')]);
    return { w: c.width, h: c.height, frames: Number(c.dataset.frames), rows: Number(c.dataset.rows), digest: sum, lit, series };
  });
}

test('the archive states its size, carries the run files, and the imported run draws the same figures', { timeout: 240000 }, async () => {
  const source = new Harness('archive-source');
  const target = new Harness('archive-target');
  try {
    await source.startServer();
    source.startWorker('w1');
    const made = await source.api('/sweeps', SWEEP);
    assert.equal(made.status, 201, JSON.stringify(made.json));
    const sweep = made.json.id;
    await waitFor(async () => (await source.api(`/sweeps/${sweep}`)).json.counts.succeeded === 1, { timeoutMs: 120000, what: 'the run to finish' });
    const job = (await source.api(`/jobs?sweep=${sweep}`)).json.jobs[0].id;

    // --- The sweeps list states both forms' sizes, each the length of what its link downloads.
    const page = await source.browser();
    await page.goto(`${source.url}/#/sweeps`);
    const archive = page.locator(`details.archive[data-id="${sweep}"]`);
    await archive.locator('summary').click();
    const sized = {};
    for (const form of ['run_page', 'none']) {
      const size = archive.locator(`[data-size="${form}"]`);
      await waitFor(async () => !/sizing/.test(await size.innerText()), { what: `the size of the ${form} archive` });
      const href = await archive.locator(`a[href*="artifacts=${form}"]`).getAttribute('href');
      const body = Buffer.from(await (await fetch(`${source.url}${href}`)).arrayBuffer());
      sized[form] = { text: await size.innerText(), bytes: body };
      const n = body.length;
      const expected = n < 1024 ? `${n} B` : n < 1024 * 1024 ? `${(n / 1024).toFixed(1)} KiB` : `${(n / 1024 / 1024).toFixed(1)} MiB`;
      assert.equal(sized[form].text, expected, `the ${form} archive: the page says ${sized[form].text}, its GET gives ${n} bytes`);
    }
    assert.ok(sized.run_page.bytes.length > 5 * sized.none.bytes.length,
      `with files ${sized.run_page.bytes.length} B, without ${sized.none.bytes.length} B`);
    // The list is redrawn at each poll: the open archive and its sizes stay.
    await page.waitForTimeout(3500);
    assert.equal(await archive.evaluate((d) => d.open), true);
    assert.equal(await archive.locator('[data-size="run_page"]').innerText(), sized.run_page.text);
    await shot(page, 'sweeps-list');
    const here = await runPageFigures(page, source.url, job);
    assert.ok(here.frames === 20 && here.lit > 200, `source run page: ${JSON.stringify({ ...here, series: here.series.length })}`);

    // --- Imported into an empty server, the run keeps its files and draws the same figures.
    await target.startServer(['--submit-token', TOKEN]);
    const imported = await fetch(`${target.url}/api/v1/imports`, {
      method: 'POST', body: sized.run_page.bytes, headers: { 'Content-Type': 'application/json', Authorization: `Bearer ${TOKEN}` },
    });
    assert.equal(imported.status, 200, await imported.text());
    const copy = (await target.api('/jobs?limit=10')).json.jobs;
    assert.equal(copy.length, 1);
    const names = (list) => list.artifacts.map((a) => a.name).sort();
    const sourceFiles = (await source.api(`/jobs/${job}/artifacts`)).json;
    const targetFiles = (await target.api(`/jobs/${copy[0].id}/artifacts`)).json;
    const carried = names(sourceFiles).filter((n) => !/^snapshot_.*\.npy$/.test(n));
    assert.deepEqual(names(targetFiles), carried, 'every file but the snapshots');
    for (const name of carried) {
      const get = async (url, id) => Buffer.from(await (await fetch(`${url}/api/v1/jobs/${id}/artifacts/${encodeURIComponent(name)}`)).arrayBuffer());
      assert.ok((await get(source.url, job)).equals(await get(target.url, copy[0].id)), `${name} byte for byte`);
    }

    const there = await runPageFigures(page, target.url, copy[0].id);
    assert.deepEqual(there, here, 'the imported run draws the source run\'s space-time map and stresses');
    await page.waitForSelector('#run-import:not([hidden]) #run-source-server');
    const note = await page.locator('#run-import').innerText();
    assert.match(note, new RegExp(`127\\.0\\.0\\.1:${new URL(source.url).port}`), note);
    assert.doesNotMatch(await page.locator('#page').innerText(), /not on this server/);
    await shot(page, 'imported-run');
    assert.deepEqual(source.pageErrors, []);
  } finally {
    await source.close();
    await target.close();
  }
});
