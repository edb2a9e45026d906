// The Plots page (#/plots, web/js/pages/plots.js) at 100 000 runs: its first paint and the time
// a filter, a saved view, an axis or a scale takes, in Debian's headless chromium against a real
// compaction-server on a database filled by jobs_table_bench.py (--keep FILLED.db), as
// runs_page_bench.mjs measures the Runs page. A benchmark, not a test.
//
//   load    a fresh document with the browser's cache off (CDP Network.setCacheDisabled): when
//           the last module of web/js came, when the page asked for its GET /jobs?format=csv,
//           the first markers drawn (the first 20 000 rows of a larger set, drawn while the
//           rest come: window.__dashboard.firstPlot), the plot of every row drawn (the page's
//           hook; all in ms since navigation start), and of it the
//           CSV request (request to response end), its split into lines and the render (the
//           columns the plot needs read from the lines, axes, colours, markers on the canvas),
//           and the largest contentful paint
//   change  after the load, each action timed from the event to the first markers (a set of
//           over 20 000 rows), to the plot drawn (a MutationObserver on the page's render
//           counter) and to the next animation frame:
//           a class chip (class=c: the rows asked again), a confidence bound (confidence_max=0.6),
//           the Fig. 3 view (class=a,b, colour N_r), the y axis (N_r: a redraw of the rows the
//           page has), the y scale (linear), "Clear filters" (every row again)
//
// usage: node bench/dashboard/feature_plot_bench.mjs --db FILLED.db [--loads 7]
//                     [--accept-encoding identity] [--out bench/results/feature_plot.md]
// --accept-encoding replaces the browser's Accept-Encoding (CDP Network.setExtraHTTPHeaders):
// identity measures the page with the CSV as the server writes it, uncompressed; without it
// chromium's own "gzip, deflate, br, zstd" gets gzip (the server never answers brotli).
// The database is copied into a temporary folder (the server may write to it). Needs
// scripts/install-browser-deps.sh (chromium, tests/browser/node_modules).
import { copyFileSync, writeFileSync } from 'node:fs';
import { cpus, loadavg } from 'node:os';
import { execFileSync } from 'node:child_process';
import { join, relative } from 'node:path';
import { Harness, REPO, waitFor } from '../../tests/browser/lib/harness.mjs';
import { f0, median, p90, parseArgs } from './stats.mjs';

const args = parseArgs(process.argv.slice(2));
if (!args.db) { console.error('usage: feature_plot_bench.mjs --db FILLED.db [--loads 7] [--out FILE]'); process.exit(2); }
const LOADS = Number(args.loads || 7);
const OUT = args.out || join(REPO, 'bench/results/feature_plot.md');

// Runs in the page: times an action until the plot is drawn again.
function timeAction({ kind, selector, value }) {
  const root = document.querySelector('.page-host');
  const el = document.querySelector(selector);
  return new Promise((resolve) => {
    let t0 = 0;
    const mo = new MutationObserver(() => {
      const dom = performance.now() - t0;
      mo.disconnect();
      const r = window.__dashboard.plots;
      const failed = r.error ? NaN : 0; // an answer that did not come: no time
      const fp = window.__dashboard.firstPlot;
      const first = fp && fp.at > t0 ? fp.at - t0 : NaN; // the first rows drawn while the rest came
      requestAnimationFrame(() => resolve({ dom: dom + failed, frame: performance.now() - t0 + failed, render: r.renderMs ?? NaN, parse: r.parseMs ?? 0, rows: r.rows, plotted: r.plotted, query: r.query, first }));
    });
    mo.observe(root, { attributes: true, attributeFilter: ['data-plot-renders'] });
    setTimeout(() => { mo.disconnect(); resolve({ dom: NaN, frame: NaN, render: NaN, parse: NaN, rows: NaN, plotted: NaN, query: 'no answer', first: NaN }); }, 30000);
    t0 = performance.now();
    if (kind === 'change') { el.value = value; el.dispatchEvent(new Event('change', { bubbles: true })); } else el.click();
  });
}

const ACTIONS = [
  ['class chip: class=c', { kind: 'click', selector: '.rt-chips[data-name="class"] input[value="c"]' }],
  ['confidence bound: + confidence_max=0.6', { kind: 'change', selector: '#rt-confidence_max', value: '0.6' }],
  ['Fig. 3 view (class=a,b, colour N_r)', { kind: 'click', selector: '.pl-view[data-view="fig3"]' }],
  ['y axis: N_r (redraw)', { kind: 'change', selector: '#pl-y', value: 'n_reflections' }],
  ['y scale: linear (redraw)', { kind: 'change', selector: '#pl-yscale', value: 'linear' }],
  ['clear filters', { kind: 'click', selector: '#pl-clear' }],
];

const h = new Harness('plots-bench');
const load0 = loadavg()[0];
try {
  copyFileSync(args.db, join(h.dir, 'compaction.db'));
  await h.startServer();
  const all = (await h.api('/jobs?format=table&limit=1')).json.total;
  const page = await h.browser({ width: 1440, height: 900 });
  const cdp = await page.context().newCDPSession(page);
  await page.addInitScript(() => {
    window.__lcp = 0;
    new PerformanceObserver((l) => { for (const e of l.getEntries()) window.__lcp = e.startTime; }).observe({ type: 'largest-contentful-paint', buffered: true });
  });
  const loads = { first: [], drawn: [], csv: [], parse: [], render: [], lcp: [], modules: [], asked: [], bytes: [] };
  let nModules = 0, first = null;
  const changes = Object.fromEntries(ACTIONS.map(([name]) => [name, { first: [], dom: [], frame: [], render: [], parse: [], rows: 0, plotted: 0, query: '' }]));
  await cdp.send('Network.enable');
  await cdp.send('Network.setCacheDisabled', { cacheDisabled: true });
  if (args['accept-encoding']) await cdp.send('Network.setExtraHTTPHeaders', { headers: { 'Accept-Encoding': args['accept-encoding'] } });
  for (let i = 0; i < LOADS + 1; i++) { // the first load warms the server's page cache; not counted
    await page.goto('about:blank');
    await page.goto(`${h.url}/#/plots`);
    await waitFor(() => page.evaluate(() => window.__dashboard?.plots?.plotted !== undefined), { timeoutMs: 60000, what: 'the first plot' });
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => setTimeout(r, 50))));
    const m = await page.evaluate(() => {
      const res = performance.getEntriesByType('resource').find((e) => e.name.includes('/api/v1/jobs?') && e.name.includes('format=csv'));
      const js = performance.getEntriesByType('resource').filter((e) => e.name.includes('/js/'));
      const p = window.__dashboard.plots;
      return {
        first: window.__dashboard.firstPlot?.at ?? NaN, drawn: p.error ? NaN : p.at, parse: p.parseMs ?? NaN, render: p.renderMs ?? NaN, error: p.error?.message, lcp: window.__lcp, csv: res ? res.responseEnd - res.requestStart : NaN,
        modules: Math.max(...js.map((e) => e.responseEnd)), asked: res ? res.startTime : NaN, bytes: res ? res.encodedBodySize : NaN,
        nModules: js.length, rows: p.rows, plotted: p.plotted, spec: p.spec,
      };
    });
    if (m.error) console.error(`# load ${i}: ${m.error}`);
    if (i > 0) for (const k of Object.keys(loads)) loads[k].push(m[k]);
    nModules = m.nModules;
    first = m;
    for (const [name, action] of ACTIONS) {
      const r = await page.evaluate(timeAction, action);
      const c = changes[name];
      if (i > 0) { c.first.push(r.first); c.dom.push(r.dom); c.frame.push(r.frame); c.render.push(r.render); c.parse.push(r.parse); }
      c.rows = r.rows; c.plotted = r.plotted; c.query = r.query;
    }
  }
  const rev = execFileSync('git', ['-C', REPO, 'rev-parse', '--short', 'HEAD'], { encoding: 'utf8' }).trim();
  const row = (what, k, unit = 'ms') => `| ${what} | ${f0(median(loads[k]))} ${unit} | ${f0(p90(loads[k]))} ${unit} |`;
  const lines = [
    '# The Plots page at 100 000 runs (first paint, filter, view, axis)', '',
    `Made by \`node bench/dashboard/feature_plot_bench.mjs --db ${args.db} --loads ${LOADS}${args['accept-encoding'] ? ` --accept-encoding ${args['accept-encoding']}` : ''}\` at ${rev} (with the Plots page's files as measured), ${new Date().toISOString().slice(0, 10)}, ` +
      `on ${cpus().length} cores shared with other work: load average ${load0.toFixed(1)} before, ${loadavg()[0].toFixed(1)} after (1 min). ` +
      `The database: ${all.toLocaleString('en')} runs, filled by \`bench/dashboard/jobs_table_bench.py\`'s fill (its report: [jobs_table.md](jobs_table.md)). ` +
      `Headless chromium 1440 x 900, a real compaction-server on loopback (\`--web-dir web/\`).`, '',
    `Goals (the issue): first paint under 500 ms, a filter under 200 ms. ${LOADS} loads, median and 90th percentile. ` +
      `The first plot: ${first.spec.y} against ${first.spec.x} (${first.spec.yscale}/${first.spec.xscale}), coloured by ${first.spec.color}: ` +
      `${first.plotted.toLocaleString('en')} of ${first.rows.toLocaleString('en')} runs plotted.`, '',
    '| load of `#/plots` (every run, one GET /jobs?format=csv) | median | p90 |', '|---|---|---|',
    row(`the last of the ${nModules} modules of web/js loaded`, 'modules'), row('GET /jobs?format=csv asked', 'asked'),
    row('the first markers drawn: the first 20 000 rows, while the rest come (since navigation start)', 'first'),
    row('the plot drawn, every row (since navigation start)', 'drawn'), row('of which the CSV (request to response end)', 'csv'),
    row('of which its split into lines', 'parse'), row('of which the render (the columns it needs read, axes, colours, markers)', 'render'),
    row('largest contentful paint', 'lcp'), `| the CSV's size | ${(median(loads.bytes) / 1e6).toFixed(1)} MB | |`,
    '',
    `| action, one after the other on the loaded page (${LOADS} times) | query | rows, plotted | to the first markers (median; a set of over 20 000 rows) | to the plot drawn (median, p90) | to the next frame (median, p90) | split, render (median) |`, '|---|---|---|---|---|---|---|',
    ...ACTIONS.map(([name]) => {
      const c = changes[name];
      const fm = c.first.filter(Number.isFinite);
      return `| ${name} | \`${c.query}\` | ${c.rows.toLocaleString('en')}, ${c.plotted.toLocaleString('en')} | ${fm.length ? `${f0(median(fm))} ms` : '—'} | ${f0(median(c.dom))} ms, ${f0(p90(c.dom))} ms | ${f0(median(c.frame))} ms, ${f0(p90(c.frame))} ms | ${median(c.parse).toFixed(0)} ms, ${median(c.render).toFixed(0)} ms |`;
    }),
    '',
  ];
  const text = lines.join('\n');
  writeFileSync(OUT, text);
  console.log(text);
  console.log(`# wrote ${relative(process.cwd(), OUT)}`);
} finally {
  await h.close();
}
