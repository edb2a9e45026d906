// Phase-map render benchmark: loads the dashboard's phase map in Debian's headless chromium with
// 10,000 points and measures how long drawing them takes. A benchmark, not a test.
//
// The data are FABRICATED: no server runs; the page's requests are answered inside the browser
// (playwright's page.route) with web/ from disk and a synthetic /api/v1/phase-map of a 100 x 100
// log grid over S in [1e-4, 1] and R in [1e-6, 1e-1] whose classes follow a made-up rule shaped
// like the paper's map, with some queued, running, failed and unstable points. It measures
// rendering (and, separately, fetch + JSON parse + render), not the server.
//
// usage: node bench/dashboard/render_bench.mjs [--points 10000] [--loads 7] [--rerenders 15]
//                                              [--out bench/results/dashboard_render.md]
// Needs scripts/install-browser-deps.sh (chromium, tests/browser/node_modules).
import { readFileSync, writeFileSync, mkdirSync } from 'node:fs';
import { cpus } from 'node:os';
import { execFileSync } from 'node:child_process';
import { extname, join, relative } from 'node:path';
import { Harness, REPO, WEB_DIR, CHROMIUM, artifactsDir } from '../../tests/browser/lib/harness.mjs';

const args = Object.fromEntries(process.argv.slice(2).reduce((a, x, i, all) => (x.startsWith('--') ? [...a, [x.slice(2), all[i + 1]]] : a), []));
const N = Number(args.points || 10000);
const LOADS = Number(args.loads || 7);
const RERENDERS = Number(args.rerenders || 15);
const OUT = args.out || join(REPO, 'bench/results/dashboard_render.md');
const ORIGIN = 'http://dashboard.bench';

function synthetic(n) {
  let seed = 12345;
  const rand = () => ((seed = (seed * 1103515245 + 12345) % 2147483648) / 2147483648);
  const side = Math.ceil(Math.sqrt(n));
  const points = [];
  let id = 1;
  for (let i = 0; i < side && points.length < n; i++) {
    for (let j = 0; j < side && points.length < n; j++) {
      const S = 10 ** (-4 + (4 * i) / (side - 1)), R = 10 ** (-6 + (5 * j) / (side - 1));
      const ratio = R / (S * S);
      // Made-up regions, loosely like Fig. 2: buckling at high R, explosive at high S and low R,
      // crossing at high S and R, reflecting bands where R/S^2 is large, else non-reflecting.
      let cls = R > 0.06 ? 'f' : S > 0.05 && R < 1e-4 ? 'e' : S > 0.02 && R > 5e-3 ? 'c' : ratio > 1e3 && S < 2e-3 ? 'd' : ratio > 10 ? 'b' : 'a';
      const k = Math.floor(rand() * 97); // ~1 % each of queued, running, failed, unstable, unlabelled
      const state = k === 0 ? 'queued' : k === 1 ? 'running' : k === 2 ? 'failed' : 'succeeded';
      const status = state === 'succeeded' ? (k === 3 ? 'unstable' : 'ok') : null;
      if (k === 4) cls = null;
      points.push({
        S, R, phi: 0.4, state, status, class: state === 'succeeded' && status === 'ok' ? cls : null,
        confidence: 0.6 + 0.4 * ((id * 7919) % 100) / 100, runner_up: 'b', n_reflections: cls === 'b' ? Math.min(6, Math.floor(Math.log10(ratio))) : 0,
        band_speed_ratio: cls === 'a' ? 1 / 0.6 : cls === 'b' ? 1.6 * ratio ** 0.15 : null, job_id: id, cells_per_unit: 8, eps_end: 0.6,
        progress_eps: state === 'running' ? 0.3 : null,
      });
      id++;
    }
  }
  return { phi: 0.4, points };
}

const TYPES = { '.html': 'text/html', '.js': 'text/javascript', '.css': 'text/css', '.svg': 'image/svg+xml', '.png': 'image/png' };
const median = (a) => { const s = [...a].sort((x, y) => x - y); const m = s.length >> 1; return s.length % 2 ? s[m] : (s[m - 1] + s[m]) / 2; };
const f1 = (v) => v.toFixed(1);

const data = JSON.stringify(synthetic(N));
const h = new Harness('bench');
const results = { load: [], firstRender: [], rerender: [], frame: [], hover: [] };
let version = '';
try {
  const page = await h.browser({ width: 1440, height: 1000 });
  version = await page.context().browser()?.version?.() ?? '';
  await page.route(`${ORIGIN}/**`, async (route) => {
    const url = new URL(route.request().url());
    const p = url.pathname;
    if (p === '/api/v1/phase-map') return route.fulfill({ contentType: 'application/json', body: data });
    if (p === '/api/v1/sweeps') return route.fulfill({ contentType: 'application/json', body: JSON.stringify({ sweeps: [{ id: 1, name: 'bench', request: { phi: 0.4 }, counts: {}, state: 'active' }], total: 1 }) });
    if (p === '/api/v1/presets') return route.fulfill({ contentType: 'application/json', body: JSON.stringify({ presets: [{ name: 'fast', cells_per_unit: 8 }], default: 'default' }) });
    if (p === '/api/v1/health') return route.fulfill({ contentType: 'application/json', body: JSON.stringify({ engine_version: 'bench', jobs: {} }) });
    if (p.startsWith('/api/')) return route.fulfill({ status: 404, contentType: 'application/json', body: '{"error":{"field":"path","message":"bench"}}' });
    const file = join(WEB_DIR, p === '/' ? 'index.html' : p);
    if (relative(WEB_DIR, file).startsWith('..')) return route.fulfill({ status: 404, body: '' });
    try { return route.fulfill({ contentType: TYPES[extname(file)] || 'application/octet-stream', body: readFileSync(file) }); } catch { return route.fulfill({ status: 404, body: '' }); }
  });
  for (let i = 0; i < LOADS; i++) {
    await page.goto('about:blank'); // a real load each time, not a same-document hash change
    await page.goto(`${ORIGIN}/#/map?phi=0.4`, { waitUntil: 'load' });
    await page.waitForFunction((n) => window.__dashboard?.phaseMap?.count === n, N, { timeout: 60000 });
    const r = await page.evaluate(() => ({ ms: window.__dashboard.phaseMap.renderMs, at: window.__dashboard.renderedAt }));
    results.firstRender.push(r.ms);
    results.load.push(r.at); // navigation start to the 10,000 points drawn (fetch, parse, render)
  }
  // Re-renders (what a live update or a control change costs), by toggling an overlay.
  // The change handler renders synchronously; "to the next frame" includes the browser's paint.
  for (let i = 0; i < RERENDERS; i++) {
    const r = await page.evaluate(async () => {
      const box = document.querySelector('#map-buckling');
      const t0 = performance.now();
      box.click();
      const t1 = performance.now();
      await new Promise((res) => requestAnimationFrame(() => setTimeout(res, 0)));
      return { render: window.__dashboard.renders.at(-1), handler: t1 - t0, frame: performance.now() - t0 };
    });
    results.rerender.push(r.render);
    results.frame.push(r.frame);
  }
  // Hover: the nearest-point search and tooltip of one mousemove, timed inside the page.
  results.hover = await page.evaluate(() => {
    const c = document.querySelector('#map-plot canvas');
    const r = c.getBoundingClientRect();
    const out = [];
    for (let i = 0; i < 50; i++) {
      const t0 = performance.now();
      c.dispatchEvent(new MouseEvent('mousemove', { clientX: r.left + ((i * 37) % r.width), clientY: r.top + ((i * 53) % r.height), bubbles: true }));
      out.push(performance.now() - t0);
    }
    return out;
  });
  const shot = join(artifactsDir(), 'bench-phase-map-10000.png');
  await page.screenshot({ path: shot, fullPage: true });
  console.log(`screenshot ${shot}`);
  // The band-speed page with the same fabricated points (a picture, not timed).
  await page.goto(`${ORIGIN}/#/bands?phi=0.4`);
  await page.waitForFunction(() => Number(document.querySelector('#bands-plot canvas')?.dataset.count) > 0, null, { timeout: 30000 });
  const shot2 = join(artifactsDir(), 'bench-band-speed.png');
  await page.screenshot({ path: shot2, fullPage: true });
  console.log(`screenshot ${shot2}`);
} finally {
  await h.close();
}

const cpu = cpus()[0]?.model?.trim() || 'unknown CPU';
let chromiumVersion = version;
try { chromiumVersion = execFileSync(CHROMIUM, ['--version'], { encoding: 'utf8' }).trim(); } catch { /* keep the CDP version */ }
const row = (name, a) => `| ${name} | ${a.length} | ${f1(median(a))} | ${f1(Math.min(...a))} | ${f1(Math.max(...a))} |`;
const md = `# Phase-map render benchmark (dashboard)

${N.toLocaleString('en')} synthetic points on the phase map (web/js/pages/phasemap.js) in headless chromium.
The data are fabricated (a 100 x 100 log grid with made-up classes, ~3 % queued, running, failed
or unstable) and served inside the browser: this measures the dashboard's rendering, not the
server. Times in milliseconds, measured in the page with performance.now().

Command: \`node bench/dashboard/render_bench.mjs --points ${N} --loads ${LOADS} --rerenders ${RERENDERS}\`
Machine: ${cpu}, ${cpus().length} cores (shared with other builds while it ran); ${chromiumVersion}; node ${process.version};
device pixel ratio 1, viewport 1440 x 1000, software rendering (--disable-gpu).

| what | runs | median ms | min ms | max ms |
|---|---|---|---|---|
${row('render: axes, 10,000 markers, legend (first render of a page load)', results.firstRender)}
${row('re-render on a control change or a live update', results.rerender)}
${row('re-render to the next painted frame', results.frame)}
${row('page load to all points drawn (navigation, modules, fetch, JSON parse, render)', results.load)}
${row('one hover: nearest-point search and tooltip', results.hover)}

Written by the command above on ${new Date().toISOString().slice(0, 10)}.
`;
mkdirSync(join(OUT, '..'), { recursive: true });
writeFileSync(OUT, md);
console.log(md);
console.log(`median render of ${N} points: ${f1(median(results.firstRender))} ms (wrote ${OUT})`);
