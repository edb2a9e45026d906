// The Runs page (#/runs, web/js/pages/runs.js) at 100 000 runs: its first paint and the time
// a filter, a sort or a page takes, in Debian's headless chromium against a real
// compaction-server on a database filled by jobs_table_bench.py (--keep FILLED.db). A benchmark,
// not a test.
//
//   load    a fresh document with the browser's cache off (CDP Network.setCacheDisabled: a
//           first visit; a later one revalidates web/'s files by their ETags): when
//           the last module of web/js came, when the page asked for its GET /jobs, the table's
//           rows in the DOM (the page's hook), the largest contentful paint (all in ms since
//           navigation start), and that GET /jobs from its request to its response's end
//   change  after the load, each action timed from the event to the rows in the DOM (a
//           MutationObserver on the page's answer counter) and to the next animation frame:
//           a class chip (class=c), a confidence bound (confidence_max=0.6, its change event,
//           not the typing delay), a sort by a column's head (confidence, then -confidence),
//           the next page by its cursor, "Clear filters"
//
// usage: node bench/dashboard/runs_page_bench.mjs --db FILLED.db [--loads 7]
//                                                 [--out bench/results/runs_page.md]
// The database is copied into a temporary folder (the server may write to it). Needs
// scripts/install-browser-deps.sh (chromium, tests/browser/node_modules).
import { copyFileSync, writeFileSync } from 'node:fs';
import { cpus, loadavg } from 'node:os';
import { execFileSync } from 'node:child_process';
import { join, relative } from 'node:path';
import { Harness, REPO, waitFor } from '../../tests/browser/lib/harness.mjs';
import { f0, median, p90, parseArgs } from './stats.mjs';

const args = parseArgs(process.argv.slice(2));
if (!args.db) { console.error('usage: runs_page_bench.mjs --db FILLED.db [--loads 7] [--out FILE]'); process.exit(2); }
const LOADS = Number(args.loads || 7);
const OUT = args.out || join(REPO, 'bench/results/runs_page.md');


// Runs in the page: times an action until the table shows its answer.
function timeAction({ kind, selector, value }) {
  const root = document.querySelector('.page-host');
  const el = document.querySelector(selector);
  return new Promise((resolve) => {
    let t0 = 0;
    const mo = new MutationObserver(() => {
      const dom = performance.now() - t0;
      mo.disconnect();
      const r = window.__dashboard.runs;
      requestAnimationFrame(() => resolve({ dom, frame: performance.now() - t0, render: r.renderMs, total: r.total, query: r.query }));
    });
    mo.observe(root, { attributes: true, attributeFilter: ['data-runs-renders'] });
    setTimeout(() => { mo.disconnect(); resolve({ dom: NaN, frame: NaN, render: NaN, total: NaN, query: 'no answer (a disabled control?)' }); }, 20000);
    t0 = performance.now();
    if (kind === 'change') { el.value = value; el.dispatchEvent(new Event('change', { bubbles: true })); } else el.click();
  });
}

const ACTIONS = [
  ['class chip: class=c', { kind: 'click', selector: '.rt-chips[data-name="class"] input[value="c"]' }],
  ['confidence bound: + confidence_max=0.6', { kind: 'change', selector: '#rt-confidence_max', value: '0.6' }],
  ['sort by confidence (ascending)', { kind: 'click', selector: '#rt-table th[data-col="confidence"] button' }],
  ['sort by -confidence', { kind: 'click', selector: '#rt-table th[data-col="confidence"] button' }],
  ['next page (cursor)', { kind: 'click', selector: '#rt-next' }],
  ['clear filters (sort -confidence stays)', { kind: 'click', selector: '#rt-clear' }],
];

const h = new Harness('runs-bench');
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
  const loads = { off: { table: [], render: [], lcp: [], server: [], modules: [], asked: [] } };
  let nModules = 0;
  const changes = Object.fromEntries(ACTIONS.map(([name]) => [name, { dom: [], frame: [], render: [], total: 0, query: '' }]));
  await cdp.send('Network.setCacheDisabled', { cacheDisabled: true });
  for (let i = 0; i < LOADS + 1; i++) { // the first load warms the server's page cache; not counted
    const mode = 'off';
    await page.goto('about:blank');
    await page.goto(`${h.url}/#/runs`);
    await waitFor(() => page.evaluate(() => window.__dashboard?.runs?.total !== undefined), { timeoutMs: 30000, what: 'the first page' });
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => setTimeout(r, 50))));
    const m = await page.evaluate(() => {
      const res = performance.getEntriesByType('resource').find((e) => e.name.includes('/api/v1/jobs?') && e.name.includes('format=table'));
      const js = performance.getEntriesByType('resource').filter((e) => e.name.includes('/js/'));
      return {
        table: window.__dashboard.runs.at, render: window.__dashboard.runs.renderMs, lcp: window.__lcp, server: res ? res.responseEnd - res.requestStart : NaN,
        modules: Math.max(...js.map((e) => e.responseEnd)), asked: res ? res.startTime : NaN, nModules: js.length,
      };
    });
    if (i > 0) for (const k of Object.keys(loads[mode])) loads[mode][k].push(m[k]);
    nModules = m.nModules;
    for (const [name, action] of ACTIONS) {
      const r = await page.evaluate(timeAction, action);
      if (i > 0) { changes[name].dom.push(r.dom); changes[name].frame.push(r.frame); changes[name].render.push(r.render); }
      changes[name].total = r.total; changes[name].query = r.query.replace(/cursor=[^&]+/, 'cursor=…');
    }
  }
  const rev = execFileSync('git', ['-C', REPO, 'rev-parse', '--short', 'HEAD'], { encoding: 'utf8' }).trim();
  const lines = [
    '# The Runs page at 100 000 runs (first paint, filter, sort, page)', '',
    `Made by \`node bench/dashboard/runs_page_bench.mjs --db ${args.db} --loads ${LOADS}\` at ${rev}, ${new Date().toISOString().slice(0, 10)}, ` +
      `on ${cpus().length} cores shared with other work: load average ${load0.toFixed(1)} before, ${loadavg()[0].toFixed(1)} after (1 min). ` +
      `The database: ${all.toLocaleString('en')} runs, filled by \`bench/dashboard/jobs_table_bench.py\`'s fill (its report: [jobs_table.md](jobs_table.md)). ` +
      `Headless chromium 1440 x 900, a real compaction-server on loopback (\`--web-dir web/\`).`, '',
    `Goals (issue 49): first paint under 500 ms, a filter under 200 ms. ${LOADS} loads, median and 90th percentile.`, '',
    '| load of `#/runs` (100 rows a page, id order) | median | p90 |', '|---|---|---|',
    ...[[`the last of the ${nModules} modules of web/js loaded`, 'modules'], ['GET /jobs?format=table asked', 'asked'],
      ['rows in the DOM (since navigation start)', 'table'], ['of which the page\'s render of the rows', 'render'], ['largest contentful paint', 'lcp'], ['its GET /jobs?format=table (request to response end)', 'server']]
      .map(([what, k]) => `| ${what} | ${f0(median(loads.off[k]))} ms | ${f0(p90(loads.off[k]))} ms |`),
    '',
    `| action, one after the other on the loaded page (${LOADS} times) | query it sends | rows | to the DOM (median, p90) | to the next frame (median, p90) | the page's render of the rows (median) |`, '|---|---|---|---|---|---|',
    ...ACTIONS.map(([name]) => {
      const c = changes[name];
      return `| ${name} | \`${c.query}\` | ${c.total.toLocaleString('en')} | ${f0(median(c.dom))} ms, ${f0(p90(c.dom))} ms | ${f0(median(c.frame))} ms, ${f0(p90(c.frame))} ms | ${median(c.render).toFixed(1)} ms |`;
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
