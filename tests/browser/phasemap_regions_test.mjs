// The phase map's predicted regions and exports in real headless Chromium against a real
// compaction-server whose database holds labelled results (a 5 x 5 grid labelled by a known
// field through the worker API, lib/mapfill.mjs): the background appears under the markers in
// the colour of the predicted class where the prediction is sure and greyed where it is not,
// the toggle takes it away and back; a label of confidence 0.05 looks faded against one of
// 0.97, two runs at one (S, R) with other numerics are both visible, an unclassified run shows
// its runner-up (ring and tooltip), tick labels use one notation and markers stay inside the
// frame; the SVG and PNG exports hold the axes, legend, background and every marker.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { Harness, artifactsDir, canvasBox, waitFor, WEB_DIR } from './lib/harness.mjs';
import { fillMap, PHI, DOUBTFUL, UNCLASSIFIED, TWIN } from './lib/mapfill.mjs';

const { cellColor } = await import(join(WEB_DIR, 'js', 'regions.js'));
const { CLASSES } = await import(join(WEB_DIR, 'js', 'classes.js'));

const hexRgb = (h) => [1, 3, 5].map((i) => parseInt(h.slice(i, i + 2), 16));
const close = (a, b, tol) => b.every((v, i) => Math.abs(a[i] - v) <= tol); // on b's channels
const near = (a, b) => Math.abs(Math.log10(a / b)) < 1e-6;

async function shot(page, name) {
  const path = join(artifactsDir(), `${name}.png`);
  await page.screenshot({ path, fullPage: true });
  console.log(`# screenshot ${path}`);
}

const mapState = (page) => page.evaluate(() => window.__dashboard?.phaseMap ?? null);
const pixel = (page, x, y) => page.evaluate(({ x, y }) => {
  const c = document.querySelector('#map-plot canvas');
  const dpr = c.width / c.clientWidth;
  return Array.from(c.getContext('2d').getImageData(Math.round(x * dpr), Math.round(y * dpr), 1, 1).data); // r, g, b, a
}, { x, y });

// Canvas pixels of the regions' cells, with the cell they show, away from every marker (3
// radii) and from the box's edges: where the background alone is seen.
async function backgroundSpots(page, regions) {
  return page.evaluate(({ regions }) => {
    const m = window.__dashboard.phaseMap;
    const c = document.querySelector('#map-plot canvas');
    const out = [];
    const { x0, y0, x1, y1 } = m.regions;
    for (let y = Math.ceil(Math.max(y0, 0)) + 6; y < Math.min(y1, c.clientHeight) - 6; y += 9) {
      for (let x = Math.ceil(Math.max(x0, 0)) + 6; x < Math.min(x1, c.clientWidth) - 6; x += 9) {
        if (m.points.some((p) => (p.x - x) ** 2 + (p.y - y) ** 2 < (3 * m.radius) ** 2)) continue;
        const i = Math.floor(((x - x0) / (x1 - x0)) * regions.grid);
        const j = regions.grid - 1 - Math.floor(((y - y0) / (y1 - y0)) * regions.grid);
        // The cell and its neighbours agree (no blend of two cells by the image's smoothing).
        const same = [[0, 0], [1, 0], [-1, 0], [0, 1], [0, -1]].every(([di, dj]) => {
          const row = regions.classes[j + dj], u = regions.uncertainty[j + dj];
          return row && row[i + di] === regions.classes[j][i] && Math.abs(u[i + di] - regions.uncertainty[j][i]) < 0.03;
        });
        if (same) out.push({ x, y, cls: regions.classes[j][i], u: regions.uncertainty[j][i] });
      }
    }
    return out;
  }, { regions });
}

test('the phase map draws the predicted regions under its markers and exports SVG and PNG', { timeout: 120000 }, async () => {
  const h = new Harness('regions');
  try {
    await h.startServer();
    assert.equal(await fillMap(h), 26, '25 grid runs and the twin');

    // --- The endpoint: 24 of the grid's runs and the twin carry a label (one is unclassified).
    const res = await fetch(`${h.url}/api/v1/phase-map/regions?phi=${PHI}`);
    assert.equal(res.status, 200);
    const regions = await res.json();
    assert.equal(regions.grid, 128);
    assert.equal(regions.runs, 25);
    assert.equal(regions.classes.length, 128);
    const again = await fetch(`${h.url}/api/v1/phase-map/regions?phi=${PHI}`, { headers: { 'If-None-Match': res.headers.get('etag') } });
    assert.equal(again.status, 304, 'served through the answer cache with its ETag');
    for (const [q, field] of [['', 'phi'], [`phi=0.9`, 'phi'], [`phi=${PHI}&grid=4`, 'grid'], [`phi=${PHI}&grid=x`, 'grid'],
      [`phi=${PHI}&cells_per_unit=1`, 'cells_per_unit'], [`phi=${PHI}&sweep=0`, 'sweep']]) {
      const r = await fetch(`${h.url}/api/v1/phase-map/regions?${q}`);
      assert.equal(r.status, 422, q);
      assert.equal((await r.json()).error.field, field, q);
    }
    const one = await (await fetch(`${h.url}/api/v1/phase-map/regions?phi=${PHI}&cells_per_unit=${TWIN.numerics.cells_per_unit}`)).json();
    assert.equal(one.runs, 1, 'the numerics filter keeps the twin alone');

    // --- The page: every run and the background. All resolutions: the twin's finer grid would
    // hide its coarser run by default (map_zoom_test checks the default).
    const page = await h.browser();
    await page.goto(`${h.url}/#/map?phi=${PHI}&cpu=all`);
    const m = await waitFor(async () => {
      const s = await mapState(page);
      return s && s.count === 26 && s.regions ? s : null;
    }, { timeoutMs: 15000, what: 'the map with 26 runs over its regions' });
    assert.equal(m.regions.grid, 128);
    assert.equal(m.regions.runs, 25);
    await shot(page, 'regions-01-map');

    // Sure cells show their class's tint, uncertain ones are grey (less saturated).
    const spots = await backgroundSpots(page, regions);
    const sure = spots.filter((s) => s.u < 0.3 && CLASSES[s.cls]);
    const unsure = spots.filter((s) => s.u > 0.85);
    assert.ok(sure.length >= 20 && unsure.length >= 5, `${sure.length} sure and ${unsure.length} uncertain background spots`);
    const classesSeen = new Set();
    for (const s of sure) {
      const got = await pixel(page, s.x, s.y);
      assert.ok(close(got, cellColor(s.cls, s.u), 10), `background at (${s.x}, ${s.y}) is ${got}, the look of ${s.cls} at u = ${s.u} is ${cellColor(s.cls, s.u)}`);
      classesSeen.add(s.cls);
    }
    assert.ok(classesSeen.size >= 4, `the background shows ${[...classesSeen]}`);
    const saturation = (c) => Math.max(...c.slice(0, 3)) - Math.min(...c.slice(0, 3));
    for (const s of unsure.slice(0, 10)) {
      const got = await pixel(page, s.x, s.y);
      assert.ok(saturation(got) <= 30, `uncertain spot (${s.x}, ${s.y}) u = ${s.u} drawn ${got}: grey expected`);
    }

    // The toggle takes the background away (the canvas is clear there: the plot area shows) and
    // brings it back.
    const probe = sure[0];
    await page.locator('#map-regions').uncheck();
    await waitFor(async () => (await mapState(page)).regions === null, { what: 'the map without regions' });
    assert.equal((await pixel(page, probe.x, probe.y))[3], 0);
    assert.match(page.url(), /regions=0/);
    await page.locator('#map-regions').check();
    await waitFor(async () => (await mapState(page)).regions !== null, { what: 'the regions back' });
    assert.ok(close(await pixel(page, probe.x, probe.y), cellColor(probe.cls, probe.u), 10));

    // --- Confidence: the 0.05 label is faded towards white, a 0.97 one of the same class is not.
    const st = await mapState(page);
    const jobs = (await h.api(`/phase-map?phi=${PHI}`)).json.points;
    const jobAt = (S, R, cpu) => jobs.find((p) => near(p.S, S) && near(p.R, R) && (!cpu || p.cells_per_unit === cpu));
    const doubtful = st.points.find((p) => p.job_id === jobAt(DOUBTFUL.S, DOUBTFUL.R).job_id);
    const sureC = st.points.find((p) => p.cat === doubtful.cat && p.job_id !== doubtful.job_id);
    assert.ok(doubtful.fade > 0.6 && sureC.fade < 0.05, `fades ${doubtful.fade} and ${sureC.fade}`);
    const cColour = hexRgb(CLASSES[doubtful.cat].color);
    const dPix = await pixel(page, doubtful.x, doubtful.y), sPix = await pixel(page, sureC.x, sureC.y);
    assert.ok(close(sPix, cColour, 12), `confident ${doubtful.cat} drawn ${sPix}`);
    assert.ok(!close(dPix, cColour, 60) && Math.min(...dPix.slice(0, 3)) > Math.min(...cColour) + 60, `doubtful ${doubtful.cat} drawn ${dPix}, lighter than ${cColour}`);

    // --- Two runs at one (S, R) with other numerics: both markers, apart.
    const twins = jobs.filter((p) => near(p.S, TWIN.S) && near(p.R, TWIN.R)).map((p) => st.points.find((q) => q.job_id === p.job_id));
    assert.equal(twins.length, 2);
    assert.ok(Math.hypot(twins[0].x - twins[1].x, twins[0].y - twins[1].y) >= 2 * st.radius, 'the twins do not cover each other');
    assert.match(await page.locator('#map-summary').innerText(), /26 runs at 25 places/);

    // --- The unclassified run: a ring in its runner-up's colour and its numbers in the tooltip.
    const un = st.points.find((p) => p.job_id === jobAt(UNCLASSIFIED.S, UNCLASSIFIED.R).job_id);
    assert.equal(un.cat, 'unclassified');
    assert.equal(un.ring, 'f');
    const ringPix = await pixel(page, un.x + st.radius + 1.6, un.y);
    assert.ok(close(ringPix, hexRgb(CLASSES.f.color), 40), `ring drawn ${ringPix}`);
    const box = await canvasBox(page, '#map-plot canvas');
    await page.mouse.move(box.x + un.x, box.y + un.y);
    await page.locator('#tooltip:not([hidden])').waitFor();
    const tip = await page.locator('#tooltip').innerText();
    assert.match(tip, /runner-up\s+f · buckling/);
    assert.match(tip, /0\.030/);
    await shot(page, 'regions-02-unclassified-tooltip');
    // Over the background alone, the tooltip tells the prediction there.
    await page.mouse.move(box.x + probe.x, box.y + probe.y);
    await waitFor(async () => /predicted region/.test(await page.locator('#tooltip').innerText()), { what: 'the region tooltip' });
    assert.match(await page.locator('#tooltip').innerText(), new RegExp(`${probe.cls} · ${CLASSES[probe.cls].name}`));

    // --- Ticks in one notation (no "0.02" beside "10^-2"), markers inside the frame.
    const ticks = await page.locator('#map-plot .plot-svg text.ticklabel').evaluateAll((ts) => ts.map((t) => t.textContent));
    assert.ok(ticks.length >= 6);
    for (const t of ticks) assert.match(t.replace(/\s/g, ''), /^(1|10|[2-9]0?|([2-9](\.\d)?×)?10−?\d+)$/, `tick label "${t}"`);
    // Positions and plot area of one render (a live update may replace the canvas meanwhile).
    const { area } = st;
    assert.ok(area.width > 200 && area.height > 200, `plot area ${area.width} x ${area.height}`);
    for (const p of st.points) {
      const edge = st.radius * 1.3;
      assert.ok(p.x >= edge && p.y >= edge && p.x <= area.width - edge && p.y <= area.height - edge,
        `run ${p.job_id} at (${p.x}, ${p.y}) is cut by the frame of the ${area.width} x ${area.height} plot area`);
    }

    // --- Exports: an SVG with axes, background, every marker and the legend; a PNG of it.
    await page.mouse.move(0, 0);
    const [svgDl] = await Promise.all([page.waitForEvent('download'), page.locator('#map-export-svg').click()]);
    assert.equal(svgDl.suggestedFilename(), `phase-map-phi${PHI}.svg`);
    const svgText = readFileSync(await svgDl.path(), 'utf8');
    await svgDl.saveAs(join(artifactsDir(), 'regions-03-export.svg'));
    assert.match(svgText, /^<\?xml/);
    const svgInfo = await page.evaluate((text) => {
      const doc = new DOMParser().parseFromString(text, 'image/svg+xml');
      const q = (s) => doc.querySelectorAll(s);
      return {
        error: q('parsererror').length,
        markers: q('[data-layer="markers"] > g').length,
        cats: [...q('[data-layer="markers"] > g')].map((g) => g.getAttribute('data-cat')),
        regions: doc.querySelector('[data-layer="regions"]')?.getAttribute('href')?.slice(0, 22),
        ticks: q('[data-layer="axes"] text').length,
        legend: [...q('[data-layer="legend"] text')].map((t) => t.textContent),
        width: Number(doc.documentElement.getAttribute('width')),
      };
    }, svgText);
    assert.equal(svgInfo.error, 0);
    assert.equal(svgInfo.markers, 26);
    assert.deepEqual(svgInfo.cats.sort(), st.points.map((p) => p.cat).sort());
    assert.equal(svgInfo.regions, 'data:image/png;base64,');
    assert.ok(svgInfo.ticks >= 8, `${svgInfo.ticks} axis texts`);
    for (const k of Object.keys(CLASSES)) assert.ok(svgInfo.legend.includes(`${k} ${CLASSES[k].name}`), `legend line of ${k}`);
    assert.ok(svgInfo.legend.some((t) => /predicted class/.test(t)));

    const [pngDl] = await Promise.all([page.waitForEvent('download'), page.locator('#map-export-png').click()]);
    assert.equal(pngDl.suggestedFilename(), `phase-map-phi${PHI}.png`);
    const png = readFileSync(await pngDl.path());
    await pngDl.saveAs(join(artifactsDir(), 'regions-04-export.png'));
    console.log(`# exports ${join(artifactsDir(), 'regions-03-export.svg')} and regions-04-export.png`);
    assert.deepEqual([...png.subarray(0, 8)], [137, 80, 78, 71, 13, 10, 26, 10], 'a PNG file');
    assert.equal(png.readUInt32BE(16), 2 * svgInfo.width, 'twice the SVG width');
    // The PNG shows the same background as the page at the probe (scaled by 2, offset by the
    // plot's margin: the canvas starts at the SVG's plot area).
    const margin = await page.locator('#map-plot canvas').evaluate((c) => [parseFloat(c.style.left), parseFloat(c.style.top)]);
    const pngPix = await page.evaluate(async ({ b64, x, y }) => {
      const bytes = Uint8Array.from(atob(b64), (ch) => ch.charCodeAt(0));
      const bmp = await createImageBitmap(new Blob([bytes], { type: 'image/png' }));
      const c = new OffscreenCanvas(bmp.width, bmp.height);
      const ctx = c.getContext('2d');
      ctx.drawImage(bmp, 0, 0);
      return Array.from(ctx.getImageData(Math.round(2 * x), Math.round(2 * y), 1, 1).data.slice(0, 3));
    }, { b64: png.toString('base64'), x: margin[0] + probe.x, y: margin[1] + probe.y });
    assert.ok(close(pngPix, cellColor(probe.cls, probe.u), 14), `PNG background ${pngPix}`);

    assert.deepEqual(h.pageErrors, [], 'no errors in the page');
  } catch (e) {
    for (const [k, v] of Object.entries(h.logs)) if (v) console.log(`# ${k} log tail:\n${v.slice(-3000)}`);
    throw e;
  } finally {
    await h.close();
  }
});

test('the sweep form shows the cost model\'s CPU-hours and the finish time for the workers connected', { timeout: 90000 }, async () => {
  const h = new Harness('estimate');
  try {
    await h.startServer();
    const page = await h.browser();
    await page.goto(`${h.url}/#/sweeps`);
    await page.locator('#f-preset option[value="fast"]').waitFor({ state: 'attached' });
    // No worker yet: the cost, and no finish time.
    await page.locator('#f-name').fill('x');
    await page.locator('#f-s-n').fill('4');
    const none = await waitFor(async () => {
      const t = await page.locator('#job-cost').innerText();
      return /CPU-hour/.test(t) ? t : null;
    }, { what: 'the cost under the job count' });
    assert.match(none, /no worker connected/);
    // The number is the server's estimate of the form's body: 4 S x 5 R at the default preset.
    const body = { name: 'x', S: { min: 1e-3, max: 1e-1, n: 4, scale: 'log' }, R: { min: 1e-5, max: 1e-1, n: 5, scale: 'log' }, phi: 0.4, numerics: { preset: 'default' } };
    const est = (await h.api('/sweeps/estimate', body)).json;
    assert.equal(est.jobs, 20);
    assert.equal(Number(await page.locator('#job-cost').getAttribute('data-cpu-seconds')), est.cpu_seconds);
    assert.match(none, new RegExp(`about ${Number((est.cpu_seconds / 3600).toPrecision(2)).toLocaleString('en-US')} CPU-hours`));
    // A worker asks for a lease (the queue is empty): it counts as connected.
    const health = (await h.api('/health')).json;
    assert.equal((await h.api('/leases', { worker: 'w1', engine_version: health.engine_version })).status, 204);
    await page.locator('#f-s-n').fill('5');
    const one = await waitFor(async () => {
      const t = await page.locator('#job-cost').innerText();
      return /1 worker connected/.test(t) ? t : null;
    }, { what: 'the finish time with one worker' });
    assert.match(one, /done in about .+ \(around \d/);
    assert.equal(await page.locator('#job-cost').getAttribute('data-workers'), '1');
    // An invalid form has no estimate.
    await page.locator('#f-s-n').fill('0');
    await waitFor(async () => (await page.locator('#job-cost').innerText()) === '', { what: 'no cost for an invalid form' });
    await page.locator('#f-s-n').fill('5');
    await waitFor(async () => /CPU-hour/.test(await page.locator('#job-cost').innerText()), { what: 'the cost again' });
    await shot(page, 'regions-05-sweep-cost');
    assert.deepEqual(h.pageErrors, [], 'no errors in the page');
  } catch (e) {
    for (const [k, v] of Object.entries(h.logs)) if (v) console.log(`# ${k} log tail:\n${v.slice(-3000)}`);
    throw e;
  } finally {
    await h.close();
  }
});
