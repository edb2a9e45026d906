// The REST API of compaction-server (/api/v1, see server/openapi.yaml), as small async functions.
// Reading needs no token; creating and cancelling sweeps send the submit token when one is stored.

const BASE = '/api/v1';
const TOKEN_KEY = 'compaction.submitToken';

export class ApiError extends Error {
  // status: HTTP status; field/message/details: the server's {"error": {...}} body.
  constructor(status, body) {
    const e = (body && body.error) || {};
    super(e.message || `HTTP ${status}`);
    this.status = status;
    this.field = e.field || '';
    this.details = e.details || (e.field !== undefined ? [{ field: e.field, message: e.message }] : []);
  }
}

export function submitToken() {
  try { return localStorage.getItem(TOKEN_KEY) || ''; } catch { return ''; }
}
export function setSubmitToken(t) {
  try { t ? localStorage.setItem(TOKEN_KEY, t) : localStorage.removeItem(TOKEN_KEY); } catch { /* private mode */ }
}

// The last answer of each GET that came with an ETag (the phase map, its regions, the sweeps,
// the run table, a plan): polling asks with If-None-Match and a 304 reuses the answer, so an
// unchanged map costs the server no answer and the page no parse. The oldest entry goes past
// MAX_REMEMBERED.
const remembered = new Map(); // path -> { etag, json }
const MAX_REMEMBERED = 32;

function remember(path, etag, json) {
  remembered.delete(path);
  remembered.set(path, { etag, json });
  if (remembered.size > MAX_REMEMBERED) remembered.delete(remembered.keys().next().value);
}

async function request(method, path, body) {
  const headers = {};
  if (body !== undefined) headers['Content-Type'] = 'application/json';
  const token = submitToken();
  if (method !== 'GET' && token) headers.Authorization = `Bearer ${token}`;
  const known = method === 'GET' ? remembered.get(path) : undefined;
  if (known) headers['If-None-Match'] = known.etag;
  const res = await fetch(BASE + path, {
    method, headers, body: body === undefined ? undefined : JSON.stringify(body), cache: 'no-store',
  });
  if (res.status === 304 && known) return known.json;
  const text = await res.text();
  let json = null;
  try { json = text ? JSON.parse(text) : null; } catch { json = null; }
  if (!res.ok) throw new ApiError(res.status, json);
  const etag = res.headers.get('ETag');
  if (method === 'GET' && etag) remember(path, etag, json);
  return json;
}

export const api = {
  health: () => request('GET', '/health'),
  presets: () => request('GET', '/presets'),
  limits: () => request('GET', '/limits'),
  // The runs at phi and their points (summaries); sweep, cpu: one sweep, one grid, or none;
  // geometry: the runs of that geometry (none: the server's default, the 2D pseudo-1D column).
  phaseMap: (phi, sweep, cpu, geometry) => request('GET', `/phase-map?${new URLSearchParams({
    phi, ...(sweep ? { sweep } : {}), ...(cpu ? { cells_per_unit: cpu } : {}), ...(geometry ? { geometry } : {}) })}`),
  // The classes the labelled runs predict over the map (its background); cpu: one grid or none.
  regions: (phi, sweep, cpu, grid, geometry) => request('GET', `/phase-map/regions?${new URLSearchParams({
    phi, ...(sweep ? { sweep } : {}), ...(cpu ? { cells_per_unit: cpu } : {}), ...(grid ? { grid } : {}),
    ...(geometry ? { geometry } : {}) })}`),
  sweeps: (limit = 200) => request('GET', `/sweeps?limit=${limit}`),
  sweep: (id) => request('GET', `/sweeps/${id}`),
  // An adaptive sweep's plan: state, runs and CPU-hours against its budgets, levels, next runs.
  sweepPlan: (id, limit = 0) => request('GET', `/sweeps/${id}/plan?limit=${limit}`),
  createSweep: (body) => request('POST', '/sweeps', body),
  // What a sweep body would cost (jobs, CPU time, finish on the workers connected); creates nothing.
  estimateSweep: (body) => request('POST', '/sweeps/estimate', body),
  cancelSweep: (id) => request('POST', `/sweeps/${id}/cancel`, {}),
  job: (id) => request('GET', `/jobs/${id}`),
  jobs: (query) => request('GET', `/jobs?${new URLSearchParams(query)}`),
  artifacts: (id) => request('GET', `/jobs/${id}/artifacts`),
  labels: (id) => request('GET', `/jobs/${id}/label`),
  setLabel: (id, body) => request('PUT', `/jobs/${id}/label`, body),
  clearLabel: (id, body) => request('DELETE', `/jobs/${id}/label`, body),
  labelAudit: (limit = 200) => request('GET', `/labels/audit?limit=${limit}`),
  exportUrl: (id, format) => `${BASE}/sweeps/${id}/export?format=${format}`,
  // The file another server imports (docs/service.md, "Merging maps"); artifacts: 'run_page'
  // (with the runs' files) or 'none' (results and provenance only).
  archiveUrl: (id, artifacts) => `${BASE}/sweeps/${id}/export?format=archive&artifacts=${artifacts}`,
  // The size in bytes of the file a GET of url saves, from a HEAD: its X-File-Size (the
  // server's, as Content-Length is the compressed body's when gzip is accepted), else its
  // Content-Length; null when neither is given.
  downloadSize: async (url) => {
    const res = await fetch(url, { method: 'HEAD', cache: 'no-store' });
    if (!res.ok) throw new ApiError(res.status, null);
    for (const h of ['X-File-Size', 'Content-Length']) {
      const n = Number(res.headers.get(h));
      if (res.headers.has(h) && Number.isFinite(n)) return n;
    }
    return null;
  },
  artifactUrl: (id, name) => `${BASE}/jobs/${id}/artifacts/${encodeURIComponent(name)}`,
};

// Fetches an artifact as an ArrayBuffer (null when the job has no such file).
export async function fetchArtifact(id, name, as = 'arrayBuffer') {
  const res = await fetch(api.artifactUrl(id, name), { cache: 'no-store' });
  if (res.status === 404) return null;
  if (!res.ok) throw new ApiError(res.status, null);
  return as === 'text' ? res.text() : res.arrayBuffer();
}
