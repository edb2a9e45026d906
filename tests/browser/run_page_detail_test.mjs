// The run page's readings (real compaction-server; results posted through the worker API by
// lib/labelled.mjs, no simulation): the plate-stress plot on a log axis shows the plateau near
// 1-10 q_y under a top stress of 12 500 q_y (and switches to linear), band speeds only on a run
// with a band, the features in the glossary's groups with their explanations, no token field on
// a server without tokens (and one at once on a server with them), an imported run (the committed
// studies/phase_map/results/sweep-2.export.json through POST /imports, as scripts/main.sh does)
// with its source shown, no false reason and no negative time, the sweeps list marking the
// imported sweep, and no sideways scrolling at 390 px. Screenshots at 1440 x 900 and 390 x 844.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { Harness, REPO, WEB_DIR, artifactsDir, waitFor } from './lib/harness.mjs';
import { completeAll } from './lib/labelled.mjs';

const GLOSSARY = JSON.parse(readFileSync(join(WEB_DIR, 'data', 'feature-glossary.json'), 'utf8'));
const EXPORT = join(REPO, 'studies', 'phase_map', 'results', 'sweep-2.export.json');

// Two points (S = 1e-3 and 1e-1): nothing runs, the results are posted.
const SWEEP = {
  name: 'run page detail test', S: { min: 1e-3, max: 1e-1, n: 2, scale: 'log' }, R: 1e-3, phi: 0.4,
  numerics: { preset: 'fast', cells_per_unit: 5, eps_end: 0.1 },
};

// frames.csv of an inertial run: the bottom plate on a plateau near 3 q_y from eps = 0.01, the
// top plate the same and then rising to 12 500 q_y (the linear axis shows the plateau as a flat
// line at its foot), and the bottom plate's first frame at 1e-150 q_y (round-off).
const FRAMES = 'eps,sigma_top_over_qy,sigma_bottom_over_qy\n' + Array.from({ length: 50 }, (_, i) => {
  const eps = (i + 1) * 0.002;
  const bottom = eps < 0.01 ? 300 * eps : 3 + 0.5 * Math.sin(i);
  const top = eps < 0.04 ? bottom * 1.1 : 3.3 * 10 ** ((eps - 0.04) / 0.06 * Math.log10(12500 / 3.3));
  // The first frame's bottom stress in round-off, as the elastic precursor's first ripple leaves it.
  return `${eps.toFixed(3)},${top.toFixed(4)},${i ? bottom.toFixed(4) : '1e-150'}`;
}).join('\n') + '\n';

// Features of the kind the classifier writes (every group of the glossary has some).
const FEATURES = {
  n_fronts: 3, n_fronts_onset: 1, onset_origins: ['top'], top_front: true, bottom_front: false, two_sided: false,
  primary_origin: 'top', n_reflections: 0, first_reflection_eps: null, band_turns: 0,
  band_speed_transit: 1.2, band_speed_transit_error: 0.1, band_speed_early: 1.3, band_speed_early_error: 0.2,
  band_speed_lead: 1.4, band_speed_lead_error: 0.2, bottom_speed_ratio: null, nonreflecting_speed: 1.667,
  speed_excess: -0.3, arrival_eps: null, coherence: 0.52, peak_jump: 4.8, stress_ratio: 1.01,
  top_stress_undulation: 0.01, undulation_share: 0.05, stress_drop: 0.02, eps_first_yield: 0.004,
  deflection_before_yield: 0.001, deflection_growth: 0.2, eps_reached: 0.1,
  scores: { a: 0, b: 0, c: 0, d: 0.93, e: 0.01, f: 0 },
};

async function shot(page, name) {
  const path = join(artifactsDir(), `${name}.png`);
  await page.screenshot({ path, fullPage: true });
  console.log(`screenshot: ${path}`);
}

// The page is no wider than its window (no sideways scrolling).
async function fits(page) {
  const w = await page.evaluate(() => ({ scroll: document.documentElement.scrollWidth, window: window.innerWidth }));
  assert.ok(w.scroll <= w.window, `the page scrolls sideways: ${JSON.stringify(w)}`);
}

async function openRun(page, url, id) {
  await page.goto(`${url}/#/run/${id}`);
  await waitFor(async () => !/no files yet/.test(await page.locator('#files-box').innerText()), { what: `run ${id}'s files` });
  await waitFor(async () => !/waiting/.test(await page.locator('#card-spacetime').innerText()), { what: `run ${id}'s figures` });
  await page.waitForSelector('#class-box .class-main, #class-box .features-box');
}

test('the run page: stress plateau, band speeds, grouped features, no token field, an imported run', { timeout: 200000 }, async () => {
  const h = new Harness('run-detail');
  try {
    await h.startServer();
    const created = await h.api('/sweeps', SWEEP);
    assert.equal(created.status, 201, JSON.stringify(created.json));
    // The slow point is erratic (d) with a fitted front speed below zero, the fast one a band.
    const done = await completeAll(h.url, (scene) => (scene.S < 0.01
      ? { class: 'd', confidence: 0.9, runner_up: 'a', n_reflections: 0, band_speed_ratio: -1.132, features: { ...FEATURES, band_speed_error: 0.481 }, frames: FRAMES }
      : { class: 'a', confidence: 0.8, runner_up: 'b', n_reflections: 0, band_speed_ratio: 1.7, features: { ...FEATURES, speed_excess: 0.02, band_speed_error: 0.05 }, frames: FRAMES }));
    assert.equal(done, 2);
    const jobs = (await h.api('/jobs?state=succeeded')).json.jobs;
    const erratic = jobs.find((j) => j.result.class === 'd').id, banded = jobs.find((j) => j.result.class === 'a').id;
    assert.equal((await h.api('/health')).json.tokens.submit, 'open');

    const page = await h.browser({ width: 1440, height: 900 });
    await openRun(page, h.url, erratic);

    // --- Plate stress: a log axis by default, whose ticks 1 and 10 enclose the bottom plate's
    // plateau (3 q_y), at least 50 px apart, and reach 10^4 (the top plate's 12 500 q_y); the
    // round-off value does not stretch the axis (at most 9 labelled ticks).
    const stress = () => page.evaluate(() => {
      const svg = document.querySelector('#stress-svg');
      const ticks = [...svg.querySelectorAll('text.ticklabel[text-anchor="end"]')].map((t) => ({ text: t.textContent, y: Number(t.getAttribute('y')) - 4.5 }));
      const d = document.querySelector('#stress-fig path[data-series="bottom"]').getAttribute('d');
      const ys = [...d.matchAll(/[ML][\d.]+,([\d.]+)/g)].map((m) => Number(m[1]));
      return { scale: svg.dataset.scale, ticks, lastBottomY: ys[ys.length - 1], label: [...svg.querySelectorAll('text.axislabel')].map((t) => t.textContent) };
    });
    const s = await stress();
    assert.equal(s.scale, 'log', JSON.stringify(s));
    const tick = (t) => s.ticks.find((x) => x.text === t);
    assert.ok(tick('1') && tick('10') && tick('104'), `ticks ${JSON.stringify(s.ticks)}`);
    assert.ok(tick('1').y - tick('10').y >= 50, `a decade of ${tick('1').y - tick('10').y} px`);
    assert.ok(s.ticks.length <= 9, `the round-off value stretches the axis: ${JSON.stringify(s.ticks)}`);
    assert.ok(s.lastBottomY < tick('1').y && s.lastBottomY > tick('10').y, `the plateau (3 q_y) at y ${s.lastBottomY} between the ticks 1 and 10: ${JSON.stringify(s.ticks)}`);
    assert.ok(s.label.some((t) => /plate stress σ \/ qy/.test(t)) && s.label.some((t) => /imposed strain ε/.test(t)), JSON.stringify(s.label));
    await page.locator('#stress-fig button[data-scale="linear"]').click();
    assert.equal((await stress()).scale, 'linear');
    await page.locator('#stress-fig button[data-scale="log"]').click();
    assert.equal((await stress()).scale, 'log');

    // --- No band in an erratic run: no c_b/V, no ± of it, none of the band's speeds, and why.
    const card = await page.locator('#card-class').innerText();
    assert.match(await page.locator('#band-speed').innerText(), /no band/);
    assert.doesNotMatch(card, /1\.132|0\.481/, card);
    assert.equal(await page.locator('#card-class li[data-feature^="band_speed"]').count(), 0);
    assert.match(await page.locator('#no-band-note').innerText(), /not band speeds/);

    // --- Features in the glossary's groups, in its order, each with the glossary's explanation.
    const groups = await page.locator('#card-class .feature-group').evaluateAll((els) => els.map((e) => e.dataset.group));
    assert.deepEqual(groups, GLOSSARY.groups.map((g) => g.id).filter((g) => g !== 'run').concat('run'), JSON.stringify(groups));
    for (const key of ['coherence', 'peak_jump', 'stress_ratio', 'deflection_growth', 'two_sided', 'scores']) {
      const li = page.locator(`#card-class li[data-feature="${key}"]`);
      assert.equal(await li.count(), 1, key);
      assert.equal(await li.locator('.feature-text').innerText(), GLOSSARY.features[key].text);
      assert.equal(await li.evaluate((e) => e.closest('.feature-group').dataset.group), GLOSSARY.features[key].group);
    }

    // --- No token field on a server without tokens.
    await page.waitForSelector('#relabel-form');
    await page.waitForTimeout(300); // the health answer
    assert.equal(await page.locator('#rl-token-row').isVisible(), false);
    await shot(page, 'run-detail-erratic-1440');

    // --- A band: its speed ± its error, and the band's readings.
    await openRun(page, h.url, banded);
    assert.match(await page.locator('#band-speed').innerText(), /^1\.700 ± 0\.050$/);
    assert.equal(await page.locator('#card-class li[data-feature="band_speed_transit"] .feature-value').innerText(), '1.2 ± 0.1');
    assert.equal(await page.locator('#no-band-note').count(), 0);

    // --- An imported run: POST /imports of the committed Fig. 2 map, as scripts/main.sh does.
    const res = await fetch(`${h.url}/api/v1/imports`, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: readFileSync(EXPORT) });
    assert.ok(res.ok, `import -> ${res.status} ${await res.text()}`);
    const file = JSON.parse(readFileSync(EXPORT, 'utf8'));
    const sweeps = (await h.api('/sweeps')).json.sweeps;
    const imported = sweeps.find((x) => x.imported);
    assert.ok(imported, JSON.stringify(sweeps.map((x) => x.id)));
    const run = (await h.api(`/jobs?sweep=${imported.id}&limit=1`)).json.jobs[0];
    const origin = run.result.origin;
    assert.ok(origin && file.runs.some((r) => r.origin.job === origin.job && r.origin.database === origin.database), JSON.stringify(origin));
    await openRun(page, h.url, run.id);
    await page.waitForSelector('#run-import:not([hidden]) #run-source-server');
    const head = await page.locator('#run-import').innerText();
    assert.match(head, new RegExp(`job ${origin.job}\\b`));
    assert.match(head, new RegExp(file.source.server.replace(/\./g, '\\.')));
    assert.match(head, /source's clock/);
    await waitFor(async () => /not on this server/.test(await page.locator('#run-import').innerText()), { what: 'the note that the files are not here' });
    const text = await page.locator('#page').innerText();
    assert.doesNotMatch(text, /ended at ε|before the requested|written before movies existed|no frames\.csv/, 'no reason that is not true of an imported run');
    // One card says so in place of the four figures.
    for (const card of ['#st-fig', '#files-box']) assert.match(await page.locator(card).innerText(), /not on this server/, card);
    for (const card of ['#card-stress', '#card-snapshot', '#card-movie']) assert.equal(await page.locator(card).isVisible(), false, card);
    const state = await page.locator('#state-box table.kv').innerText();
    assert.doesNotMatch(state, /waited in queue|created/, state);
    assert.doesNotMatch(state, /(^|\s)[-−]\d/m, `a negative time: ${state}`);
    assert.match(state, /imported here/);
    await shot(page, 'run-detail-imported-1440');

    // --- The sweeps list marks the imported sweep with its source server.
    await page.goto(`${h.url}/#/sweeps`);
    const mark = page.locator(`tr[data-sweep="${imported.id}"] .badge.imported`);
    await mark.waitFor();
    assert.match(await mark.innerText(), new RegExp(`imported from ${file.source.server.replace(/\./g, '\\.')}`));
    assert.match(await page.locator(`tr[data-sweep="${imported.id}"] .muted.small`).first().innerText(), /^imported /, 'its date is the import\'s');
    assert.equal(await page.locator(`tr[data-sweep="${created.json.id}"] .badge.imported`).count(), 0);
    await shot(page, 'run-detail-sweeps-1440');

    // --- A phone: nothing scrolls sideways.
    await page.setViewportSize({ width: 390, height: 844 });
    for (const [id, name] of [[erratic, 'erratic'], [run.id, 'imported']]) {
      await openRun(page, h.url, id);
      await page.waitForTimeout(200);
      await fits(page);
      await shot(page, `run-detail-${name}-390`);
    }
    await page.goto(`${h.url}/#/sweeps`);
    await page.locator('.badge.imported').first().waitFor();
    await shot(page, 'run-detail-sweeps-390');
    assert.deepEqual(h.pageErrors, []);
  } finally {
    await h.close();
  }
});

test('the relabel form asks for the token at once on a server that wants one', { timeout: 90000 }, async () => {
  const h = new Harness('run-detail-token');
  try {
    await h.startServer(['--submit-token', 'detail-test-token']);
    assert.equal((await h.api('/health')).json.tokens.submit, 'required');
    const created = await fetch(`${h.url}/api/v1/sweeps`, {
      method: 'POST', headers: { 'Content-Type': 'application/json', Authorization: 'Bearer detail-test-token' },
      body: JSON.stringify({ ...SWEEP, S: 1e-3 }),
    });
    assert.equal(created.status, 201);
    await completeAll(h.url, () => ({ class: 'b', confidence: 0.7, runner_up: 'a', n_reflections: 1, band_speed_ratio: 3.1, features: FEATURES, frames: FRAMES }));
    const id = (await h.api('/jobs?state=succeeded')).json.jobs[0].id;
    const page = await h.browser({ width: 1440, height: 900 });
    await openRun(page, h.url, id);
    await page.waitForSelector('#rl-token-row', { state: 'visible' });
    assert.deepEqual(h.pageErrors, []);
  } finally {
    await h.close();
  }
});
