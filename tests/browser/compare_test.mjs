// The compare page (#/compare?ids=…, web/js/pages/compare.js) on a real compaction-server: three
// runs completed through the worker API (lib/labelled.mjs, no simulation) with a frames.csv and a
// spacetime.npy each (different rates, one with a spike its clipping cuts), and one run of the
// committed studies/phase_map/results/sweep-2.export.json imported without files (POST /imports,
// as scripts/main.sh does). Checked: the stress plot has one curve per run with frames; the one
// colour bar's extent is the lowest value and the highest clipping top of the maps, computed here
// from the artifacts as downloaded; every cell of the features table holds the API's value; the
// imported run says it has no files and keeps its column; the Runs page's checkboxes lead to
// #/compare?ids= in the order ticked, and a run page adds its run; a replicate's run page (a
// point of three replicates) compares its point's runs; removing a run rewrites the
// address, and keeps the ids past the six compared; an unknown id, an entry that is not an id and a single run say so; at 390 px nothing
// scrolls sideways; no JavaScript error. Screenshots at 1440 x 900 and 390 x 844.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { Harness, REPO, WEB_DIR, artifactsDir, waitFor } from './lib/harness.mjs';
import { completeAll, npyFloat32 } from './lib/labelled.mjs';

const GLOSSARY = JSON.parse(readFileSync(join(WEB_DIR, 'data', 'feature-glossary.json'), 'utf8'));
const EXPORT = join(REPO, 'studies', 'phase_map', 'results', 'sweep-2.export.json');

// Three points (S = 1e-3, 1e-2, 1e-1): nothing runs, the results are posted.
const SWEEP = {
  name: 'compare test', S: { min: 1e-3, max: 1e-1, n: 3, scale: 'log' }, R: 1e-3, phi: 0.4,
  numerics: { preset: 'fast', cells_per_unit: 5, eps_end: 0.1 },
};

const NF = 50, NR = 20; // frames (ε = 0.002 … 0.1) × rows of each space-time map

// frames.csv whose plateau sits at `level` q_y.
const frames = (level) => 'eps,sigma_top_over_qy,sigma_bottom_over_qy\n' + Array.from({ length: NF }, (_, i) => {
  const eps = (i + 1) * 0.002;
  const bottom = eps < 0.01 ? 100 * level * eps : level;
  return `${eps.toFixed(3)},${(bottom * (1 + 3 * eps)).toFixed(4)},${bottom.toFixed(4)}`;
}).join('\n') + '\n';

// A space-time map: a band of peak `peak` running down from the top over a floor `floor`, and
// optionally one spike (a single cell far above the rest, which the 99.5th percentile cuts).
function spacetime(peak, floor, spike = 0) {
  const v = new Float32Array(NF * NR);
  for (let f = 0; f < NF; f++) {
    for (let r = 0; r < NR; r++) {
      const at = (NR - 1) * (1 - f / (NF - 1));
      v[f * NR + r] = floor + peak * Math.exp(-((r - at) ** 2) / 4);
    }
  }
  if (spike) v[10 * NR + 3] = spike;
  return npyFloat32([NF, NR], v);
}

const FEATURES = {
  n_fronts: 1, onset_origins: ['top'], top_front: true, two_sided: false, n_reflections: 0,
  band_speed_transit: 1.2, band_speed_transit_error: 0.1, coherence: 0.52, peak_jump: 4.8, stress_ratio: 1.01,
  scores: { a: 0.7, b: 0.2, c: 0, d: 0.1, e: 0, f: 0 },
};

// The runs by S: their class, features, plateau and map.
const VERDICTS = [
  { S: 1e-3, v: { class: 'd', confidence: 0.9, runner_up: 'a', n_reflections: 0, band_speed_ratio: -0.4, features: { ...FEATURES, coherence: 0.11, band_speed_error: 0.2 }, frames: frames(0.5), files: [{ name: 'spacetime.npy', value: spacetime(2, 0.02) }] } },
  { S: 1e-2, v: { class: 'a', confidence: 0.8, runner_up: 'b', n_reflections: 0, band_speed_ratio: 1.7, features: { ...FEATURES, peak_jump: 9.5 }, frames: frames(3), files: [{ name: 'spacetime.npy', value: spacetime(30, 0.5, 1e5) }] } },
  { S: 1e-1, v: { class: 'b', confidence: 0.6, runner_up: 'a', n_reflections: 1, band_speed_ratio: 2.4, features: { ...FEATURES, n_reflections: 1 }, frames: frames(20), files: [{ name: 'spacetime.npy', value: spacetime(300, 1) }] } },
];

async function shot(page, name) {
  const path = join(artifactsDir(), `${name}.png`);
  await page.screenshot({ path, fullPage: true });
  console.log(`screenshot: ${path}`);
}

async function fits(page, what) {
  const w = await page.evaluate(() => ({ scroll: document.documentElement.scrollWidth, window: window.innerWidth }));
  assert.ok(w.scroll <= w.window, `${what}: the page scrolls sideways: ${JSON.stringify(w)}`);
}

// The map's colour quantity of a downloaded spacetime.npy as the page defines it: log10(1 + rate)
// in float32, its lowest value and its 99.5th percentile (the run page's clipping top). The file
// is read here, not with web/js/npy.js.
async function levels(url, id) {
  const buf = Buffer.from(await (await fetch(`${url}/api/v1/jobs/${id}/artifacts/spacetime.npy`)).arrayBuffer());
  assert.equal(buf.subarray(1, 6).toString('latin1'), 'NUMPY');
  const start = 10 + buf.readUInt16LE(8);
  const raw = new Float32Array(buf.buffer.slice(buf.byteOffset + start, buf.byteOffset + buf.length));
  assert.equal(raw.length, NF * NR);
  const vals = Float32Array.from(raw, (x) => Math.log10(1 + Math.max(0, x))).sort();
  return { lo: vals[0], top: vals[Math.floor(0.995 * (vals.length - 1))], max: vals[vals.length - 1] };
}

// Runs action (a navigation) and waits until a compare page mounted after it has drawn or said
// why it could not: the page shown before is marked, so that it is not taken for the new one.
async function freshCompare(page, action, what) {
  await page.evaluate(() => document.querySelector('#page .page-host')?.setAttribute('data-old', '1'));
  await action();
  await waitFor(() => page.evaluate(() => {
    const host = document.querySelector('#page .page-host');
    const sub = host && !host.dataset.old && host.querySelector('#cmp-sub');
    return Boolean(sub) && !/loading…/.test(sub.textContent);
  }), { what });
}

const openCompare = (page, url, ids) => freshCompare(page, () => page.goto(`${url}/#/compare?ids=${ids}`), `the comparison of ${ids}`);

test('compare: one colour scale, one stress plot, one features table, and the ways in and out', { timeout: 240000 }, async () => {
  const h = new Harness('compare');
  try {
    await h.startServer();
    const imp = await fetch(`${h.url}/api/v1/imports`, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: readFileSync(EXPORT) });
    assert.ok(imp.ok, `import -> ${imp.status} ${await imp.text()}`);
    const created = await h.api('/sweeps', SWEEP);
    assert.equal(created.status, 201, JSON.stringify(created.json));
    // A point of three replicates (its run page's "compare these runs").
    const replicated = await h.api('/sweeps', { name: 'compare test, replicated', points: [{ S: 0.05, R: 1e-3, phi: 0.4 }], numerics: SWEEP.numerics, replicates: { n: 3, perturbation: 0.01 } });
    assert.equal(replicated.status, 201, JSON.stringify(replicated.json));
    const other = { class: 'b', confidence: 0.7, runner_up: 'a', n_reflections: 1, band_speed_ratio: 2, frames: frames(5) };
    assert.equal(await completeAll(h.url, (scene) => VERDICTS.find((x) => Math.abs(Math.log10(scene.S / x.S)) < 0.01)?.v ?? other), 6);
    const local = (await h.api(`/jobs?sweep=${created.json.id}&limit=10`)).json.jobs.sort((a, b) => a.S - b.S);
    assert.equal(local.length, 3);
    const [erratic, banded, reflecting] = local.map((j) => j.id);
    const importedSweep = (await h.api('/sweeps')).json.sweeps.find((s) => s.imported);
    const imported = (await h.api(`/jobs?sweep=${importedSweep.id}&state=succeeded&limit=1`)).json.jobs[0].id;
    const ids = [erratic, banded, reflecting, imported];
    const jobs = new Map();
    for (const id of ids) jobs.set(id, (await h.api(`/jobs/${id}`)).json);
    assert.equal((await (await fetch(`${h.url}/api/v1/jobs/${imported}/artifacts`)).json()).artifacts.length, 0, 'the import carried no files');

    const page = await h.browser({ width: 1440, height: 900 });
    await openCompare(page, h.url, ids.join(','));
    await page.locator('#cmp-table').waitFor();

    // --- One curve per run with frames (the imported run has none), named in the legend.
    const series = await page.locator('#cmp-stress path[data-series]').evaluateAll((els) => els.map((e) => Number(e.dataset.series)));
    assert.deepEqual(series, [erratic, banded, reflecting]);
    assert.equal(await page.locator('#cmp-stress-svg').getAttribute('data-scale'), 'log');
    const legend = await page.locator('#cmp-stress-legend li').evaluateAll((els) => els.map((e) => ({ run: Number(e.dataset.run), text: e.innerText })));
    assert.deepEqual(legend.map((l) => l.run), ids);
    assert.match(legend[0].text, /run \d+\s+d · erratic\s+S = 1\.00×10-3, R = 1\.00×10-3, φ = 0\.4 · 5 cells\/unit/);
    assert.match(legend[1].text, /a · non-reflecting band/);
    assert.match(legend[3].text, /imported without its files/);
    await page.locator('#cmp-stress button[data-scale="bottom"]').click();
    assert.equal(await page.locator('#cmp-stress path[data-series]').count(), 3);
    await page.locator('#cmp-stress button[data-scale="linear"]').click();
    assert.equal(await page.locator('#cmp-stress-svg').getAttribute('data-scale'), 'linear');

    // --- One colour bar: from the lowest value of the three maps to the highest of their
    // clipping tops (the spike of the banded run, 10^5, is cut as on its own page).
    const lv = await Promise.all([erratic, banded, reflecting].map((id) => levels(h.url, id)));
    const lo = Math.min(...lv.map((l) => l.lo)), hi = Math.max(...lv.map((l) => l.top));
    assert.ok(lv[1].max > hi, 'the spike lies above the common top');
    assert.equal(await page.locator('#cmp-colorbar').count(), 1);
    assert.equal(await page.locator('#cmp-maps .colorbar').count(), 0, 'no map has a colour bar of its own');
    const bar = await page.locator('#cmp-colorbar').evaluate((e) => ({ lo: Number(e.dataset.lo), hi: Number(e.dataset.hi) }));
    assert.ok(Math.abs(bar.lo - lo) <= 1e-6 * Math.max(1, Math.abs(lo)), `bar from ${bar.lo}, the maps' lowest ${lo}`);
    assert.ok(Math.abs(bar.hi - hi) <= 1e-6 * hi, `bar to ${bar.hi}, the maps' highest top ${hi}`);
    assert.match(await page.locator('#cmp-scale').innerText(), /One colour scale for the 3 maps/);
    for (const id of [erratic, banded, reflecting]) assert.equal(await page.locator(`#cmp-st-${id}`).count(), 1, `map of run ${id}`);
    assert.match(await page.locator(`.cmp-no-map[data-run="${imported}"]`).innerText(), /no space-time map: imported without its files/);
    assert.equal(await page.locator(`.cmp-map[data-run="${imported}"]`).count(), 0);

    // --- The features table: a column per run (the imported one too), each cell the API's value.
    const heads = await page.locator('#cmp-table thead th[data-run]').evaluateAll((els) => els.map((e) => Number(e.dataset.run)));
    assert.deepEqual(heads, ids);
    const cells = await page.locator('#cmp-table td[data-run]').evaluateAll((els) => els.map((e) => ({
      run: Number(e.dataset.run), feature: e.closest('tr').dataset.feature, param: e.closest('tr').dataset.param,
      value: e.dataset.value, text: e.innerText, differs: e.closest('tr').classList.contains('differs'),
    })));
    let checked = 0;
    for (const id of ids) {
      const f = jobs.get(id).result.features;
      for (const [key, want] of Object.entries(f)) {
        if (GLOSSARY.features[key]?.error_of) continue; // shown as the ± of its value
        const cell = cells.find((c) => c.run === id && c.feature === key);
        assert.ok(cell, `run ${id}: no cell of ${key}`);
        assert.deepEqual(JSON.parse(cell.value), want, `run ${id}, ${key}`);
        if (typeof want === 'number' && Math.abs(want) >= 0.01 && Math.abs(want) < 1e4 && !/no band/.test(cell.text)) {
          assert.ok(cell.text.startsWith(String(Number(want.toPrecision(3)))), `run ${id}, ${key}: "${cell.text}" for ${want}`);
        }
        checked++;
      }
    }
    assert.ok(checked > 30, `${checked} cells checked`);
    // The groups are the glossary's, in its order; band speeds only where a run has a band.
    const groups = await page.locator('#cmp-table tbody[data-group]').evaluateAll((els) => els.map((e) => e.dataset.group));
    assert.deepEqual(groups, GLOSSARY.groups.map((g) => g.id).filter((g) => groups.includes(g)).concat(groups.includes('other') ? ['other'] : []));
    const transit = (id) => cells.find((c) => c.run === id && c.feature === 'band_speed_transit').text;
    assert.match(transit(erratic), /no band/);
    assert.match(transit(banded), /^1\.2 ± 0\.1/);
    // Parameters on top; a row whose values differ is marked, one whose values agree is not.
    const param = (key, id) => cells.find((c) => c.param === key && c.run === id);
    assert.match(param('S', erratic).text, /1\.000×10-3|1×10-3/);
    assert.equal(param('cells_per_unit', banded).text, '5');
    assert.ok(param('class', erratic).differs && param('S', erratic).differs);
    assert.ok(cells.find((c) => c.feature === 'peak_jump').differs);
    await page.locator('#cmp-diff-only').check();
    assert.equal(await page.locator('#cmp-table tr[data-param="phi"]').isVisible(), false, 'φ is the same for all four runs');
    await page.locator('#cmp-diff-only').uncheck();
    // Each run links to its page.
    assert.equal(await page.locator(`#cmp-runs li[data-run="${banded}"] a.cmp-run-link`).getAttribute('href'), `#/run/${banded}`);
    await shot(page, 'compare-1440');

    // --- Removing a run rewrites the address and compares the others.
    await freshCompare(page, () => page.locator(`#cmp-runs li[data-run="${reflecting}"] a.cmp-remove`).click(), 'the comparison without the removed run');
    assert.equal(await page.evaluate(() => location.hash), `#/compare?ids=${erratic},${banded},${imported}`);
    assert.deepEqual(await page.locator('#cmp-table thead th[data-run]').evaluateAll((els) => els.map((e) => Number(e.dataset.run))), [erratic, banded, imported]);
    assert.deepEqual(await page.locator('#cmp-stress path[data-series]').evaluateAll((els) => els.map((e) => Number(e.dataset.series))), [erratic, banded]);

    // --- A phone: nothing scrolls sideways (the table scrolls in its own box).
    await page.setViewportSize({ width: 390, height: 844 });
    await openCompare(page, h.url, ids.join(','));
    await page.locator('#cmp-table').waitFor();
    await page.waitForTimeout(300);
    await fits(page, 'compare at 390');
    await shot(page, 'compare-390');
    await page.setViewportSize({ width: 1440, height: 900 });

    // --- The Runs page: tick two runs, "Compare selected" opens them in the order ticked.
    await page.goto(`${h.url}/#/runs?sweep=${created.json.id}`);
    await page.locator(`#rt-table tr[data-id="${reflecting}"] input.rt-pick`).waitFor();
    assert.match(await page.locator('#rt-compare').innerText(), /tick up to 6 runs/);
    await page.locator(`#rt-table tr[data-id="${reflecting}"] input.rt-pick`).check();
    assert.match(await page.locator('#rt-compare').innerText(), /one more/);
    await page.locator(`#rt-table tr[data-id="${erratic}"] input.rt-pick`).check();
    assert.equal(await page.locator('#rt-compare-link').getAttribute('href'), `#/compare?ids=${reflecting},${erratic}`);
    await freshCompare(page, () => page.locator('#rt-compare-link').click(), 'the comparison of the ticked runs');
    assert.equal(await page.evaluate(() => location.hash), `#/compare?ids=${reflecting},${erratic}`);
    assert.deepEqual(await page.locator('#cmp-table thead th[data-run]').evaluateAll((els) => els.map((e) => Number(e.dataset.run))), [reflecting, erratic]);
    // A run page adds its run to the picks.
    await page.goto(`${h.url}/#/run/${banded}`);
    await page.locator('#run-pick').waitFor();
    assert.match(await page.locator('#run-compare-link').innerText(), /compare the 2 picked runs/);
    await page.locator('#run-pick').click();
    assert.equal(await page.locator('#run-compare-link').getAttribute('href'), `#/compare?ids=${reflecting},${erratic},${banded}`);
    // The picks stay ticked on the Runs page; "clear" unticks them.
    await page.goto(`${h.url}/#/runs?sweep=${created.json.id}`);
    await page.locator(`#rt-table tr[data-id="${banded}"] input.rt-pick:checked`).waitFor();
    await page.locator('#rt-compare-clear').click();
    assert.equal(await page.locator('#rt-table input.rt-pick:checked').count(), 0);

    // --- A replicate's run page compares its point's runs.
    const reps = (await h.api(`/jobs?sweep=${replicated.json.id}&limit=10`)).json.jobs.map((j) => j.id);
    assert.equal(reps.length, 3);
    const repJob = (await h.api(`/jobs/${reps[0]}`)).json;
    await page.goto(`${h.url}/#/run/${reps[0]}`);
    await page.locator('#run-compare-replicates').waitFor();
    assert.equal(await page.locator('#run-compare-replicates').getAttribute('href'), `#/compare?ids=${[reps[0], ...repJob.replicates].join(',')}`);
    await freshCompare(page, () => page.locator('#run-compare-replicates').click(), 'the comparison of the replicates');
    assert.deepEqual((await page.locator('#cmp-table thead th[data-run]').evaluateAll((els) => els.map((e) => Number(e.dataset.run)))).sort((a, b) => a - b), reps.sort((a, b) => a - b));
    assert.equal(await page.locator('#cmp-stress path[data-series]').count(), 3);

    // --- Seven runs: the seventh is left out, and removing one keeps it in the address.
    const seven = [...ids, ...reps];
    await openCompare(page, h.url, seven.join(','));
    await page.locator('#cmp-table').waitFor();
    assert.match(await page.locator('#cmp-notes').innerText(), new RegExp(`run ${seven[6]} left out`));
    await freshCompare(page, () => page.locator(`#cmp-runs li[data-run="${erratic}"] a.cmp-remove`).click(), 'the comparison of seven without one');
    assert.equal(await page.evaluate(() => location.hash), `#/compare?ids=${seven.slice(1).join(',')}`);
    assert.equal(await page.locator('#cmp-notes').innerText(), '');

    // --- Unknown ids, entries that are no ids, a single run.
    const before = h.pageErrors.length;
    await openCompare(page, h.url, `${erratic},${banded},999999,abc`);
    await page.locator('#cmp-table').waitFor();
    assert.match(await page.locator('#cmp-notes').innerText(), /There is no run 999999\. Leave it out/);
    assert.match(await page.locator('#cmp-notes').innerText(), /“abc” is not a run id/);
    assert.equal(await page.locator('#cmp-table thead th[data-run]').count(), 2);
    await freshCompare(page, () => page.locator('#cmp-notes [data-missing="999999"] a').click(), 'the comparison without the unknown id');
    assert.equal(await page.evaluate(() => location.hash), `#/compare?ids=${erratic},${banded}`);
    assert.equal(await page.locator('#cmp-notes').innerText(), '');
    await openCompare(page, h.url, `${erratic},999999`);
    assert.match(await page.locator('#cmp-notes').innerText(), /There is no run 999999/);
    assert.match(await page.locator('#cmp-sub').innerText(), /needs two runs or more/);
    assert.equal(await page.locator('#cmp-body').isVisible(), false);
    await openCompare(page, h.url, `${erratic}`);
    assert.match(await page.locator('#cmp-sub').innerText(), new RegExp(`needs two runs or more.*Only run ${erratic} is here`, 's'));
    await openCompare(page, h.url, '');
    assert.match(await page.locator('#cmp-sub').innerText(), /needs two runs or more/);
    // The unknown id's GET /jobs/999999 is a 404 chromium logs as a failed resource: nothing else.
    const late = h.pageErrors.splice(before);
    assert.ok(late.every((e) => /status of 404/.test(e)), JSON.stringify(late));
    assert.deepEqual(h.pageErrors, []);
  } finally {
    await h.close();
  }
});
