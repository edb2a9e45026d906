// Hash router of the dashboard: #/map, #/run/ID, #/runs, #/bands, #/sweeps (query parameters after '?').
// Each page module exports mount(root, params) returning an unmount function (stops its polling).
import { api } from './api.js';
import * as phaseMap from './pages/phasemap.js';
import * as runDetail from './pages/run.js';
import * as bandSpeed from './pages/bands.js';
import * as sweeps from './pages/sweeps.js';
import * as labelAudit from './pages/labels.js';
import * as runTable from './pages/runs.js';
import { parseHash } from './router.js';

const routes = [
  { re: /^\/?(map)?$/, page: phaseMap, nav: 'map' },
  { re: /^\/run\/(\d+)$/, page: runDetail, nav: 'map', id: true },
  { re: /^\/bands$/, page: bandSpeed, nav: 'bands' },
  { re: /^\/sweeps$/, page: sweeps, nav: 'sweeps' },
  { re: /^\/labels$/, page: labelAudit, nav: 'labels' },
  { re: /^\/runs$/, page: runTable, nav: 'runs' },
];

let unmount = null;

function route() {
  const { path, params } = parseHash();
  const r = routes.find((x) => x.re.test(path)) || routes[0];
  if (r.id) params.id = Number(r.re.exec(path)[1]);
  if (unmount) { try { unmount(); } catch (e) { console.error(e); } }
  document.getElementById('tooltip').hidden = true;
  for (const a of document.querySelectorAll('.nav a')) a.classList.toggle('active', a.dataset.page === r.nav);
  const root = document.getElementById('page');
  // A fresh host per page: a late callback of the previous page only touches its detached host.
  const host = document.createElement('div');
  host.className = 'page-host';
  root.replaceChildren(host);
  root.dataset.page = r.page === runDetail ? 'run' : r.nav;
  unmount = r.page.mount(host, params) || null;
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
