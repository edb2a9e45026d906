// The Plots page (#/plots): any numeric column of the run table against any other, for the
// runs the Runs page's filters keep (the same form, js/runfilters.js, and the same query,
// js/runquery.js), as optuna-dashboard plots any parameter against any value. The rows come as
// one GET /api/v1/jobs?format=csv of the columns the plot reads (every row of the filtered set,
// up to limits.jobs.max_csv_rows); another scale or a variable the rows hold redraws them,
// another variable or filter asks again. The URL holds the
// filters and x, y, xscale, yscale, color, so a link shows the same plot; a saved view (the
// paper's Fig. 3 among them) sets them in one click. Exports SVG and PNG as the map does
// (js/mapexport.js).
import { api, ApiError } from '../api.js';
import { swatch } from '../classes.js';
import {
  CATEGORY_COLOURS, PLOT_KEYS, VIEWS, colourKeys, columnsFor, drawExportMark, drawFeatureMarkers, markerRadius, newFeaturePlot, parseRunsCsv,
  placeable, readSpec, rgbOf, varHtml, varText, variablesOf, viewOf,
} from '../featureplot.js';
import { escapeHtml, sciText } from '../format.js';
import { svgEl } from '../plot.js';
import { parseHash } from '../router.js';
import { fillFilterForm, fillSweepSelect, filterFormHtml, readFilterForm, showFilterErrors } from '../runfilters.js';
import { checkQuery, csvQuery, readQuery, sameQuery, sharedQuery } from '../runquery.js';

const TYPE_DELAY_MS = 350; // a typed filter applies this long after the last key
const PICK_PX = 10; // the tooltip's and the click's reach
// A set of more rows is drawn first from its first FIRST_ROWS as they arrive, then whole: the
// CSV of 100 000 runs takes about 0.4 s to come, its first 20 000 rows a tenth of that. The
// browser tests set a smaller one in the page's hook (window.__dashboard.firstRows).
const FIRST_ROWS = 20000;
const firstRows = () => window.__dashboard?.firstRows ?? FIRST_ROWS;

function pageHtml() {
  const views = VIEWS.map((v) => `<button type="button" class="small pl-view" data-view="${v.key}" title="${escapeHtml(v.title)}">${escapeHtml(v.name)}</button>`).join(' ');
  const scale = (id, label) => `<select id="${id}" aria-label="${label}"><option value="log">log</option><option value="linear">linear</option></select>`;
  return `
    <div class="page-head"><h1>Plots</h1>
      <p class="sub">Any number of the run table against any other, for the runs its filters keep (<code>GET /api/v1/jobs</code>, as on the Runs page); the address holds the plot and the filters, so a link shows the same plot.</p></div>
    <section class="card rt-filters"><details id="pl-details" open><summary>Filters <span id="pl-active" class="muted"></span></summary>
      <form id="pl-form" class="rt-grid" autocomplete="off"><p class="muted">loading…</p></form>
      <div class="rt-filter-foot"><button type="button" class="small" id="pl-clear">Clear filters</button><span class="field-error" data-for="" id="pl-error"></span></div>
    </details></section>
    <div class="layout-map">
      <section class="card figure"><div class="figure-plot" id="pl-plot"></div>
        <div class="figure-foot"><span id="pl-summary" class="summary">loading…</span></div>
        <ul class="left-off" id="pl-left-off"></ul></section>
      <aside class="card controls">
        <div class="field"><span>Saved views</span><div class="pl-views">${views}</div></div>
        <label class="field"><span>x axis</span><select id="pl-x" aria-label="x axis"></select></label>
        <label class="field"><span>x scale</span>${scale('pl-xscale', 'x scale')}</label>
        <label class="field"><span>y axis</span><select id="pl-y" aria-label="y axis"></select></label>
        <label class="field"><span>y scale</span>${scale('pl-yscale', 'y scale')}</label>
        <label class="field"><span>Colour</span><select id="pl-color" aria-label="colour"></select></label>
        <h2 class="legend-title" id="pl-legend-title">Colour</h2>
        <ul class="legend" id="pl-legend"></ul>
        <p class="hint">A log axis leaves out values ≤ 0 (counted under the plot). Hover a marker for its run, click to open it.</p>
        <p class="pl-export"><button type="button" class="small" id="pl-svg">SVG</button> <button type="button" class="small" id="pl-png">PNG</button>
          · <a id="pl-runs" href="#/runs">these runs in the table</a></p>
      </aside>
    </div>`;
}

function createPage(root, params) {
  root.innerHTML = pageHtml();
  const $ = (id) => root.querySelector(`#${id}`);
  const first = readSpec(params);
  return {
    root, params,
    limits: null, presets: [],
    query: null, // readQuery's {filters, ...}: the table's filters
    spec: first.spec, // x, y, xscale, yscale, color
    notes: first.problems, // what the page replaced or ignored of its URL, said under the filters
    data: null, // parseRunsCsv's columns of the rows of query
    total: 0, // rows the filters keep (X-Total-Count; more than data.n past max_csv_rows)
    early: null, // the rows asked for before the limits came: {qs, answer, first, firstRows}
    partial: false, // the plot shows the first rows of a set while the rest arrive
    seq: 0,
    timer: null, resizeTimer: null, onResize: null,
    plot: null, drawn: null, // the last render: its Plot, rows and canvas positions
    alive: true,
    tooltip: document.getElementById('tooltip'),
    el: {
      form: $('pl-form'), clear: $('pl-clear'), error: $('pl-error'), active: $('pl-active'), details: $('pl-details'),
      plotBox: $('pl-plot'), summary: $('pl-summary'), leftOff: $('pl-left-off'), legend: $('pl-legend'), legendTitle: $('pl-legend-title'),
      x: $('pl-x'), y: $('pl-y'), xscale: $('pl-xscale'), yscale: $('pl-yscale'), color: $('pl-color'),
      svg: $('pl-svg'), png: $('pl-png'), runs: $('pl-runs'),
    },
  };
}

// The hash's parameters of the table's filters (those of the plot taken out).
const filterParams = (params) => Object.fromEntries(Object.entries(params).filter(([k]) => !PLOT_KEYS.includes(k)));

// The rows' request: the table's CSV of the filters (id order; up to the server's row limit),
// the columns the spec reads.
const rowsQuery = (q, limits, spec) => csvQuery({ ...q, sort: '', columns: columnsFor(spec).join(',') }, limits);
// ... read straight from the hash, before GET /limits has come.
function earlyRowsQuery(params) {
  const s = new URLSearchParams(filterParams(params));
  for (const k of ['sort', 'limit', 'offset', 'cursor', 'format', 'columns']) s.delete(k);
  s.set('format', 'csv');
  s.set('columns', columnsFor(readSpec(params).spec).join(','));
  return s.toString();
}
// Whether the rows hold every column the spec reads.
const holds = (data, spec) => columnsFor(spec).every((k) => data.names.includes(k));

// GET /jobs?qs as CSV: {csv, total}; a refusal as the ApiError of its JSON body. When the set
// holds more than firstRows() rows, the body is read as it comes and first(text, total) is
// called once with its complete lines so far, once they are more than that (the header
// included).
async function fetchRows(qs, first = null) {
  const res = await fetch(`/api/v1/jobs?${qs}`, { cache: 'no-store' });
  const count = res.headers.get('X-Total-Count');
  const total = count === null ? NaN : Number(count);
  if (!res.ok) {
    const text = await res.text();
    let body = null;
    try { body = JSON.parse(text); } catch { /* not JSON */ }
    throw new ApiError(res.status, body);
  }
  const limit = firstRows();
  if (!first || !res.body || !(total > limit)) return { csv: await res.text(), total };
  const reader = res.body.pipeThrough(new TextDecoderStream()).getReader();
  const parts = [];
  let lines = 0;
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
    parts.push(value);
    if (lines > limit) continue;
    for (let i = value.indexOf('\n'); i >= 0; i = value.indexOf('\n', i + 1)) lines++;
    if (lines > limit) {
      const text = parts.join('');
      first(text.slice(0, text.lastIndexOf('\n') + 1), total);
    }
  }
  return { csv: parts.join(''), total };
}

// The table's filters as text (the API's names and order, commas as written).
const filtersText = (page) => sharedQuery({ ...page.query, sort: '' }, page.limits).replace(/%2C/g, ',');

// The page's hash: the filters, then the plot.
function pageHash(page) {
  const s = new URLSearchParams(filtersText(page));
  for (const k of PLOT_KEYS) s.set(k, page.spec[k]);
  return `#/plots?${s.toString().replace(/%2C/g, ',')}`;
}

// A person's change is an entry of the history (Back shows the plot before).
function syncUrl(page, push) {
  const hash = pageHash(page);
  if (push && hash !== location.hash) history.pushState(null, '', hash);
  else history.replaceState(null, '', hash);
  const f = filtersText(page);
  page.el.runs.href = `#/runs${f ? `?${f}` : ''}`;
}

// The figure's size for the page's width and the window's height (as the band-speed page's).
function figureSize(box) {
  const width = Math.max(300, Math.min(1100, box.clientWidth || 760));
  return { width, height: Math.round(Math.min(width * (width < 500 ? 1 : 0.62), Math.max(420, window.innerHeight - 260))) };
}

// The controls set from the spec (the variable lists from the table's columns, once the limits
// came).
function fillControls(page) {
  const { el, spec, limits } = page;
  if (limits) {
    const vars = variablesOf(limits.jobs.columns);
    const opts = (list) => list.map((k) => `<option value="${escapeHtml(k)}">${escapeHtml(varText(k))}</option>`).join('');
    if (el.x.dataset.vars !== vars.join()) {
      el.x.innerHTML = el.y.innerHTML = opts(vars);
      el.color.innerHTML = Object.entries(CATEGORY_COLOURS).map(([k, t]) => `<option value="${k}">${escapeHtml(t)}</option>`).join('') + opts(vars);
      el.x.dataset.vars = vars.join();
    }
  }
  for (const k of PLOT_KEYS) el[k].value = spec[k];
  const view = viewOf(spec, page.query?.filters || {});
  for (const b of page.root.querySelectorAll('.pl-view')) b.setAttribute('aria-pressed', String(b.dataset.view === view));
}

// The filters form from the query, its checks, the URL; then the rows (push: a history entry).
function apply(page, push = true) {
  const problems = checkQuery(page.query, page.limits, page.presets);
  showFilterErrors(page.root, problems, page.el.error);
  const n = fillFilterForm(page.el.form, page.query.filters);
  page.el.active.textContent = n ? `(${n} set)` : '';
  fillControls(page);
  syncUrl(page, push);
  if (problems.length) {
    ++page.seq; // an answer still coming is of the filters before: it draws nothing
    page.el.summary.textContent = 'fix the marked filter';
    page.el.plotBox.classList.add('stale');
    return;
  }
  load(page);
}

async function load(page) {
  const seq = ++page.seq;
  const qs = rowsQuery(page.query, page.limits, page.spec);
  const t0 = performance.now();
  page.el.plotBox.classList.add('loading');
  const early = page.early;
  page.early = null;
  // The first rows drawn while the rest arrive, if this is still the page's last request.
  const first = (text, total) => { if (page.alive && seq === page.seq) drawFirstRows(page, text, total); };
  let answer;
  try {
    if (early && sameQuery(early.qs, qs)) {
      early.first = first;
      if (early.firstRows) first(early.firstRows.text, early.firstRows.total);
      answer = await early.answer;
    } else {
      answer = await fetchRows(qs, first);
    }
  } catch (e) {
    if (!page.alive || seq !== page.seq) return;
    page.el.plotBox.classList.remove('loading');
    page.el.plotBox.classList.add('stale');
    page.el.summary.textContent = 'not loaded';
    showFilterErrors(page.root, [{ field: e instanceof ApiError ? e.field : '', message: e.message }], page.el.error);
    publish(page, { query: qs, error: { field: e.field || '', message: e.message } });
    return;
  }
  if (!page.alive || seq !== page.seq) return;
  const t1 = performance.now();
  page.partial = false;
  page.data = parseRunsCsv(answer.csv);
  page.total = Number.isFinite(answer.total) ? answer.total : page.data.n;
  fillControls(page);
  syncUrl(page, false);
  const t2 = performance.now();
  render(page);
  page.el.plotBox.classList.remove('loading', 'stale');
  publish(page, { query: qs, ms: performance.now() - t0, parseMs: t2 - t1, renderMs: performance.now() - t2 });
}

// The plot of the first rows of a large set, while the rest arrive (the plot stays marked as
// loading; the page's hook keeps it apart from the whole plot: window.__dashboard.firstPlot).
function drawFirstRows(page, text, total) {
  page.partial = true;
  page.data = parseRunsCsv(text);
  page.total = Number.isFinite(total) ? total : page.data.n;
  render(page);
  const hook = (window.__dashboard ||= { renders: [] });
  hook.firstPlot = { at: performance.now(), rows: page.data.n, total: page.total, plotted: page.drawn.rows.length };
}

// The plot of the rows for the spec, its legend and what it left off; keeps what it drew.
function render(page) {
  const { el, data, spec } = page;
  const t0 = performance.now();
  const { rows, leftOff } = placeable(data, spec);
  el.plotBox.replaceChildren();
  const plot = (page.plot = newFeaturePlot(el.plotBox, figureSize(el.plotBox), data, spec, rows));
  const coloured = colourKeys(data, spec.color, rows);
  const r = markerRadius(rows.length);
  const { px, py } = drawFeatureMarkers(plot, data, rows, coloured, r);
  page.drawn = { rows, px, py, coloured, r };
  if (!rows.length) {
    svgEl('text', { x: plot.m.l + plot.pw / 2, y: plot.m.t + plot.ph / 2, 'text-anchor': 'middle', class: 'empty-note' }, plot.front)
      .textContent = data.n ? `None of the ${data.n} runs has both values.` : 'No run matches these filters.';
  }
  plot.canvas.dataset.count = String(rows.length);
  wireCanvas(page, plot);
  renderLegend(page, coloured.legend);
  renderSummary(page, rows, leftOff);
  page.renderMs = performance.now() - t0;
}

function renderLegend(page, legend) {
  const { el, spec } = page;
  el.legendTitle.innerHTML = CATEGORY_COLOURS[spec.color] ? escapeHtml(CATEGORY_COLOURS[spec.color]) : varHtml(spec.color);
  el.legend.replaceChildren(...legend.map((e) => {
    const li = document.createElement('li');
    li.dataset.key = e.key;
    li.dataset.count = String(e.count);
    li.innerHTML = `<span class="dot big" style="background:${e.color}"></span><span class="legend-name">${escapeHtml(e.name)}</span><span class="legend-count">${e.count.toLocaleString('en')}</span>`;
    if (e.cat) li.firstChild.replaceWith(swatch(e.cat)); // a class's or a state's own marker
    return li;
  }));
}

function renderSummary(page, rows, leftOff) {
  const { el, data, spec, total } = page;
  const cut = page.partial ? ` (the first ${data.n.toLocaleString('en')} of ${total.toLocaleString('en')}; the others are coming)`
    : total > data.n ? ` (the first ${data.n.toLocaleString('en')} of ${total.toLocaleString('en')}: the server's row limit)` : '';
  el.summary.dataset.plotted = String(rows.length);
  el.summary.innerHTML = `<b>${rows.length.toLocaleString('en')}</b> of ${data.n.toLocaleString('en')} run${data.n === 1 ? '' : 's'} plotted${cut}: ${varHtml(spec.y)} against ${varHtml(spec.x)}`;
  el.leftOff.replaceChildren(...leftOff.map((l) => {
    const li = document.createElement('li');
    li.dataset.reason = l.reason;
    li.dataset.axis = l.axis;
    li.dataset.count = String(l.count);
    const runs = `${l.count.toLocaleString('en')} run${l.count === 1 ? '' : 's'}`;
    li.innerHTML = l.reason === 'missing' ? `left off: ${runs} without a value of ${varHtml(spec[l.axis])}`
      : `left off: ${runs} with ${varHtml(spec[l.axis])} ≤ 0 (a log ${l.axis} axis cannot show ${l.count === 1 ? 'it' : 'them'})`;
    return li;
  }));
}

// For the browser tests and the bench: what the last render drew (the row ids and canvas
// positions of its markers) and how long it took.
function publish(page, what) {
  const hook = (window.__dashboard ||= { renders: [] });
  const n = (hook.plots?.n || 0) + 1;
  const d = page.drawn;
  hook.plots = {
    ...what, n, at: performance.now(), spec: { ...page.spec }, rows: page.data?.n ?? 0, total: page.total,
    plotted: d ? d.rows.length : 0, ids: d ? d.rows.map((i) => page.data.numeric.id[i]) : [], px: d?.px, py: d?.py,
    plot: page.plot ? { m: page.plot.m, pw: page.plot.pw, ph: page.plot.ph, x: [page.plot.x.d0, page.plot.x.d1], y: [page.plot.y.d0, page.plot.y.d1] } : null,
    legend: d ? d.coloured.legend.map((e) => ({ key: e.key, count: e.count })) : [],
  };
  page.root.dataset.plotRenders = String(n);
}

// ---- the mouse: the nearest marker's run in the tooltip, a click opens it ----

function nearest(page, ev) {
  const { plot, drawn } = page;
  const rect = plot.canvas.getBoundingClientRect();
  const mx = ev.clientX - rect.left, my = ev.clientY - rect.top;
  let best = -1, bd = PICK_PX * PICK_PX;
  for (let k = 0; k < drawn.rows.length; k++) {
    const q = (drawn.px[k] - mx) ** 2 + (drawn.py[k] - my) ** 2;
    if (q < bd) { bd = q; best = k; }
  }
  return best < 0 ? null : drawn.rows[best];
}

function tipHtml(page, i) {
  const { data, spec } = page;
  const num = (k) => { const v = data.numeric[k]?.[i]; return Number.isFinite(v) ? sciText(v, 4) : '—'; };
  const keys = [...new Set([spec.x, spec.y, ...(CATEGORY_COLOURS[spec.color] ? [] : [spec.color]), 'S', 'R', 'phi'])].filter((k) => data.numeric[k]);
  const cls = data.text.class?.[i] || '—', lab = data.text.label?.[i] || '—';
  return `<div class="tt-head">run ${data.numeric.id[i]}</div><table>${keys.map((k) => `<tr><th>${varHtml(k)}</th><td>${num(k)}</td></tr>`).join('')}
    <tr><th>class</th><td>${escapeHtml(cls)}${lab !== cls ? ` (label ${escapeHtml(lab)})` : ''}</td></tr></table><div class="muted">click to open the run</div>`;
}

function wireCanvas(page, plot) {
  plot.canvas.addEventListener('mousemove', (ev) => {
    const i = nearest(page, ev);
    if (i === null) { page.tooltip.hidden = true; plot.canvas.style.cursor = ''; return; }
    plot.canvas.style.cursor = 'pointer';
    page.tooltip.innerHTML = tipHtml(page, i);
    page.tooltip.hidden = false;
    page.tooltip.style.left = `${ev.clientX + 16 + window.scrollX}px`;
    page.tooltip.style.top = `${ev.clientY + 14 + window.scrollY}px`;
  });
  plot.canvas.addEventListener('mouseleave', () => { page.tooltip.hidden = true; });
  plot.canvas.addEventListener('click', (ev) => {
    const i = nearest(page, ev);
    if (i !== null) location.hash = `#/run/${page.data.numeric.id[i]}`;
  });
}

// ---- export: the figure as the map's export draws it, a marker per run (data-job) ----

function figureOf(page) {
  const { plot, drawn, data, spec } = page;
  const markers = drawn.rows.map((i, k) => {
    const e = drawn.coloured.legend.find((l) => l.key === drawn.coloured.keys[k]);
    return { cat: e.cat || `colour ${e.key}`, color: e.color, x: drawn.px[k], y: drawn.py[k], r: drawn.r, job: data.numeric.id[i] };
  });
  // Categories as their markers; numbers as swatches.
  const legend = drawn.coloured.legend.map((e) => (e.cat ? { cat: e.cat, name: e.name, count: e.count } : { color: rgbOf(e.color), name: e.name, count: e.count }));
  const filters = filtersText(page);
  return {
    plot, markers, regions: null, legend, drawMark: (ctx, m) => drawExportMark(ctx, m.cat.startsWith('colour ') ? { ...m, cat: null } : m),
    title: `${varText(spec.y)} against ${varText(spec.x)}`,
    note: [`${drawn.rows.length} of ${data.n} runs plotted`, `colour: ${CATEGORY_COLOURS[spec.color] || varText(spec.color)}`, `filters: ${filters || 'none'}`],
  };
}

async function exportAs(page, kind) {
  if (!page.drawn) return;
  const figure = figureOf(page);
  // The export's code (mapexport.js and what only it imports) loads on the first export, not
  // with the page.
  const { download, mapSvg, pngBlob, svgText } = await import('../mapexport.js');
  const svg = mapSvg(figure);
  const name = `plot-${page.spec.y}-vs-${page.spec.x}.${kind}`;
  if (kind === 'svg') download(new Blob([svgText(svg)], { type: 'image/svg+xml' }), name);
  else download(await pngBlob(svg), name);
}

// ---- the controls ----

// A changed filter asks for the rows again (the same filters ask nothing).
function onFilters(page) {
  const filters = readFilterForm(page.el.form);
  const text = (f) => JSON.stringify(Object.entries(f || {}).sort());
  if (text(filters) === text(page.query.filters)) return;
  page.query = { ...page.query, filters };
  apply(page);
}

// Another axis, scale or colour redraws the rows the page has, or asks for the rows with the
// columns it lacks.
function onSpec(page, spec) {
  page.spec = spec;
  fillControls(page);
  syncUrl(page, true);
  if (!page.data) return;
  if (!holds(page.data, spec)) { load(page); return; }
  const t0 = performance.now();
  render(page);
  publish(page, { query: rowsQuery(page.query, page.limits, page.spec), ms: performance.now() - t0, renderMs: performance.now() - t0, redraw: true });
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
  el.clear.addEventListener('click', () => { page.query = { ...page.query, filters: {} }; apply(page); });
  for (const k of PLOT_KEYS) el[k].addEventListener('change', () => onSpec(page, { ...page.spec, [k]: el[k].value }));
  for (const b of page.root.querySelectorAll('.pl-view')) {
    b.addEventListener('click', () => {
      const v = VIEWS.find((w) => w.key === b.dataset.view);
      const filters = { ...page.query.filters, ...(v.filters || {}) };
      page.spec = { ...v.spec };
      if (JSON.stringify(filters) !== JSON.stringify(page.query.filters)) { page.query = { ...page.query, filters }; apply(page); } else onSpec(page, page.spec);
    });
  }
  el.svg.addEventListener('click', () => exportAs(page, 'svg'));
  el.png.addEventListener('click', () => exportAs(page, 'png'));
  page.onResize = () => {
    clearTimeout(page.resizeTimer);
    page.resizeTimer = setTimeout(() => {
      if (!page.alive || !page.plot || !page.data) return;
      const { width, height } = figureSize(el.plotBox);
      if (width !== page.plot.opts.width || height !== page.plot.opts.height) render(page);
    }, 150);
  };
  window.addEventListener('resize', page.onResize);
}

async function start(page) {
  // The rows are asked for at once, beside the limits (load takes them when its query is the
  // one the limits make); the sweeps' names after the rows.
  const qs = earlyRowsQuery(page.params);
  // Its first rows are kept until load() takes the answer, then handed to it (early.first).
  const early = { qs, first: null, firstRows: null };
  early.answer = fetchRows(qs, (text, total) => {
    early.firstRows = { text, total };
    early.first?.(text, total);
  });
  page.early = early;
  page.early.answer.catch(() => {});
  const sweeps = page.early.answer.catch(() => null).then(() => api.sweeps()).catch(() => ({ sweeps: [] }));
  let limits, presets;
  try {
    [limits, presets] = await Promise.all([api.limits(), api.presets()]);
  } catch (e) {
    if (page.alive) page.el.form.innerHTML = `<p class="error">Could not load the table's limits: ${escapeHtml(e.message)}</p>`;
    return;
  }
  if (!page.alive) return;
  if (window.matchMedia('(max-width: 640px)').matches) page.el.details.open = false;
  page.limits = limits;
  // A spec of a column the table has not falls back to the default (said under the filters).
  const checked = readSpec(page.params, variablesOf(limits.jobs.columns));
  page.spec = checked.spec;
  page.notes = checked.problems;
  page.presets = presets.presets.map((p) => p.name);
  page.el.form.innerHTML = filterFormHtml(limits, page.presets);
  page.query = readQuery(filterParams(page.params), limits);
  wire(page);
  apply(page, false);
  sweeps.then((s) => { if (page.alive) fillSweepSelect(page.el.form, s.sweeps || []); });
  const ignored = page.query.unknown.filter((k) => !['sort', 'limit', 'cursor', 'offset', 'format'].includes(k));
  if (ignored.length) page.notes.push(`ignored: ${ignored.join(', ')} (not a parameter of the table or the plot)`);
  if (page.notes.length && !page.el.error.textContent) page.el.error.textContent = page.notes.join('; ');
}

export function mount(root, params) {
  const page = createPage(root, params || parseHash().params);
  start(page);
  return () => {
    page.alive = false;
    clearTimeout(page.timer);
    clearTimeout(page.resizeTimer);
    window.removeEventListener('resize', page.onResize);
    page.tooltip.hidden = true;
  };
}
