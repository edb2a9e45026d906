// Hash router of the dashboard: #/map, #/run/ID, #/runs, #/compare, #/plots, #/bands, #/sweeps,
// #/plan, #/labels (query parameters after '?').
// Each page module exports mount(root, params) returning an unmount function (stops its polling).
import { api } from './api.js';
import { parseHash } from './router.js';

// A page's module (and what only it imports) loads when the page is first shown, so the first
// paint of one page does not wait for the code of the others.
const routes = [
  { re: /^\/?(map)?$/, load: () => import('./pages/phasemap.js'), nav: 'map', name: 'map' },
  { re: /^\/run\/(\d+)$/, load: () => import('./pages/run.js'), nav: 'map', name: 'run', id: true },
  { re: /^\/bands$/, load: () => import('./pages/bands.js'), nav: 'bands', name: 'bands' },
  { re: /^\/sweeps$/, load: () => import('./pages/sweeps.js'), nav: 'sweeps', name: 'sweeps' },
  { re: /^\/labels$/, load: () => import('./pages/labels.js'), nav: 'labels', name: 'labels' },
  { re: /^\/runs$/, load: () => import('./pages/runs.js'), nav: 'runs', name: 'runs' },
  { re: /^\/compare$/, load: () => import('./pages/compare.js'), nav: 'runs', name: 'compare' },
  { re: /^\/plan$/, load: () => import('./pages/plan.js'), nav: 'sweeps', name: 'plan' },
  { re: /^\/plots$/, load: () => import('./pages/plots.js'), nav: 'plots', name: 'plots' },
];

let unmount = null;
let shown = 0;  // the number of the latest navigation: a page whose module arrives late is dropped

async function route() {
  const ticket = ++shown;
  const { path, params } = parseHash();
  const r = routes.find((x) => x.re.test(path)) || routes[0];
  if (r.id) params.id = Number(r.re.exec(path)[1]);
  if (unmount) { try { unmount(); } catch (e) { console.error(e); } }
  unmount = null;
  document.getElementById('tooltip').hidden = true;
  for (const a of document.querySelectorAll('.nav a')) a.classList.toggle('active', a.dataset.page === r.nav);
  const root = document.getElementById('page');
  // A fresh host per page: a late callback of the previous page only touches its detached host.
  const host = document.createElement('div');
  host.className = 'page-host';
  root.replaceChildren(host);
  root.dataset.page = r.name;
  const failed = (e) => {
    if (ticket === shown) host.innerHTML = '<p class="error">This page could not be loaded; reload to try again.</p>';
    console.error(e);
  };
  let page;
  try {
    page = await r.load();
  } catch (e) {
    failed(e);
    return;
  }
  if (ticket !== shown) return;
  try {
    unmount = page.mount(host, params) || null;
  } catch (e) {
    failed(e);
  }
  window.scrollTo(0, 0);
}

async function health() {
  const el = document.getElementById('server-status');
  try {
    const h = await api.health();
    const j = h.jobs || {};
    el.className = 'server-status ok';
    el.textContent = `engine ${h.engine_version} · ${j.running || 0} running · ${j.queued || 0} queued`;
    el.title = `source ${h.source_revision}`;
  } catch {
    el.className = 'server-status down';
    el.textContent = 'server unreachable';
  }
}

window.addEventListener('hashchange', route);
route();
health();
setInterval(() => { if (!document.hidden) health(); }, 5000);
