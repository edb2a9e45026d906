// The Plots page (#/plots, web/js/pages/plots.js) in real headless Chromium against a real
// compaction-server holding the committed export studies/phase_map/results/sweep-2.export.json
// (200 imported runs of all six classes). Checked against direct requests of GET /api/v1/jobs:
// the plotted runs are the API's rows of the filter that have both values (and > 0 on a log
// axis, the others counted), markers sit at the pixels their values map to and show their
// class's colour there, the first rows of a set drawn while the rest come (the threshold lowered
// to 50 rows), a class chip of the shared filter form narrows the rows as the table's
// query does, the log/linear switch, the Fig. 3 view (its URL, only classes a and b, coloured by
// N_r), the tooltip and the click to a run, the SVG export (one marker per plotted run) and the
// PNG, the Runs page's "plot these runs" link, a reload of a shared URL, 390 x 844 without
// sideways scrolling, and no JavaScript error. Screenshots go to $BROWSER_ARTIFACTS_DIR.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { Harness, REPO, artifactsDir, binaries, canvasBox, waitFor } from './lib/harness.mjs';
import { CLASSES } from '../../web/js/classes.js';

const EXPORT = join(REPO, 'studies', 'phase_map', 'results', 'sweep-2.export.json');

async function shot(page, name) {
  const path = join(artifactsDir(), `${name}.png`);
  await page.screenshot({ path, fullPage: true });
  console.log(`# screenshot ${path}`);
}

// The page publishes each plot it draws (window.__dashboard.plots); mark() forgets the last,
// drawn() waits for the next and returns it (typed arrays as arrays).
const mark = (page) => page.evaluate(() => { if (window.__dashboard) window.__dashboard.plots = null; });
async function drawn(page, what) {
  return waitFor(() => page.evaluate(() => {
    const p = window.__dashboard?.plots;
    if (!p || document.querySelector('#pl-plot.loading')) return null;
    return { ...p, px: p.px ? Array.from(p.px) : [], py: p.py ? Array.from(p.py) : [] };
  }), { what: `the plot (${what})` });
}
const hashParams = (page) => page.evaluate(() => Object.fromEntries(new URLSearchParams(location.hash.split('?')[1] || '')));
const leftOff = (page) => page.$$eval('#pl-left-off li', (lis) => lis.map((l) => `${l.dataset.reason}:${l.dataset.axis}:${l.dataset.count}`));

const stressRatio = (r) => r.R / (r.S * r.S);
// A row's value of a plot variable.
const valueOf = (r, k) => (k === 'R_S2' ? stressRatio(r) : r[k]);
const placed = (rows, spec) => rows.filter((r) => {
  const x = valueOf(r, spec.x), y = valueOf(r, spec.y);
  return Number.isFinite(x) && Number.isFinite(y) && (spec.xscale !== 'log' || x > 0) && (spec.yscale !== 'log' || y > 0);
});
const sorted = (a) => [...a].sort((x, y) => x - y);

// The canvas pixel a value maps to (relative to the plot area), from the plot's axes.
function pixelOf(p, spec, r) {
  const f = (kind, v) => (kind === 'log' ? Math.log10(v) : v);
  const at = (kind, [d0, d1], v, len) => ((f(kind, v) - f(kind, d0)) / (f(kind, d1) - f(kind, d0))) * len;
  return [at(spec.xscale, p.plot.x, valueOf(r, spec.x), p.plot.pw), p.plot.ph - at(spec.yscale, p.plot.y, valueOf(r, spec.y), p.plot.ph)];
}

test('the Plots page: rows of the filter, positions, log/linear, Fig. 3, tooltip, exports, phone width', { timeout: 150000 }, async () => {
  const h = new Harness('plots');
  try {
    const imp = spawnSync(binaries().server, ['--db', join(h.dir, 'compaction.db'), '--import', EXPORT, '--log-level', 'warn'], { encoding: 'utf8' });
    assert.equal(imp.status, 0, imp.stderr);
    await h.startServer();
    const rowsOf = async (qs) => {
      const r = await h.api(`/jobs?${qs}${qs ? '&' : ''}format=table&limit=1000`);
      assert.equal(r.status, 200, JSON.stringify(r.json));
      return r.json.rows;
    };
    const all = await rowsOf('');
    assert.equal(all.length, 200);

    const page = await h.browser({ width: 1440, height: 900 });
    // A set of more than 50 rows is drawn first from its first rows as they come (the page's
    // 20 000 lowered so that these 200 runs take that path), then whole.
    await page.addInitScript(() => { window.__dashboard = { renders: [], firstRows: 50 }; });
    await page.goto(`${h.url}/#/plots`);
    let p = await drawn(page, 'the default plot');
    const firstPlot = await page.evaluate(() => window.__dashboard.firstPlot);
    assert.ok(firstPlot && firstPlot.rows > 50 && firstPlot.rows <= 200 && firstPlot.total === 200, `the first rows drawn first: ${JSON.stringify(firstPlot)}`);
    assert.ok(firstPlot.at <= p.at, 'before the whole plot');
    assert.equal(await page.locator('.nav a.active').getAttribute('data-page'), 'plots');
    const spec0 = { x: 'R_S2', y: 'band_speed_ratio', xscale: 'log', yscale: 'log', color: 'class' };
    assert.deepEqual(p.spec, spec0);
    assert.deepEqual(await hashParams(page), spec0, 'the URL holds the plot');
    // Every row came; the plotted ones are the API's rows with c_b/V > 0; the others are counted.
    assert.equal(p.rows, 200);
    let want = placed(all, spec0);
    assert.ok(want.length > 150 && want.length < 200, `${want.length} of 200 have c_b/V > 0`);
    assert.deepEqual(sorted(p.ids), sorted(want.map((r) => r.id)));
    assert.equal(Number(await page.locator('#pl-plot canvas').getAttribute('data-count')), want.length);
    const noValue = all.filter((r) => !Number.isFinite(r.band_speed_ratio)).length;
    const nonPositive = all.filter((r) => Number.isFinite(r.band_speed_ratio) && r.band_speed_ratio <= 0).length;
    assert.equal(noValue + nonPositive, 200 - want.length);
    assert.deepEqual(await leftOff(page), [...(noValue ? [`missing:y:${noValue}`] : []), ...(nonPositive ? [`nonPositive:y:${nonPositive}`] : [])]);
    assert.match(await page.locator('#pl-summary').innerText(), new RegExp(`^${want.length} of 200 runs plotted`));

    // Positions: the axes span the values, each marker sits where its values map; at a few
    // markers with no other within 12 px, the canvas shows its class's colour at that pixel.
    const byId = new Map(all.map((r) => [r.id, r]));
    const xs = want.map((r) => stressRatio(r)), ys = want.map((r) => r.band_speed_ratio);
    assert.ok(p.plot.x[0] < Math.min(...xs) && p.plot.x[1] > Math.max(...xs) && p.plot.y[0] < Math.min(...ys) && p.plot.y[1] > Math.max(...ys));
    p.ids.forEach((id, k) => {
      const [ex, ey] = pixelOf(p, spec0, byId.get(id));
      assert.ok(Math.abs(p.px[k] - ex) < 0.01 && Math.abs(p.py[k] - ey) < 0.01, `run ${id} at (${p.px[k]}, ${p.py[k]}), expected (${ex}, ${ey})`);
    });
    const lone = p.ids.map((id, k) => ({ id, x: p.px[k], y: p.py[k] }))
      .filter((a) => p.ids.every((_, j) => p.ids[j] === a.id || (p.px[j] - a.x) ** 2 + (p.py[j] - a.y) ** 2 > 144)).slice(0, 4);
    assert.ok(lone.length >= 3, 'at least three markers stand alone');
    for (const a of lone) {
      const rgb = await page.evaluate(({ x, y }) => {
        const c = document.querySelector('#pl-plot canvas');
        const dpr = c.width / c.clientWidth;
        return [...c.getContext('2d').getImageData(Math.round(x * dpr), Math.round(y * dpr), 1, 1).data];
      }, a);
      const hex = CLASSES[byId.get(a.id).class].color;
      const exp = [1, 3, 5].map((i) => parseInt(hex.slice(i, i + 2), 16));
      assert.deepEqual(rgb, [...exp, 255], `run ${a.id} (class ${byId.get(a.id).class}) drawn at its pixel`);
    }
    await shot(page, '70-plots-default');

    // The tooltip names the run under the mouse; a click opens it.
    const one = lone[0];
    await page.locator('#pl-plot canvas').scrollIntoViewIfNeeded();
    const box = await canvasBox(page, '#pl-plot canvas');
    await page.mouse.move(box.x + one.x, box.y + one.y);
    await waitFor(async () => (await page.locator('#tooltip').isVisible()) && (await page.locator('#tooltip').innerText()).includes(`run ${one.id}`), { what: 'the tooltip' });
    await page.mouse.click(box.x + one.x, box.y + one.y);
    await waitFor(() => page.evaluate((id) => location.hash === `#/run/${id}`, one.id), { what: 'the run page' });
    await mark(page);
    await page.goBack();
    await drawn(page, 'back from the run');

    // A class chip of the table's filter form: the rows of the table's query.
    await mark(page);
    await page.locator('.rt-chips[data-name="class"] label:has(input[value="c"])').click();
    p = await drawn(page, 'class c');
    const rowsC = await rowsOf('class=c');
    assert.ok(rowsC.length > 0 && rowsC.length < 200);
    assert.equal(p.rows, rowsC.length);
    assert.match(p.query, /(^|&)class=c(&|$)/);
    assert.deepEqual(sorted(p.ids), sorted(placed(rowsC, spec0).map((r) => r.id)));
    assert.equal((await hashParams(page)).class, 'c');

    // Log and linear: N_r on a log y axis leaves out N_r = 0 (counted), on a linear one not.
    await mark(page);
    await page.locator('.rt-chips[data-name="class"] label:has(input[value="c"])').click(); // off again
    assert.equal((await drawn(page, 'all classes again')).rows, 200);
    await mark(page);
    await page.locator('#pl-y').selectOption('n_reflections');
    p = await drawn(page, 'N_r, log');
    const specLog = { ...spec0, y: 'n_reflections' };
    assert.deepEqual(p.spec, specLog);
    assert.equal(p.rows, 200, 'another axis redraws the rows it has');
    const zeros = all.filter((r) => r.n_reflections === 0).length;
    assert.ok(zeros > 0);
    assert.ok((await leftOff(page)).includes(`nonPositive:y:${zeros}`), `${zeros} runs with N_r = 0 left off: ${await leftOff(page)}`);
    assert.deepEqual(sorted(p.ids), sorted(placed(all, specLog).map((r) => r.id)));
    await mark(page);
    await page.locator('#pl-yscale').selectOption('linear');
    p = await drawn(page, 'N_r, linear');
    const specLin = { ...specLog, yscale: 'linear' };
    assert.deepEqual(await hashParams(page), specLin);
    assert.deepEqual(sorted(p.ids), sorted(placed(all, specLin).map((r) => r.id)));
    assert.ok(p.ids.length > placed(all, specLog).length);
    assert.ok(!(await leftOff(page)).some((l) => l.startsWith('nonPositive')));
    // Linear positions too.
    p.ids.slice(0, 5).forEach((id, k) => {
      const [ex, ey] = pixelOf(p, specLin, byId.get(id));
      assert.ok(Math.abs(p.px[k] - ex) < 0.01 && Math.abs(p.py[k] - ey) < 0.01, `run ${id} on the linear axis`);
    });

    // A classifier's feature (a column of the table since migration 0015): the deflection before
    // yield against R, asked for with the columns the plot reads only.
    await mark(page);
    await page.locator('#pl-x').selectOption('R');
    await drawn(page, 'N_r against R');
    await mark(page);
    await page.locator('#pl-y').selectOption('deflection_before_yield');
    await page.locator('#pl-yscale').selectOption('log');
    p = await drawn(page, 'deflection before yield against R');
    const specDefl = { ...specLin, x: 'R', y: 'deflection_before_yield', yscale: 'log' };
    assert.deepEqual(p.spec, specDefl);
    const cols = new URLSearchParams(p.query).get('columns').split(',');
    assert.ok(cols.includes('deflection_before_yield') && cols.includes('R') && !cols.includes('source_database'), `columns=${cols}`);
    const withDefl = placed(all, specDefl);
    assert.ok(withDefl.length >= 10, `${withDefl.length} runs with a deflection before yield`);
    const offCount = (await leftOff(page)).reduce((n, l) => n + Number(l.split(':')[2]), 0);
    assert.equal(offCount, all.length - withDefl.length, 'the others counted as left off (no value, or <= 0 on the log axis)');
    assert.deepEqual(sorted(p.ids), sorted(withDefl.map((r) => r.id)));
    withDefl.slice(0, 5).forEach((r) => {
      const k = p.ids.indexOf(r.id);
      const [ex, ey] = pixelOf(p, specDefl, r);
      assert.ok(Math.abs(p.px[k] - ex) < 0.01 && Math.abs(p.py[k] - ey) < 0.01, `run ${r.id}'s deflection at its pixel`);
    });
    await shot(page, '71-plots-deflection');

    // Fig. 3: one click sets the axes, scales, colour N_r and the class filter a,b; only bands.
    await mark(page);
    await page.locator('.pl-view[data-view="fig3"]').click();
    p = await drawn(page, 'Fig. 3');
    const fig3 = { x: 'R_S2', y: 'band_speed_ratio', xscale: 'log', yscale: 'log', color: 'n_reflections' };
    assert.deepEqual(await hashParams(page), { class: 'a,b', ...fig3 });
    assert.equal(await page.locator('.pl-view[data-view="fig3"]').getAttribute('aria-pressed'), 'true');
    const bands = await rowsOf('class=a,b');
    assert.equal(p.rows, bands.length);
    assert.deepEqual(sorted(p.ids), sorted(placed(bands, fig3).map((r) => r.id)));
    assert.ok(p.ids.every((id) => ['a', 'b'].includes(byId.get(id).class)), 'only classes a and b');
    const nr = {};
    for (const id of p.ids) { const n = Math.min(6, byId.get(id).n_reflections); nr[`n${n}`] = (nr[`n${n}`] || 0) + 1; }
    assert.deepEqual(Object.fromEntries(p.legend.map((e) => [e.key, e.count])), nr, 'the legend counts N_r');
    assert.equal(await page.locator('.rt-chips[data-name="class"] input[value="a"]').isChecked(), true);
    assert.equal(await page.locator('#pl-runs').getAttribute('href'), '#/runs?class=a,b', 'the table of the plotted filters');
    await shot(page, '71-plots-fig3');

    // SVG export: parses, one marker per plotted run (its data-job); PNG: a PNG twice as wide.
    const [svgDl] = await Promise.all([page.waitForEvent('download'), page.locator('#pl-svg').click()]);
    assert.equal(svgDl.suggestedFilename(), 'plot-band_speed_ratio-vs-R_S2.svg');
    const svg = readFileSync(await svgDl.path(), 'utf8');
    await svgDl.saveAs(join(artifactsDir(), 'plots-fig3.svg'));
    const info = await page.evaluate((text) => {
      const doc = new DOMParser().parseFromString(text, 'image/svg+xml');
      return {
        error: doc.querySelector('parsererror')?.textContent || '', width: Number(doc.documentElement.getAttribute('width')),
        jobs: [...doc.querySelectorAll('[data-layer="markers"] g[data-job]')].map((g) => Number(g.getAttribute('data-job'))),
        title: doc.querySelector('title')?.textContent,
      };
    }, svg);
    assert.equal(info.error, '');
    assert.deepEqual(sorted(info.jobs), sorted(p.ids));
    assert.equal(info.title, 'c_b/V against R/S²');
    const [pngDl] = await Promise.all([page.waitForEvent('download'), page.locator('#pl-png').click()]);
    const png = readFileSync(await pngDl.path());
    assert.deepEqual([...png.subarray(0, 8)], [137, 80, 78, 71, 13, 10, 26, 10], 'a PNG file');
    assert.equal(png.readUInt32BE(16), 2 * info.width);

    // A shared URL shows the same plot after a reload.
    const ids = p.ids;
    await mark(page);
    await page.reload();
    p = await drawn(page, 'reloaded');
    assert.deepEqual(p.spec, fig3);
    assert.deepEqual(sorted(p.ids), sorted(ids));

    // The Runs page's "plot these runs" carries its filters.
    await page.goto(`${h.url}/#/runs?class=c&confidence_max=0.8&sort=-confidence`);
    await waitFor(async () => {
      const href = await page.locator('#rt-plot').getAttribute('href');
      const [path, qs] = href.split('?');
      return path === '#/plots' && JSON.stringify(Object.fromEntries([...new URLSearchParams(qs)].sort())) === JSON.stringify({ class: 'c', confidence_max: '0.8' });
    }, { what: 'the Runs page\'s plot link (its filters, not its sort)' });
    await mark(page);
    await page.locator('#rt-plot').click();
    p = await drawn(page, 'from the Runs page');
    const rowsLink = await rowsOf('class=c&confidence_max=0.8');
    assert.equal(p.rows, rowsLink.length);
    assert.deepEqual(sorted(p.ids), sorted(placed(rowsLink, spec0).map((r) => r.id)));
    assert.equal(await page.locator('#rt-confidence_max').inputValue(), '0.8', 'the shared filter form shows the filter');

    // A phone: the page and the plot fit 390 px.
    await page.setViewportSize({ width: 390, height: 844 });
    await mark(page);
    await page.goto(`${h.url}/#/plots?x=S&y=confidence&xscale=log&yscale=linear`);
    await page.reload();
    p = await drawn(page, 'phone');
    assert.equal(p.plotted, all.filter((r) => Number.isFinite(r.confidence)).length);
    assert.ok(await page.evaluate(() => document.documentElement.scrollWidth <= window.innerWidth), 'no sideways scroll at 390 px');
    const cb = await canvasBox(page, '#pl-plot canvas');
    assert.ok(cb.x >= 0 && cb.x + cb.width <= 390, `the plot within the window: ${JSON.stringify(cb)}`);
    await shot(page, '72-plots-390');

    assert.deepEqual(h.pageErrors, []);
  } finally {
    await h.close();
  }
});
