// Hash routes: #/path?key=value. Pages keep their own state in the query (shareable links).

export function parseHash() {
  const h = location.hash.replace(/^#/, '');
  const [path, query = ''] = h.split('?');
  return { path: path || '/map', params: Object.fromEntries(new URLSearchParams(query)) };
}

// Replaces the query of the current page without re-mounting it (no hashchange event).
export function setParams(params) {
  const { path } = parseHash();
  const q = new URLSearchParams(Object.entries(params).filter(([, v]) => v !== '' && v !== null && v !== undefined)).toString();
  history.replaceState(null, '', `#${path}${q ? `?${q}` : ''}`);
}
