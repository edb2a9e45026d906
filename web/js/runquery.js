// The Runs page's query (js/pages/runs.js) as text: the filters, sort, page size and cursor of
// GET /api/v1/jobs (docs/service.md, "The run table"), under the API's own parameter names, so
// the page's URL, the table's request and the CSV link hold one and the same query. Which
// parameters, columns and sort keys there are comes from GET /limits (jobs), never from here.

// The parameters that page or shape an answer; every other parameter of limits.jobs.parameters
// is a filter.
const PAGE_PARAMS = ['sort', 'limit', 'offset', 'cursor', 'format', 'columns'];
// Older or shorter names a link may use for a filter.
const ALIASES = { cls: 'class' };
export const LETTERS = ['a', 'b', 'c', 'd', 'e', 'f'];
export const JOB_STATES = ['queued', 'running', 'succeeded', 'failed', 'cancelled'];

// URLSearchParams writes a comma as %2C; a list reads better with its commas (both mean the same).
const text = (s) => s.toString().replace(/%2C/g, ',');

export function filterNames(limits) {
  return limits.jobs.parameters.filter((p) => !PAGE_PARAMS.includes(p));
}

// The ranges NAME_min / NAME_max, by NAME, in the server's order.
export function rangeNames(limits) {
  return limits.jobs.parameters.filter((p) => p.endsWith('_min')).map((p) => p.slice(0, -4));
}

// The columns the table shows unless its query names others (columns=): the run, its
// parameters and numerics, and the classifier's verdict. The classifier's other features and
// the run's measures, the rest of GET /limits' jobs.columns, are a choice away.
export const DEFAULT_COLUMNS = [
  'id', 'sweep', 'state', 'S', 'R', 'phi', 'preset', 'cells_per_unit', 'cells_per_strut', 'seed', 'point_id',
  'status', 'class', 'confidence', 'runner_up', 'n_reflections', 'band_speed_ratio', 'human_label', 'label',
  'source_database', 'source_job', 'geometry',
];

// A link's own columns, the run's id first where it left it out (its cell opens the run).
const withId = (own) => (own.includes('id') ? own : ['id', ...own]);

// The columns of the query's table and CSV, in its order: its own (withId), else the default
// ones the server has.
export function shownColumns(q, limits) {
  if (!q.columns) return DEFAULT_COLUMNS.filter((c) => limits.jobs.columns.includes(c));
  return withId(q.columns.split(','));
}

// A choice of columns as the query holds it: in the server's order, '' for the default set.
export function columnsParam(chosen, limits) {
  const list = limits.jobs.columns.filter((c) => chosen.includes(c));
  const dflt = DEFAULT_COLUMNS.filter((c) => limits.jobs.columns.includes(c));
  return list.join(',') === dflt.join(',') ? '' : list.join(',');
}

// {filters: {name: text}, sort, limit, cursor, columns, unknown: [names]} from the hash's
// parameters.
export function readQuery(params, limits) {
  const names = filterNames(limits);
  const q = { filters: {}, sort: '', limit: '', cursor: '', columns: '', unknown: [] };
  for (const [k0, v] of Object.entries(params)) {
    const k = ALIASES[k0] || k0;
    if (v === '') continue;
    if (names.includes(k)) q.filters[k] = v;
    else if (k === 'sort' || k === 'limit' || k === 'cursor' || k === 'columns') q[k] = v;
    else q.unknown.push(k0);
  }
  return q;
}

// The filters in the server's order of its parameters (one query has one text).
function filterPairs(q, limits) {
  return filterNames(limits).filter((n) => q.filters[n] !== undefined && q.filters[n] !== '').map((n) => [n, q.filters[n]]);
}

// What the table asks the server (format=table), and what the CSV link downloads: the same
// filters and order, every row of the filtered set (up to limits.jobs.max_csv_rows).
export function tableQuery(q, limits) {
  const s = new URLSearchParams(filterPairs(q, limits));
  if (q.sort) s.set('sort', q.sort);
  if (q.limit) s.set('limit', q.limit); // else the server's default_limit
  if (q.cursor) s.set('cursor', q.cursor);
  s.set('columns', shownColumns(q, limits).join(','));
  s.set('format', 'table');
  return text(s);
}

// The table's request read straight from the hash's parameters, before GET /limits has come
// (the first page is asked for at once, beside it); sameQuery tells whether the request the
// page then makes is this one.
export function earlyTableQuery(params) {
  const s = new URLSearchParams();
  for (const [k, v] of Object.entries(params)) if (v !== '' && k !== 'format' && k !== 'offset') s.set(ALIASES[k] || k, v);
  s.set('columns', (s.has('columns') ? withId(s.get('columns').split(',')) : DEFAULT_COLUMNS).join(','));
  s.set('format', 'table');
  return text(s);
}
export function sameQuery(a, b) {
  const norm = (t) => JSON.stringify([...new URLSearchParams(t)].sort(([x], [y]) => (x < y ? -1 : x > y ? 1 : 0)));
  return norm(a) === norm(b);
}

// The CSV holds the columns the table shows.
export function csvQuery(q, limits) {
  const s = new URLSearchParams(filterPairs(q, limits));
  if (q.sort) s.set('sort', q.sort);
  s.set('columns', shownColumns(q, limits).join(','));
  s.set('format', 'csv');
  return text(s);
}

// The filters and sort alone (what the table and the CSV share).
export function sharedQuery(q, limits) {
  const s = new URLSearchParams(filterPairs(q, limits));
  if (q.sort) s.set('sort', q.sort);
  return text(s);
}

// The page's own hash: filters, sort, columns other than the default, a page size other than
// the default, the cursor.
export function pageHash(q, limits) {
  const s = new URLSearchParams(filterPairs(q, limits));
  if (q.sort) s.set('sort', q.sort);
  if (q.columns) s.set('columns', q.columns);
  if (q.limit && Number(q.limit) !== limits.lists.default_limit) s.set('limit', q.limit);
  if (q.cursor) s.set('cursor', q.cursor);
  const t = text(s);
  return `#/runs${t ? `?${t}` : ''}`;
}

// ---- checks, the server's rules as /limits states them (the server checks again: its 422 is
// shown at the field it names) ----

const NUMBER = /^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$/;
const isNumber = (v) => NUMBER.test(String(v).trim()) && Number.isFinite(Number(v));
const isId = (v) => /^\d+$/.test(v) && Number(v) >= 1;

function checkList(v, allowed, what) {
  const items = v.split(',');
  if (items.some((i) => i === '')) return 'must be a comma-separated list without empty items';
  const bad = items.find((i) => !allowed.includes(i));
  return bad === undefined ? '' : `${JSON.stringify(bad)} is not ${what}`;
}

// The problems of a query: [{field, message}] (none: it may be sent).
export function checkQuery(q, limits, presetNames) {
  const out = [];
  const f = q.filters;
  const add = (field, message) => out.push({ field, message });
  const choices = ['none', 'any'];
  for (const [name, v] of Object.entries(f)) {
    let m = '';
    if (name === 'sweep' || name === 'point') m = isId(v) ? '' : 'must be a positive whole number (an id)';
    else if (name === 'phi') m = isNumber(v) ? '' : 'must be a number';
    else if (name === 'state') m = checkList(v, JOB_STATES, `a job state (${JOB_STATES.join(', ')})`);
    else if (name === 'class' || name === 'label' || name === 'human_label') m = checkList(v, [...LETTERS, ...choices], 'a class letter a-f, none or any');
    else if (name === 'preset') m = checkList(v, [...presetNames, ...choices], `a preset (${presetNames.join(', ')}), none or any`);
    else if (name === 'cells_per_unit') {
      const { lo, hi } = limits.scene.cells_per_unit;
      const items = v.split(',');
      m = items.every((i) => /^\d+$/.test(i.trim()) && Number(i) >= lo && Number(i) <= hi) ? '' : `must be whole numbers in [${lo}, ${hi}], comma-separated`;
    } else if (name === 'imported') m = v === 'true' || v === 'false' ? '' : 'must be true or false';
    else if (name === 'source') m = /^[0-9a-fA-F]{1,32}$/.test(v) ? '' : 'must be 1 to 32 hexadecimal digits (the start of a database id)';
    else if (name === 'q') {
      const bytes = new TextEncoder().encode(v).length;
      // eslint-disable-next-line no-control-regex
      m = bytes > limits.jobs.q_max_bytes ? `must be at most ${limits.jobs.q_max_bytes} bytes (is ${bytes})` : /[\u0000-\u001f\u007f]/.test(v) ? 'must not hold control characters' : '';
    } else if (name.endsWith('_min') || name.endsWith('_max')) m = isNumber(v) ? '' : 'must be a number (e.g. 0.5 or 1e-3)';
    if (m) add(name, m);
  }
  for (const r of rangeNames(limits)) {
    const lo = f[`${r}_min`], hi = f[`${r}_max`];
    if (lo !== undefined && hi !== undefined && isNumber(lo) && isNumber(hi) && Number(lo) > Number(hi)) add(`${r}_max`, `must be at least ${r}_min (${lo})`);
  }
  if (q.limit && !(isId(q.limit) && Number(q.limit) <= limits.lists.max_limit)) add('limit', `must be a whole number from 1 to ${limits.lists.max_limit}`);
  if (q.columns) {
    const m = checkList(q.columns, limits.jobs.columns, 'a column of the table');
    const items = q.columns.split(',');
    if (m) add('columns', m);
    else if (new Set(items).size !== items.length) add('columns', 'names a column twice');
  }
  if (q.sort) {
    const key = q.sort.replace(/^-/, '');
    if (!limits.jobs.sort.includes(key)) add('sort', `must be one of ${limits.jobs.sort.join(', ')}, with - before it for descending`);
  }
  return out;
}

// ---- links between the Runs page and the phase map (js/pages/phasemap.js) ----

// The map's filters (phi, sweep, cpu: the cells per unit cell, or 'all') as the table's.
export function runsHashOfMap({ phi, sweep, cpu }) {
  const s = new URLSearchParams();
  if (phi !== null && phi !== undefined && phi !== '') s.set('phi', String(phi));
  if (sweep) s.set('sweep', String(sweep));
  if (cpu && cpu !== 'all') s.set('cells_per_unit', String(cpu));
  const t = s.toString();
  return `#/runs${t ? `?${t}` : ''}`;
}

// The runs of one point of the map (its replicates) in the table.
export const runsHashOfPoint = (pointId) => `#/runs?point=${encodeURIComponent(pointId)}`;

// The map of the table's phi and sweep (and its grid, when the table keeps one): phi as the
// table's phi, else a phi range of one value.
export function mapHashOfQuery(q) {
  const f = q.filters;
  const s = new URLSearchParams();
  const phi = f.phi ?? (f.phi_min !== undefined && f.phi_min === f.phi_max ? f.phi_min : undefined);
  if (phi !== undefined) s.set('phi', phi);
  if (f.sweep) s.set('sweep', f.sweep);
  if (f.cells_per_unit && /^\d+$/.test(f.cells_per_unit)) s.set('cpu', f.cells_per_unit);
  const t = s.toString();
  return `#/map${t ? `?${t}` : ''}`;
}

// The Plots page (js/pages/plots.js) of the table's filters (its default axes; the sort and the
// page do not matter to a plot).
export function plotsHashOfQuery(q, limits) {
  const t = sharedQuery({ ...q, sort: '' }, limits);
  return `#/plots${t ? `?${t}` : ''}`;
}
