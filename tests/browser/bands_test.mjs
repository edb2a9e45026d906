// The band-speed page (Fig. 3) in real headless Chromium, served by a real compaction-server, on
// phase-map points answered by playwright's request routing: only bands, classes (a) and (b), are
// plotted; every run left off is counted with its reason; each plotted band with an uncertainty
// has an error bar from c_b/V - e to c_b/V + e (cut at the plot's edge), for every reading.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { Harness, artifactsDir, canvasBox, waitFor } from './lib/harness.mjs';

const point = (job_id, extra) => ({
  S: 0.03, R: 1e-3, phi: 0.4, state: 'succeeded', class: null, confidence: 0.9, runner_up: null, n_reflections: 0,
  band_speed_ratio: null, band_speed_error: null, band_speed_transit: null, band_speed_transit_error: null,
  band_speed_early: null, band_speed_early_error: null, band_speed_lead: null, band_speed_lead_error: null,
  job_id, status: 'ok', cells_per_unit: 20, eps_end: 0.2, progress_eps: null, ...extra,
});

const POINTS = [
  point(1, { class: 'a', S: 0.03, R: 1e-3, band_speed_ratio: 1.73, band_speed_error: 0.008, band_speed_transit: 1.694, band_speed_transit_error: 0.016, band_speed_early: 1.731, band_speed_early_error: 0.003, band_speed_lead: 1.729, band_speed_lead_error: 0.004 }),
  // a random structure: a square marker, as in the paper's Fig. 3 (the others are regular: circles)
  point(2, { class: 'b', S: 0.01, R: 1e-2, n_reflections: 3, band_speed_ratio: 3.57, band_speed_error: 0.15, band_speed_transit: 3.49, band_speed_transit_error: 0.03, band_speed_lead: 2.79, band_speed_lead_error: 0.01, structure: 'random' }),
  point(3, { class: 'b', S: 0.02, R: 3e-3, n_reflections: 1, band_speed_ratio: 2.5 }), // no uncertainty
  point(4, { class: 'a', S: 0.05, R: 1e-4 }), // no band speed measured
  point(5, { class: 'a', S: 0.04, R: 2e-4, band_speed_ratio: -0.4, band_speed_error: 0.1, band_speed_transit: -0.3, band_speed_transit_error: 0.1 }),
  point(6, { class: 'd', S: 0.1, R: 1e-4, band_speed_ratio: 0.03, band_speed_error: 0.01 }),
  point(7, { class: 'f', S: 0.01, R: 0.05, band_speed_ratio: 0.031, band_speed_error: 0.01 }),
  point(8, { state: 'queued', status: null, confidence: null, n_reflections: null }),
  // an uncertainty larger than the value: the bar runs off the bottom of the log axis
  point(9, { class: 'b', S: 0.015, R: 5e-3, n_reflections: 2, band_speed_ratio: 0.9, band_speed_error: 1.2, band_speed_transit: 1.1, band_speed_transit_error: 0.05 }),
];
const byId = new Map(POINTS.map((p) => [p.job_id, p]));

async function shot(page, name) {
  const path = join(artifactsDir(), `${name}.png`);
  await page.screenshot({ path, fullPage: true });
  console.log(`# screenshot ${path}`);
}

// What the page drew: the plotted runs, the plot area and y axis, the error bars and caps.
const drawing = (page) => page.evaluate(() => {
  const hook = window.__dashboard?.bands;
  const area = document.querySelector('#bands-plot rect.plot-area');
  if (!hook || !area) return null;
  const num = (e, k) => Number(e.getAttribute(k));
  return {
    ...hook,
    area: { x: num(area, 'x'), y: num(area, 'y'), width: num(area, 'width'), height: num(area, 'height') },
    bars: [...document.querySelectorAll('#bands-plot line.error-bar')].map((e) => ({ job: Number(e.dataset.job), x1: num(e, 'x1'), x2: num(e, 'x2'), y1: num(e, 'y1'), y2: num(e, 'y2') })),
    caps: document.querySelectorAll('#bands-plot line.error-cap').length,
    leftOff: Object.fromEntries([...document.querySelectorAll('#bands-left-off li')].map((li) => [li.dataset.reason, { count: Number(li.dataset.count), text: li.innerText }])),
    summary: document.querySelector('#bands-summary').innerText,
  };
});

// The SVG y of a value on the page's log axis, from the plot area and the axis domain alone.
function yOf(d, v) {
  const [lo, hi] = d.yDomain.map(Math.log10);
  return d.area.y + ((hi - Math.log10(v)) / (hi - lo)) * d.area.height;
}

function checkBars(d, valueKey, errorKey) {
  const withError = d.plotted.filter((q) => Number.isFinite(byId.get(q.job_id)[errorKey]));
  assert.deepEqual(d.bars.map((b) => b.job).sort(), withError.map((q) => q.job_id).sort(), 'one error bar per plotted run with an uncertainty');
  let caps = 0;
  for (const b of d.bars) {
    const p = byId.get(b.job), v = p[valueKey], e = p[errorKey];
    const marker = d.plotted.find((q) => q.job_id === b.job);
    assert.ok(Math.abs(b.x1 - (d.area.x + marker.x)) < 0.01 && b.x1 === b.x2, `bar of run ${b.job} is vertical through its marker`);
    const top = yOf(d, v + e);
    const bottom = v - e > 0 ? yOf(d, v - e) : d.area.y + d.area.height;
    assert.ok(Math.abs(b.y1 - Math.max(top, d.area.y)) < 0.01, `bar of run ${b.job} reaches c_b/V + e: y ${b.y1}, expected ${top}`);
    assert.ok(Math.abs(b.y2 - Math.min(bottom, d.area.y + d.area.height)) < 0.01, `bar of run ${b.job} reaches c_b/V - e (or the axis): y ${b.y2}, expected ${bottom}`);
    caps += (top >= d.area.y ? 1 : 0) + (v - e > 0 && bottom <= d.area.y + d.area.height ? 1 : 0);
  }
  assert.equal(d.caps, caps, 'a cap at each end that is inside the plot');
}

test('the band-speed page plots bands only, with an error bar per band, and says what it left off', { timeout: 90000 }, async () => {
  const h = new Harness('bands');
  try {
    await h.startServer();
    const page = await h.browser();
    await page.route('**/api/v1/phase-map?**', (route) => route.fulfill({ status: 200, contentType: 'application/json', body: JSON.stringify({ phi: 0.4, points: POINTS }) }));
    await page.goto(`${h.url}/#/bands?phi=0.4`);

    // The fit: bands (a) and (b) with a positive c_b/V; (d), (f), the queued run, the missing
    // and the negative band speed left off and counted.
    const fit = await waitFor(async () => { const d = await drawing(page); return d && d.plotted.length ? d : null; }, { what: 'the band plot' });
    assert.equal(fit.reading, 'fit');
    assert.deepEqual(fit.plotted.map((q) => q.job_id).sort(), [1, 2, 3, 9]);
    assert.equal(await page.locator('#bands-plot canvas').getAttribute('data-count'), '4');
    checkBars(fit, 'band_speed_ratio', 'band_speed_error');
    assert.equal(fit.caps, 5, 'runs 1 and 2 have two caps, run 9 only the upper one');
    assert.deepEqual(Object.fromEntries(Object.entries(fit.leftOff).map(([k, v]) => [k, v.count])), { missing: 1, nonPositive: 1, notBand: 2, unlabelled: 1 });
    assert.match(fit.leftOff.missing.text, /run 4/);
    assert.match(fit.leftOff.nonPositive.text, /run 5/);
    assert.match(fit.summary, /4 bands plotted of 9 runs at φ = 0.4 · 1 without an uncertainty/);
    const legend = await page.locator('#bands-legend li').evaluateAll((lis) => lis.map((li) => Number(li.dataset.count)));
    assert.deepEqual(legend, [1, 1, 1, 1, 0, 0, 0], 'N_r of the plotted bands: 0, 1, 2 and 3');
    await shot(page, '10-band-speed-fit');

    // Marker shapes: run 2 (random) a square, the rest (regular) circles. The canvas holds only
    // the markers; 5 px right and down of a centre lies inside the 11 px square and outside the
    // circle of radius 6 and its 1.2 px outline (7.07 px from the centre).
    assert.deepEqual(Object.fromEntries(fit.plotted.map((q) => [q.job_id, q.shape])), { 1: 'circle', 2: 'square', 3: 'circle', 9: 'circle' });
    const alphaAt = (x, y) => page.evaluate(({ x, y }) => {
      const c = document.querySelector('#bands-plot canvas');
      const dpr = c.width / c.clientWidth;
      return c.getContext('2d').getImageData(Math.round(x * dpr), Math.round(y * dpr), 1, 1).data[3];
    }, { x, y });
    for (const q of fit.plotted) {
      const corner = await alphaAt(q.x + 5, q.y + 5);
      if (q.shape === 'square') assert.equal(corner, 255, `run ${q.job_id}: the square's corner is drawn`);
      else assert.equal(corner, 0, `run ${q.job_id}: a circle leaves the corner empty`);
      assert.equal(await alphaAt(q.x, q.y), 255, `run ${q.job_id}: the marker's centre is drawn`);
    }

    // Hover: both readings with their uncertainties.
    const one = fit.plotted.find((q) => q.job_id === 1);
    const box = await canvasBox(page, '#bands-plot canvas');
    await page.mouse.move(box.x + one.x, box.y + one.y);
    await page.locator('#tooltip:not([hidden])').waitFor();
    const tip = await page.locator('#tooltip').innerText();
    assert.match(tip, /run 1/);
    assert.match(tip, /1\.730 ± 0\.008/);
    assert.match(tip, /1\.694 ± 0\.016/);
    assert.match(tip, /early, middle\)\s+1\.731 ± 0\.003/);
    assert.match(tip, /early, leading edge\)\s+1\.729 ± 0\.004/);
    assert.match(tip, /structure\s+regular/);
    await page.mouse.move(box.x + 2, box.y + 2);

    // The transit reading: runs 3 and 4 have none, run 5's is negative.
    await page.locator('#bands-reading').selectOption('transit');
    const transit = await waitFor(async () => { const d = await drawing(page); return d && d.reading === 'transit' ? d : null; }, { what: 'the transit plot' });
    assert.deepEqual(transit.plotted.map((q) => q.job_id).sort(), [1, 2, 9]);
    checkBars(transit, 'band_speed_transit', 'band_speed_transit_error');
    assert.equal(transit.leftOff.missing.count, 2);
    assert.match(page.url(), /speed=transit/);
    await shot(page, '11-band-speed-transit');

    // The early stage's leading edge: only runs 1 and 2 have one.
    await page.locator('#bands-reading').selectOption('lead');
    const lead = await waitFor(async () => { const d = await drawing(page); return d && d.reading === 'lead' ? d : null; }, { what: 'the leading-edge plot' });
    assert.deepEqual(lead.plotted.map((q) => q.job_id).sort(), [1, 2]);
    checkBars(lead, 'band_speed_lead', 'band_speed_lead_error');
    assert.equal(lead.leftOff.missing.count, 4);
    assert.match(page.url(), /speed=lead/);
    await shot(page, '12-band-speed-lead');

    assert.deepEqual(h.pageErrors, [], 'no errors in the page');
  } catch (e) {
    for (const [k, v] of Object.entries(h.logs)) if (v) console.log(`# ${k} log tail:\n${v.slice(-3000)}`);
    throw e;
  } finally {
    await h.close();
  }
});
