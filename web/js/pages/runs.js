// The Runs page (#/runs): every run as a table served a page at a time by GET /api/v1/jobs
// (format=table, docs/service.md "The run table"), as datasette serves a table. The URL holds
// the filters, the sort and the page's cursor under the API's own names (js/runquery.js), so a
// reload or a shared link shows the same rows; the CSV link downloads the whole filtered set in
// the same order. Which columns, sort keys and parameters there are comes from GET /limits.
// The cursors of the pages before the one shown are a stack kept in history.state (a reload
// keeps it); "previous" pops it. Each change is an entry of the browser's history.
import { api, ApiError } from '../api.js';
import { CLASSES, inkOn } from '../classes.js';
import { MAX_COMPARE, compareHash, picked, setPicked } from '../compareset.js';
import { escapeHtml, fixed, sci } from '../format.js';
import { geometryName } from '../geometries.js';
import { parseHash } from '../router.js';
import { fillFilterForm, fillSweepSelect, filterFormHtml, readFilterForm, showFilterErrors } from '../runfilters.js';
import { varText } from '../featureplot.js';
import { loadGlossary } from '../glossary.js';
import {
  DEFAULT_COLUMNS, checkQuery, columnsParam, csvQuery, earlyTableQuery, mapHashOfQuery, pageHash, plotsHashOfQuery, readQuery,
  sameQuery, shownColumns, tableQuery,
} from '../runquery.js';

// How each column is headed (HTML) and titled; a column not listed is headed as the Plots page
// names it (js/featureplot.js), else by its name, and titled by the feature glossary.
const HEADS = {
  id: ['run', 'job id: opens the run'], sweep: ['sweep', 'the first sweep that holds the run'], state: ['state'],
  S: ['<i>S</i>', 'Mach number V/√(E/ρ)'], R: ['<i>R</i>', 'relative strength q_y/E'], phi: ['φ', 'solid fraction'],
  preset: ['preset', 'numerics preset the scene was made from'], cells_per_unit: ['cells/unit', 'cells per unit cell (resolution)'],
  cells_per_strut: ['cells/strut', 'cells across the thinnest strut'], seed: ['seed'], point_id: ['point', 'the point (its replicates)'],
  status: ['status'], class: ['class', "the classifier's label"], confidence: ['conf.', "the classifier's confidence"],
  runner_up: ['runner-up'], n_reflections: ['<i>N</i><sub>r</sub>', 'reflections of the band'],
  band_speed_ratio: ['<i>c</i><sub>b</sub>/<i>V</i>', 'band speed over the piston speed'],
  human_label: ['human', "a person's label"], label: ['label', 'the label that counts: a person\'s, else the classifier\'s'],
  source_database: ['source', 'the database that computed the result (imported runs)'], source_job: ['source job'],
  geometry: ['column', "the scene's geometry: the 2D pseudo-1D column, full 2D or the 3D pseudo-1D column"],
  band_speed_error: ['<i>c</i><sub>b</sub>/<i>V</i> error', "the standard error of the band speed's fit"],
};

// A column's head and title: [html, title or undefined]; glossary: the feature glossary's
// entries by key, once loaded.
function headOf(c, glossary) {
  if (HEADS[c]) return HEADS[c];
  const text = varText(c);
  const name = text !== c ? text : glossary?.[c]?.name ?? c.replace(/_/g, ' ');
  return [escapeHtml(name), glossary?.[c]?.text];
}

const PAGE_SIZES = [25, 50, 100, 200, 500, 1000];
const TYPE_DELAY_MS = 350; // a typed filter applies this long after the last key

function classDot(c) {
  if (!c) return '<span class="muted">—</span>';
  const k = CLASSES[c];
  return k ? `<span class="rt-cls" style="background:${k.color};color:${inkOn(k.color)}" title="${escapeHtml(k.name)}">${c}</span>` : escapeHtml(c);
}

function cellHtml(col, v) {
  if (v === null || v === undefined) return '<span class="muted">—</span>';
  switch (col) {
    case 'id': return `<a href="#/run/${v}">${v}</a>`;
    case 'sweep': return `<a href="#/runs?sweep=${v}" title="this sweep's runs">${v}</a>`;
    case 'point_id': return `<a href="#/runs?point=${v}" title="this point's runs (replicates)">${v}</a>`;
    case 'state': return `<span class="state-${escapeHtml(v)}">${escapeHtml(v)}</span>`;
    case 'S': case 'R': return sci(v, 3);
    case 'phi': return String(Number(v.toPrecision(6)));
    case 'cells_per_strut': return fixed(v, 2);
    case 'confidence': return fixed(v, 3);
    case 'band_speed_ratio': return fixed(v, 3);
    case 'class': case 'runner_up': case 'human_label': case 'label': return classDot(v);
    case 'source_database': return `<span class="mono" title="${escapeHtml(v)}">${escapeHtml(v.slice(0, 8))}</span>`;
    case 'status': return v === 'unstable' ? '<span class="bad">unstable</span>' : escapeHtml(v);
    case 'geometry': return escapeHtml(geometryName(v));
    default: return escapeHtml(typeof v === 'number' ? String(v) : v);
  }
}

function pageHtml() {
  return `
    <div class="page-head"><h1>Runs</h1>
      <p class="sub">Every run, filtered, sorted and paged by the server (<code>GET /api/v1/jobs</code>); the address holds the query, so a link shows the same rows.</p></div>
    <section class="card rt-filters"><details id="rt-details" open><summary>Filters <span id="rt-active" class="muted"></span></summary>
      <form id="rt-form" class="rt-grid" autocomplete="off"><p class="muted">loading…</p></form>
      <div class="rt-filter-foot"><button type="button" class="small" id="rt-clear">Clear filters</button><span class="field-error" data-for="" id="rt-error"></span></div>
    </details></section>
    <section class="card rt-card">
      <div class="rt-bar">
        <span id="rt-count" class="rt-count">…</span>
        <span class="rt-pager">
          <button type="button" class="small" id="rt-first" title="first page">«</button>
          <button type="button" class="small" id="rt-prev">‹ previous</button>
          <button type="button" class="small" id="rt-next">next ›</button>
          <select id="rt-limit" aria-label="rows a page" class="rt-limit"></select>
        </span>
        <details class="rt-cols" id="rt-cols"><summary>Columns <span id="rt-cols-count" class="muted"></span></summary>
          <div class="rt-cols-pop"><div id="rt-cols-list" class="rt-cols-list"></div>
            <div class="rt-cols-foot"><button type="button" class="small" id="rt-cols-default">default</button> <button type="button" class="small" id="rt-cols-all">all</button></div></div>
        </details>
        <span class="rt-compare" id="rt-compare"></span>
        <span class="rt-links"><a id="rt-csv" download href="#">CSV</a> · <a id="rt-map" href="#/map">on the map</a> · <a id="rt-plot" href="#/plots">plot these runs</a></span>
      </div>
      <div class="rt-scroll" id="rt-scroll"><table class="rt" id="rt-table"></table></div>
      <p class="hint" id="rt-foot"></p>
    </section>`;
}

function createPage(root, params) {
  root.innerHTML = pageHtml();
  const $ = (id) => root.querySelector(`#${id}`);
  return {
    root, params,
    limits: null, presets: [],
    query: null, // readQuery's {filters, sort, limit, cursor}
    early: null, // the first page asked for before the limits came: {qs, answer (a promise)}
    stack: [], // cursors of the pages before this one ('' the first page)
    answer: null,
    seq: 0, // the newest request; older answers are dropped
    timer: null,
    closeColumns: null, // the document's listener that closes the open choice of columns
    alive: true,
    el: {
      form: $('rt-form'), clear: $('rt-clear'), error: $('rt-error'), active: $('rt-active'),
      count: $('rt-count'), first: $('rt-first'), prev: $('rt-prev'), next: $('rt-next'), limit: $('rt-limit'),
      csv: $('rt-csv'), map: $('rt-map'), plot: $('rt-plot'), table: $('rt-table'), foot: $('rt-foot'), compare: $('rt-compare'),
      cols: $('rt-cols-list'), colsCount: $('rt-cols-count'), colsDefault: $('rt-cols-default'), colsAll: $('rt-cols-all'),
    },
    glossary: null, // the feature glossary's entries by key, for the heads' titles
  };
}

// The form's controls set from the query's filters, and its summary's count; the column
// choice's boxes from the query's columns.
function fillForm(page) {
  const n = fillFilterForm(page.el.form, page.query.filters);
  page.el.active.textContent = n ? `(${n} set)` : '';
  const shown = shownColumns(page.query, page.limits);
  for (const box of page.el.cols.querySelectorAll('input[data-col]')) box.checked = shown.includes(box.dataset.col);
  page.el.colsCount.textContent = `(${shown.length} of ${page.limits.jobs.columns.length})`;
}

// The column choice: a box for every column of the table, the default ones first. The run's id
// is always shown (its link and its box for comparing).
function columnsHtml(page) {
  const all = page.limits.jobs.columns;
  const box = (c) => {
    const [head, title] = headOf(c, page.glossary);
    const fixed = c === 'id' ? ' disabled' : '';
    return `<label${title ? ` title="${escapeHtml(title)}"` : ''}><input type="checkbox" data-col="${c}"${fixed}> ${head}</label>`;
  };
  const dflt = all.filter((c) => DEFAULT_COLUMNS.includes(c)), more = all.filter((c) => !DEFAULT_COLUMNS.includes(c));
  return `<fieldset><legend>run, parameters, verdict</legend>${dflt.map(box).join('')}</fieldset>`
    + (more.length ? `<fieldset><legend>the classifier's features, the run's measures</legend>${more.map(box).join('')}</fieldset>` : '');
}

// A new choice of columns: the same rows (the cursor and its stack stay), other cells.
function onColumns(page, chosen) {
  page.query = { ...page.query, columns: columnsParam(['id', ...chosen], page.limits) };
  apply(page);
}

const readForm = (page) => readFilterForm(page.el.form);
const showErrors = (page, problems) => showFilterErrors(page.root, problems, page.el.error);

// The page's URL: the query, and the cursor stack in history.state (a reload keeps both). A
// person's change is a new entry of the history (Back shows the rows before: the router mounts
// the page again from that URL and its state); the first URL is only written in its own form.
function syncUrl(page, push) {
  const hash = pageHash(page.query, page.limits);
  const state = { runsStack: page.stack };
  if (push && hash !== location.hash) history.pushState(state, '', hash);
  else history.replaceState(state, '', hash);
}

// Applies a query: checks it, writes the URL (push: as a new history entry), asks the server
// for its page.
function apply(page, push = true) {
  const problems = checkQuery(page.query, page.limits, page.presets);
  showErrors(page, problems);
  fillForm(page);
  syncUrl(page, push);
  updateLinks(page);
  if (problems.length) {
    page.el.table.classList.add('stale');
    page.el.count.textContent = 'fix the marked filter';
    disablePager(page); // the rows shown are of the query before
    return;
  }
  load(page);
}

function disablePager(page) {
  const { el } = page;
  el.first.disabled = el.prev.disabled = el.next.disabled = true;
}

function updateLinks(page) {
  const { el, query, limits } = page;
  el.csv.href = `/api/v1/jobs?${csvQuery(query, limits)}`;
  el.map.href = mapHashOfQuery(query);
  el.plot.href = plotsHashOfQuery(query, limits);
}

async function load(page) {
  const seq = ++page.seq;
  const qs = tableQuery(page.query, page.limits);
  const t0 = performance.now();
  page.el.table.classList.add('loading');
  const early = page.early;
  page.early = null;
  let answer;
  try {
    answer = await (early && sameQuery(early.qs, qs) ? early.answer : api.jobs(qs));
  } catch (e) {
    if (!page.alive || seq !== page.seq) return;
    page.el.table.classList.remove('loading');
    page.el.table.classList.add('stale');
    page.el.count.textContent = 'not loaded';
    disablePager(page);
    showErrors(page, [{ field: e instanceof ApiError ? e.field : '', message: e.message }]);
    publish(page, { query: qs, error: { field: e.field || '', message: e.message } });
    return;
  }
  if (!page.alive || seq !== page.seq) return;
  page.answer = answer;
  const t1 = performance.now();
  render(page);
  page.el.table.classList.remove('loading', 'stale');
  // ms: from the request to the rows in the DOM; renderMs: the page's own part (the rows' HTML).
  publish(page, { query: qs, total: answer.total, ids: answer.rows.map((r) => r.id), next: answer.next, page: page.stack.length + 1, ms: performance.now() - t0, renderMs: performance.now() - t1 });
}

function render(page) {
  const { el, answer, query, limits } = page;
  const cols = answer.columns;
  const sortKey = query.sort.replace(/^-/, '') || 'id';
  const desc = query.sort.startsWith('-');
  const head = cols.map((c) => {
    const [text, title] = headOf(c, page.glossary);
    const sortable = limits.jobs.sort.includes(c);
    const aria = c === sortKey ? ` aria-sort="${desc ? 'descending' : 'ascending'}"` : '';
    const arrow = c === sortKey ? `<span class="rt-arrow">${desc ? '▼' : '▲'}</span>` : '';
    const inner = sortable ? `<button type="button" class="rt-sort" data-col="${c}"${title ? ` title="${escapeHtml(title)}: sort"` : ''}>${text}${arrow}</button>` : `<span${title ? ` title="${escapeHtml(title)}"` : ''}>${text}</span>`;
    return `<th data-col="${c}"${aria}>${inner}</th>`;
  }).join('');
  const ids = picked(); // the tab's picks, read once for every row
  const body = answer.rows.map((r) => `<tr data-id="${r.id}">${cols.map((c) => `<td data-col="${c}">${c === 'id' ? pickBoxHtml(r.id, ids) : ''}${cellHtml(c, r[c])}</td>`).join('')}</tr>`).join('');
  el.table.innerHTML = `<thead><tr>${head}</tr></thead><tbody>${body || `<tr><td colspan="${cols.length}" class="muted rt-empty">No run matches these filters.</td></tr>`}</tbody>`;
  const first = page.stack.length * answer.limit;
  const total = answer.total;
  el.count.innerHTML = total === 0 ? '<b>0</b> runs'
    : `${(first + 1).toLocaleString()}–${(first + answer.rows.length).toLocaleString()} of <b>${total.toLocaleString()}</b> run${total === 1 ? '' : 's'}`;
  el.count.dataset.total = String(total);
  el.prev.disabled = el.first.disabled = page.stack.length === 0;
  el.next.disabled = !answer.next;
  const max = limits.jobs.max_csv_rows;
  updatePicked(page, ids);
  el.foot.textContent = total > max ? `The CSV holds the first ${max.toLocaleString()} of the ${total.toLocaleString()} rows (the server's limit).`
    : 'Click a column\'s head to sort by it, again for the other direction. The CSV holds every row of the filtered set in this order.';
}

// A row's checkbox: the run picked for comparison (js/compareset.js keeps the picks in the tab
// across filters, pages and visits), at most MAX_COMPARE of them; ids: the picks.
function pickBoxHtml(id, ids) {
  const on = ids.includes(id);
  return `<input type="checkbox" class="rt-pick" data-id="${id}" aria-label="compare run ${id}"${on ? ' checked' : ''}>`;
}

// The bar's "Compare selected" link with the count, and the boxes that may still be ticked;
// ids: the picks, when the caller has read them.
function updatePicked(page, ids = picked()) {
  const full = ids.length >= MAX_COMPARE;
  for (const box of page.el.table.querySelectorAll('input.rt-pick')) {
    box.checked = ids.includes(Number(box.dataset.id));
    box.disabled = full && !box.checked;
    box.title = box.disabled ? `at most ${MAX_COMPARE} runs are compared` : '';
  }
  const el = page.el.compare;
  if (!ids.length) {
    el.innerHTML = `<span class="muted">tick up to ${MAX_COMPARE} runs to compare them</span>`;
    return;
  }
  const link = ids.length >= 2
    ? `<a id="rt-compare-link" href="${compareHash(ids)}">Compare selected (${ids.length})</a>`
    : '<span id="rt-compare-link" class="muted">Compare selected: tick one more</span>';
  el.innerHTML = `${link} <span class="muted">${ids.map((id) => `run ${id}`).join(', ')} · at most ${MAX_COMPARE}</span> <button type="button" class="small" id="rt-compare-clear">clear</button>`;
}

function publish(page, what) {
  const hook = (window.__dashboard ||= { renders: [] });
  hook.runs = { ...what, at: performance.now(), n: (hook.runs?.n || 0) + 1 };
  page.root.dataset.runsRenders = String(hook.runs.n);
}

// A changed filter starts again at the first page. The form's change event also comes when a
// typed filter, already applied, loses focus (a click on a column's head, say): the same
// filters again ask nothing, so that no second answer redraws the table under that click.
function onFilters(page) {
  const filters = readForm(page);
  const text = (f) => JSON.stringify(Object.entries(f || {}).sort());
  if (text(filters) === text(page.query.filters)) return;
  page.query = { ...page.query, filters, cursor: '' };
  page.stack = [];
  apply(page);
}

function wire(page) {
  const { el } = page;
  el.form.addEventListener('submit', (ev) => ev.preventDefault());
  el.form.addEventListener('change', () => { clearTimeout(page.timer); onFilters(page); });
  el.form.addEventListener('input', (ev) => {
    if (ev.target.type !== 'text') return;
    clearTimeout(page.timer);
    page.timer = setTimeout(() => onFilters(page), TYPE_DELAY_MS);
  });
  el.clear.addEventListener('click', () => {
    page.query = { ...page.query, filters: {}, cursor: '' };
    page.stack = [];
    apply(page);
  });
  el.table.addEventListener('change', (ev) => {
    const box = ev.target.closest('input.rt-pick');
    if (!box) return;
    const id = Number(box.dataset.id);
    const ids = picked().filter((x) => x !== id);
    setPicked(box.checked ? [...ids, id].slice(0, MAX_COMPARE) : ids);
    updatePicked(page);
  });
  el.compare.addEventListener('click', (ev) => {
    if (!ev.target.closest('#rt-compare-clear')) return;
    setPicked([]);
    updatePicked(page);
  });
  el.table.addEventListener('click', (ev) => {
    const b = ev.target.closest('.rt-sort');
    if (!b) return;
    const c = b.dataset.col;
    const now = page.query.sort || 'id';
    page.query = { ...page.query, sort: now === c ? `-${c}` : c, cursor: '' };
    page.stack = [];
    apply(page);
  });
  el.next.addEventListener('click', () => {
    if (!page.answer?.next) return;
    page.stack = [...page.stack, page.query.cursor];
    page.query = { ...page.query, cursor: page.answer.next };
    apply(page);
  });
  el.prev.addEventListener('click', () => {
    if (!page.stack.length) return;
    const stack = [...page.stack];
    const cursor = stack.pop();
    page.stack = stack;
    page.query = { ...page.query, cursor };
    apply(page);
  });
  el.first.addEventListener('click', () => {
    page.stack = [];
    page.query = { ...page.query, cursor: '' };
    apply(page);
  });
  el.cols.addEventListener('change', () => {
    onColumns(page, [...el.cols.querySelectorAll('input[data-col]:checked')].map((b) => b.dataset.col));
  });
  el.colsDefault.addEventListener('click', () => onColumns(page, DEFAULT_COLUMNS));
  el.colsAll.addEventListener('click', () => onColumns(page, page.limits.jobs.columns));
  // The open choice of columns closes on a click outside it or on Escape (on a phone it covers
  // its own summary).
  const fold = page.root.querySelector('#rt-cols');
  page.closeColumns = (ev) => {
    if (fold.open && (ev.type === 'keydown' ? ev.key === 'Escape' : !fold.contains(ev.target))) fold.open = false;
  };
  document.addEventListener('click', page.closeColumns);
  document.addEventListener('keydown', page.closeColumns);
  el.limit.addEventListener('change', () => {
    page.query = { ...page.query, limit: el.limit.value, cursor: '' };
    page.stack = [];
    apply(page);
  });
}

async function start(page) {
  const { root } = page;
  // The first page is asked for at once, beside the limits (load takes it when its query is
  // the one the limits make); the sweeps' names fill their list when they come.
  const qs = earlyTableQuery(page.params);
  page.early = { qs, answer: api.jobs(qs) };
  page.early.answer.catch(() => {}); // a refusal is shown when load takes it
  // (after the first page: at 100 000 runs GET /sweeps costs the server more than the page does)
  const sweeps = page.early.answer.catch(() => null).then(() => api.sweeps()).catch(() => ({ sweeps: [] }));
  let limits, presets;
  try {
    [limits, presets] = await Promise.all([api.limits(), api.presets()]);
  } catch (e) {
    if (page.alive) page.el.form.innerHTML = `<p class="error">Could not load the table's limits: ${escapeHtml(e.message)}</p>`;
    return;
  }
  if (!page.alive) return;
  // On a phone the filters start folded (their summary says how many are set).
  if (window.matchMedia('(max-width: 640px)').matches) root.querySelector('#rt-details').open = false;
  page.limits = limits;
  page.presets = presets.presets.map((p) => p.name);
  page.el.form.innerHTML = filterFormHtml(limits, page.presets);
  page.el.cols.innerHTML = columnsHtml(page);
  page.query = readQuery(page.params, limits);
  // The stack of a reload (history.state), if it belongs to this cursor.
  const kept = history.state?.runsStack;
  page.stack = page.query.cursor && Array.isArray(kept) ? kept : [];
  const sizes = [...new Set([...PAGE_SIZES.filter((n) => n <= limits.lists.max_limit), limits.lists.default_limit, Number(page.query.limit) || limits.lists.default_limit])].sort((a, b) => a - b);
  page.el.limit.innerHTML = sizes.map((n) => `<option value="${n}">${n} a page</option>`).join('');
  page.el.limit.value = String(Number(page.query.limit) || limits.lists.default_limit);
  wire(page);
  apply(page, false);
  sweeps.then((s) => { if (page.alive) fillSweepSelect(page.el.form, s.sweeps || []); });
  // The heads' and boxes' titles, when the glossary comes (the table is drawn without them first).
  loadGlossary().then((g) => {
    if (!page.alive) return;
    page.glossary = g.features || {};
    page.el.cols.innerHTML = columnsHtml(page);
    fillForm(page);
    if (page.answer) render(page);
  });
  if (page.query.unknown.length) page.el.error.textContent = `ignored: ${page.query.unknown.join(', ')} (not a parameter of the table)`;
}

export function mount(root, params) {
  const page = createPage(root, params || parseHash().params);
  start(page);
  return () => {
    page.alive = false;
    clearTimeout(page.timer);
    if (page.closeColumns) {
      document.removeEventListener('click', page.closeColumns);
      document.removeEventListener('keydown', page.closeColumns);
    }
  };
}
