// Phase map: log10 S against log10 R at one phi, one marker per point (a computation up to its
// seed: its runs are its replicates, docs/replicates.md) coloured by its class (Fig. 2 of the
// paper), over the regions the labelled runs predict, live while sweeps run. Canvas for the
// background and the markers (10,000 stay fast), SVG for axes and overlays. Hover: a tooltip
// with the point's numbers (or the prediction under the mouse); click: the run's page, or for a
// point of several runs its tooltip pinned with a link to each. Export: SVG and PNG of the
// figure with its legend. Wheel, drag and pinch zoom and pan the view (mapview.js, kept in the
// URL); by default each place shows its finest runs only (mapnumerics.js); an adaptive sweep's
// plan and the points its planner added are shown when the sweep is chosen (mapplan.js).
import { humanTipRows } from '../humanlabels.js';
import { api } from '../api.js';
import { CLASSES, STATES, confidenceFade, label, look, swatch } from '../classes.js';
import { drawPointMark, drawPointMarks, majorityCount, mapPoints, notRobustWhy, probabilitiesHtml, runLinksHtml, spreadText } from '../points.js';
import { cellAt, cellColor, drawRegions } from '../regions.js';
import { Plot, logExtent, richText, svgEl, valueRange } from '../plot.js';
import { sci, sciText, fixed, escapeHtml } from '../format.js';
import { setParams } from '../router.js';
import { GEOMETRIES } from '../geometries.js';
import { plotView, spacingRadii, viewOf, viewParams, wireView } from '../mapview.js';
import { FINEST, numericsCaption, ofNumerics, placeKey } from '../mapnumerics.js';
import { addedByPlanner, planCaption } from '../mapplan.js';
import { runsHashOfMap, runsHashOfPoint } from '../runquery.js';

const POLL_MS = 2000;
// Draw order: pending below finished, labelled on top.
const ORDER = { cancelled: 0, queued: 1, failed: 2, running: 3, unclassified: 4, unstable: 5 };

function pageHtml() {
  return `
    <div class="page-head">
      <h1>Phase map</h1>
      <p class="sub">Pattern of compaction of every run in the plane of the Mach number
        <i>S</i> = <i>V</i>/√(<i>E</i>/ρ) and the relative strength <i>R</i> = <i>q</i><sub>y</sub>/<i>E</i>,
        at one solid fraction φ.</p>
    </div>
    <div class="layout-map">
      <section class="card figure">
        <div class="figure-plot" id="map-plot"></div>
        <div class="figure-foot"><span id="map-summary" class="summary"></span><span id="map-live" class="live"></span></div>
        <div class="map-notes">
          <div class="map-view"><button type="button" class="small" id="map-reset" disabled>reset view</button>
            <span id="map-view-text" class="muted">wheel or pinch: zoom · drag: pan</span></div>
          <div id="map-numerics" class="map-caption"></div>
          <div id="map-plan" class="map-caption" hidden></div>
        </div>
      </section>
      <aside class="card controls">
        <label class="field">Solid fraction φ
          <select id="map-phi" aria-label="solid fraction phi"></select></label>
        <label class="field">Numerics
          <select id="map-cpu" aria-label="numerics preset"><option value="finest">finest run per point</option><option value="all">all resolutions</option></select></label>
        <label class="field">Column
          <select id="map-geometry" aria-label="geometry">${GEOMETRIES.map(([g, name]) => `<option value="${g === 'pseudo1d' ? '' : g}">${name}</option>`).join('')}</select></label>
        <label class="field">Sweep
          <select id="map-sweep" aria-label="sweep"><option value="">all sweeps</option></select></label>
        <label class="check"><input type="checkbox" id="map-buckling"><span>buckling onset <i>R</i><sub>crit</sub> = π²<i>a</i>²/12</span></label>
        <label class="check"><input type="checkbox" id="map-regions"><span>predicted regions (background)</span></label>
        <label class="check"><input type="checkbox" id="map-robust"><span>robust points only <span class="muted">(replicates all agree)</span></span></label>
        <div class="export-row"><span>Export</span>
          <button type="button" class="small" id="map-export-svg">SVG</button>
          <button type="button" class="small" id="map-export-png">PNG</button></div>
        <p class="map-runs"><a id="map-to-runs" href="#/runs">these runs in the table</a></p>
        <h2 class="legend-title">Legend</h2>
        <ul class="legend" id="map-legend"></ul>
        <ul class="legend legend-keys" id="map-keys"></ul>
        <p class="hint">Hover a marker for its numbers, click it to open the run (a point of several runs: its list of runs).</p>
      </aside>
    </div>`;
}

// Points at one (S, R) (other numerics, or perturbed and unperturbed runs) are set around their
// place, evenly on a circle of SPREAD radii, the coarsest grid first at the top, so none hides
// another.
const SPREAD = 1.15;
function placeOffsets(pts, radiusOf) {
  const at = new Map(); // place (mapnumerics.js: placeKey) -> the points there
  for (const p of pts) {
    const g = at.get(placeKey(p));
    if (g) g.push(p);
    else at.set(placeKey(p), [p]);
  }
  const off = new Map();
  for (const g of at.values()) {
    if (g.length < 2) continue;
    g.sort((a, b) => a.cells_per_unit - b.cells_per_unit || a.id - b.id);
    const r = radiusOf(g[0]);
    g.forEach((p, k) => {
      const a = -Math.PI / 2 + (2 * Math.PI * k) / g.length;
      off.set(p, [SPREAD * r * Math.cos(a), SPREAD * r * Math.sin(a)]);
    });
  }
  return off;
}

// The points whose markers reach into the plot area (a zoomed view leaves the others out of
// the drawing, the tooltips and the export), and the radius of each place that their spacing on
// screen allows (mapview.js: spacingRadii), at most the radius for their count.
function inView(plot, pts) {
  const pad = markerRadius(pts.length) * (SPREAD + 1.3);
  const shown = pts.filter((p) => {
    const x = plot.cx(p.S), y = plot.cy(p.R);
    return x >= -pad && y >= -pad && x <= plot.pw + pad && y <= plot.ph + pad;
  });
  const index = new Map(), xy = [], shared = []; // place -> its index in xy and shared
  for (const p of shown) {
    const k = placeKey(p);
    if (index.has(k)) shared[index.get(k)] = true;
    else { index.set(k, index.size); xy.push(plot.cx(p.S), plot.cy(p.R)); shared.push(false); }
  }
  const most = markerRadius(shown.length);
  const radii = spacingRadii(Float32Array.from(xy), most, shared);
  return { shown, most, radiusOf: (p) => radii[index.get(placeKey(p))] };
}

// Markers of the visible points in a stable draw order (categories by ORDER, classes last; finer
// resolution over coarser), each of its place's radius (radiusOf), at most `most`; `added`: the test of a point an adaptive planner added,
// or null. Returns the drawn points, their canvas positions, the counts of every visible point
// (in the view or not) and what the SVG export redraws (markers).
function drawPoints(plot, pts, all, { most, radiusOf }, added) {
  const off = placeOffsets(pts, radiusOf);
  const places = new Set(all.map(placeKey)).size;
  const drawn = pts.map((p) => ({ p, cat: p.cat }));
  drawn.sort((a, b) => (ORDER[a.cat] ?? 9) - (ORDER[b.cat] ?? 9) || a.p.cells_per_unit - b.p.cells_per_unit);
  const positions = new Float32Array(drawn.length * 2); // [x, y] per drawn point (canvas pixels)
  const counts = {};
  for (const p of all) counts[p.cat] = (counts[p.cat] || 0) + 1;
  const markers = [];
  for (let i = 0; i < drawn.length; i++) {
    const { p, cat } = drawn[i];
    const [dx, dy] = off.get(p) || [0, 0];
    const x = plot.cx(p.S) + dx, y = plot.cy(p.R) + dy, r = radiusOf(p);
    positions[2 * i] = x; positions[2 * i + 1] = y;
    markers.push({ cat, x, y, r, progress: p.progress, fade: p.fade, ring: p.ring, split: p.split, unsettled: p.unsettled, human: p.human, added: !!(added && added(p)) });
  }
  drawPointMarks(plot.ctx, markers);
  return { drawn, positions, counts, radius: most, markers, places };
}

function markerRadius(n) {
  return n > 3000 ? 2.6 : n > 600 ? 3.6 : n > 150 ? 5 : 7;
}

// A log axis's domain widened, when needed, so that markers of radius r (and their spread and
// rings) at the extreme values stay inside the px-long plot area instead of being cut at its
// frame.
function fitMarkers(dom, values, px, r) {
  const range = valueRange(values, true);
  if (!range) return dom;
  const lo = Math.log10(range[0]), hi = Math.log10(range[1]);
  let a = Math.log10(dom[0]), b = Math.log10(dom[1]);
  const need = (r * (SPREAD + 1.3) + 4) / px; // as a share of the axis
  for (let k = 0; k < 3; k++) { // the share grows with the span: settle in a few rounds
    const span = b - a;
    a = Math.min(a, lo - need * span);
    b = Math.max(b, hi + need * span);
  }
  return [10 ** a, 10 ** b];
}

// The buckling onset R_crit at phi as a dashed line with its label, when it is inside the plot
// (model: the phase map's answer's, what the engine predicts at phi).
function drawBuckling(plot, model) {
  const Rc = model?.buckling_R;
  if (!(Rc > plot.y.d0 && Rc < plot.y.d1)) return;
  const y = plot.y.map(Rc);
  svgEl('line', { x1: plot.m.l, x2: plot.m.l + plot.pw, y1: y, y2: y, class: 'overlay-line' }, plot.front);
  const t = svgEl('text', { x: plot.m.l + plot.pw - 8, y: y - 7, 'text-anchor': 'end', class: 'overlay-label' }, plot.front);
  // A phone's narrow plot takes the short label (the long one ran off the card).
  richText(t, plot.pw < 560 ? `R_{crit} ≈ ${sciText(Rc, 2)}` : `buckling onset R_{crit} = π²a²/12 ≈ ${sciText(Rc, 2)}   (strut aspect ratio a = ${model.strut_aspect_ratio.toFixed(3)})`);
}

// One legend line per class, then per state, each with its count.
function renderLegend(legend, counts) {
  legend.replaceChildren();
  const item = (cat, text, note) => {
    const li = document.createElement('li');
    li.dataset.cat = cat;
    li.dataset.count = String(counts[cat] || 0);
    if (!counts[cat]) li.classList.add('zero');
    li.append(swatch(cat));
    const name = document.createElement('span');
    name.className = 'legend-name';
    name.innerHTML = text;
    if (note) name.title = note;
    const n = document.createElement('span');
    n.className = 'legend-count';
    n.textContent = counts[cat] || 0;
    li.append(name, n);
    legend.append(li);
  };
  for (const [k, c] of Object.entries(CLASSES)) item(k, `<b>${k}</b> ${c.name}`);
  const sep = document.createElement('li');
  sep.className = 'legend-sep';
  legend.append(sep);
  for (const [k, s] of Object.entries(STATES)) item(k, s.name, s.note);
}

// The keys below the legend: marker fading by confidence, the runner-up ring of an unclassified
// run, a split and an unsettled point when some point has replicates, and the background's tint
// and grey when it is shown.
function keyItems(regions, replicated, added) {
  const items = [0.95, 0.5, 0.05].map((c) => ({ kind: 'confidence', mark: { cat: 'a', fade: confidenceFade(c) }, text: `confidence ${c}` }));
  items.push({ kind: 'runner-up', mark: { cat: 'unclassified', ring: 'b' }, text: 'unclassified, ringed by its runner-up' });
  if (replicated) {
    // The pie's key larger and without its ring (the next key's), so that the pie reads.
    items.push({ kind: 'split', mark: { cat: 'a', split: [['a', 0.75], ['b', 0.25]], r: 6.6 }, text: 'replicates split: pie of their classes (a 3 of 4)' });
    items.push({ kind: 'unsettled', mark: { cat: 'a', unsettled: true }, text: 'dashed: not robust (replicates split, failed or pending)' });
  }
  if (added) items.push({ kind: 'added', mark: { cat: 'a', added: true }, text: 'dot: added by the adaptive planner' });
  if (regions) {
    items.push({ kind: 'region', color: cellColor('a', 0), text: 'background: predicted class' });
    items.push({ kind: 'uncertain', color: cellColor('a', 1), text: 'grey: uncertain prediction' });
  }
  return items;
}

function renderKeys(list, items) {
  list.replaceChildren();
  for (const it of items) {
    const li = document.createElement('li');
    li.dataset.key = it.kind;
    let sw;
    if (it.color) {
      sw = document.createElement('span');
      sw.className = 'swatch region-swatch';
      sw.style.background = `rgb(${it.color.join(',')})`;
    } else {
      sw = swatch(it.mark.cat);
      const ctx = sw.getContext('2d');
      ctx.clearRect(0, 0, 16, 16);
      drawPointMark(ctx, { r: 4.6, ...it.mark, x: 8, y: 8 });
    }
    const name = document.createElement('span');
    name.className = 'legend-name';
    name.textContent = it.text;
    li.append(sw, name, document.createElement('span'));
    list.append(li);
  }
}

// The footer: how many points (and runs, when some point has replicates) at how many places,
// labelled, pending and robust; what the robust-only control hides.
function summaryHtml(counts, pts, phi, places, hidden) {
  const total = pts.length;
  const runs = pts.reduce((a, p) => a + p.runs.length, 0);
  const labelled = Object.keys(CLASSES).reduce((a, k) => a + (counts[k] || 0), 0);
  const pending = (counts.queued || 0) + (counts.running || 0);
  const what = runs === total && !hidden ? 'runs' : `points${runs !== total ? ` (${runs.toLocaleString()} runs)` : ''}`;
  const shared = total > places ? ` at ${places.toLocaleString()} places (${what === 'runs' ? 'runs' : 'points'} at one place are set around it)` : '';
  const robust = pts.some((p) => p.runs.length > 1) ? ` · ${pts.filter((p) => p.robust).length} robust` : '';
  const only = hidden ? ` · robust only: ${hidden.toLocaleString()} other point${hidden === 1 ? '' : 's'} hidden` : '';
  return `<b>${total.toLocaleString()}</b> ${what}${shared} at φ = ${phi} · ${labelled} labelled · ${pending} pending${robust}${only}`;
}

// The tooltip of a point of several runs: its majority and share, the classes of its
// replicates, its robustness, its readings as mean ± sd (n) and a link to each run.
function pointTipHtml(pt, numerics, pinned) {
  const { s, runs, cat } = pt;
  const labelled = s.labelled ?? 0;
  const cls = CLASSES[cat] ? `<span class="dot" style="background:${CLASSES[cat].color}"></span>${escapeHtml(label(cat))}` : escapeHtml(look(cat).name);
  const rows = [
    ['S', sci(pt.S)], ['R', sci(pt.R)], ['φ', s.phi],
    ['class', `${cls}${CLASSES[cat] ? ' <span class="muted-tt">(majority)</span>' : ''}`],
    ['share', s.share === null || s.share === undefined ? '—' : `${fixed(s.share, 2)} <span class="muted-tt">(${majorityCount(s)} of ${labelled} labelled)</span>`],
    ['classes', probabilitiesHtml(s.probabilities)],
    ['robust', s.robust ? 'yes: every replicate finished with this class' : `no: ${notRobustWhy(s)}`],
    ['runs', `${s.runs} · ${s.finished} finished · ${labelled} labelled`],
    ['<i>N</i><sub>r</sub>', spreadText(s.n_reflections, 2)],
    ['<i>c</i><sub>b</sub>/<i>V</i>', spreadText(s.band_speed_ratio, 3)],
    ['numerics', numerics],
  ];
  const head = `point ${s.point_id} · ${s.runs} runs${s.robust ? ' · <span class="robust-tag">robust</span>' : ''}`;
  const close = pinned ? '<button type="button" class="tt-close" aria-label="close">×</button>' : '';
  const foot = pinned ? `<div class="tt-foot"><a href="${runsHashOfPoint(s.point_id)}">these runs in the table</a></div>` : '<div class="tt-foot">click to pin, then open a run</div>';
  return `<div class="tt-head">${close}${head}</div><table>${rows.map(([k, v]) => `<tr><th>${k}</th><td>${v}</td></tr>`).join('')}</table>
    <div class="tt-runs">${runLinksHtml(runs)}</div>${foot}`;
}

function tooltipHtml(p, cat, numerics) {
  const rows = [
    ['S', sci(p.S)], ['R', sci(p.R)], ['φ', p.phi],
    ['class', CLASSES[cat] ? `<span class="dot" style="background:${CLASSES[cat].color}"></span>${escapeHtml(label(cat))}` : escapeHtml(look(cat).name)],
    ...humanTipRows(p),
    ['confidence', p.confidence === null ? '—' : fixed(p.confidence, 2)],
    ['runner-up', p.runner_up ? escapeHtml(label(p.runner_up)) : '—'],
    ['<i>N</i><sub>r</sub>', p.n_reflections ?? '—'],
    ['<i>c</i><sub>b</sub>/<i>V</i>', p.band_speed_ratio === null ? '—' : fixed(p.band_speed_ratio, 3)],
    ['state', escapeHtml(p.state) + (p.state === 'running' && p.progress_eps !== null ? `, ε = ${fixed(p.progress_eps, 3)} of ${fixed(p.eps_end, 2)}` : '')],
    ['numerics', numerics],
  ];
  return `<div class="tt-head">run ${p.job_id}</div><table>${rows.map(([k, v]) => `<tr><th>${k}</th><td>${v}</td></tr>`).join('')}</table>`;
}

// Shows the tooltip beside the mouse, on the other side when it would leave the window.
function placeTooltip(tooltip, ev) {
  tooltip.hidden = false;
  const w = tooltip.offsetWidth, h = tooltip.offsetHeight;
  let x = ev.clientX + 16, y = ev.clientY + 14;
  if (x + w > window.innerWidth - 8) x = ev.clientX - w - 16;
  if (y + h > window.innerHeight - 8) y = ev.clientY - h - 14;
  tooltip.style.left = `${x + window.scrollX}px`;
  tooltip.style.top = `${y + window.scrollY}px`;
}

// The tooltip over the background: the class predicted under the mouse and its uncertainty.
function regionTipHtml(cell) {
  const c = CLASSES[cell.cls];
  const what = c ? `<span class="dot" style="background:${c.color}"></span>${escapeHtml(label(cell.cls))}` : 'no labelled run within reach';
  return `<div class="tt-head">predicted region</div><table><tr><th>class</th><td>${what}</td></tr><tr><th>uncertainty</th><td>${fixed(cell.u, 2)}</td></tr></table>`;
}

// For the browser tests and the render benchmark (bench/dashboard): a marker per point, with its
// first run's id (job_id: the run of a point of one run) and all its runs (jobs).
function publishRender(root, state, ms, plot, { drawn, positions, counts, radius, markers }, regions) {
  const hook = (window.__dashboard ||= { renders: [] });
  hook.renders.push(ms);
  hook.renderedAt = performance.now();
  hook.phaseMap = {
    phi: state.phi, robustOnly: state.robust, numerics: numericsChoice(state), view: plotView(plot), zoomed: !!state.view, count: drawn.length, runs: drawn.reduce((a, d) => a + d.p.runs.length, 0), counts, renderMs: ms, radius,
    area: { width: plot.pw, height: plot.ph }, // the canvas over the plot area, in CSS pixels
    regions: regions ? { grid: regions.data.grid, runs: regions.data.runs, x0: regions.x0, y0: regions.y0, x1: regions.x1, y1: regions.y1 } : null,
    points: drawn.map(({ p, cat }, i) => ({
      point_id: p.id, job_id: p.runs[0].job_id, jobs: p.runs.map((q) => q.job_id), cat, color: look(cat).color,
      x: positions[2 * i], y: positions[2 * i + 1], fade: markers[i].fade, ring: markers[i].ring,
      share: p.s.share ?? null, probabilities: p.s.probabilities ?? null, robust: p.robust, unsettled: p.unsettled, split: p.split,
      cells_per_unit: p.cells_per_unit, added: markers[i].added, r: markers[i].r,
    })),
  };
  root.dispatchEvent(new CustomEvent('phasemap:rendered', { bubbles: true, detail: { ms, count: drawn.length } }));
}

// The page: its filters and data (state, the query's keys first), its controls and boxes (el),
// what the last render drew (shown) and its timers. Every part below takes it explicitly.
function createPage(root, params) {
  root.innerHTML = pageHtml();
  const $ = (id) => root.querySelector(`#${id}`);
  return {
    root,
    state: {
      phi: params.phi ? Number(params.phi) : null,
      // The grid filter ('all' or cells per unit cell) and, with 'all', whether each place shows
      // its finest points only (the default: no cpu in the URL; cpu=all shows every grid).
      cpu: params.cpu && params.cpu !== FINEST ? params.cpu : 'all',
      finest: !params.cpu || params.cpu === FINEST,
      view: viewOf(params), // the part of the plane shown (mapview.js), null: every point
      sweep: params.sweep || '',
      geometry: params.geometry || '', // the runs' geometry ('': the 2D pseudo-1D column)
      buckling: params.buckling !== '0',
      regions: params.regions !== '0',
      robust: params.robust === '1', // robust points only
      // The answer's runs and its points (points.js: mapPoints), and what they were read from.
      runs: [], points: [], signature: '', answer: null, presets: [], sweeps: [], updated: null, error: null,
      // The last /phase-map/regions answer, the filters it is for, and what it was read from.
      regionData: null, regionFor: '', regionKey: '',
      // The chosen adaptive sweep's plan (GET /sweeps/{id}/plan) and its sweep's id, or null.
      plan: null, planFor: null, planAt: 0,
    },
    el: {
      plotBox: $('map-plot'), summary: $('map-summary'), live: $('map-live'),
      phi: $('map-phi'), cpu: $('map-cpu'), sweep: $('map-sweep'), geometry: $('map-geometry'), buckling: $('map-buckling'), regions: $('map-regions'), robust: $('map-robust'),
      exportSvg: $('map-export-svg'), exportPng: $('map-export-png'), legend: $('map-legend'), keys: $('map-keys'),
      reset: $('map-reset'), viewText: $('map-view-text'), numerics: $('map-numerics'), plan: $('map-plan'),
    },
    tooltip: document.getElementById('tooltip'),
    // What the last render drew: the plot, the points in draw order with their canvas positions
    // (Float32Array [x, y] per point), the regions shown and the figure for the export.
    shown: { plot: null, drawn: [], positions: null, regions: null, figure: null },
    pinned: null, // the point whose tooltip is pinned (its runs' links can be clicked), or null
    view: null, // the wheel, drag and pinch handlers (mapview.js: wireView)
    dragging: false,
    alive: true,
    timer: null, // the next poll
    resizeTimer: null, // the redraw a moment after the last resize
    onResize: null,
    onKey: null,
  };
}

function syncUrl(state) {
  setParams({ phi: state.phi, cpu: state.cpu !== 'all' ? state.cpu : state.finest ? '' : 'all', sweep: state.sweep, geometry: state.geometry, buckling: state.buckling ? '' : '0', regions: state.regions ? '' : '0', robust: state.robust ? '1' : '', ...viewParams(state.view) });
}

// A new view (null: every point), in the URL and drawn.
function setView(page, view) {
  page.state.view = view;
  syncUrl(page.state);
  render(page);
}

// The wheel, drag and pinch handlers on the plot's box; a drag hides the hover tooltip.
function wireZoom(page) {
  page.view = wireView(page.el.plotBox, {
    plot: () => page.shown.plot,
    onView: (view) => { if (page.alive) setView(page, view); },
    onDrag: (on) => {
      page.dragging = on;
      page.el.plotBox.classList.toggle('dragging', on);
      if (on && !page.pinned) page.tooltip.hidden = true;
    },
  });
}

// The test of "the planner added this point" of the chosen adaptive sweep, or null.
function planAdded(state) {
  if (!state.sweep || state.planFor !== state.sweep) return null;
  return addedByPlanner(state.sweeps.find((x) => String(x.id) === String(state.sweep)), state.plan);
}

// Reads the chosen sweep's plan when it is adaptive: at most every PLAN_MS, and at once when
// the sweep changed. A grid sweep, or none, has none.
const PLAN_MS = 10000;
async function loadPlan(page) {
  const { state } = page;
  const sweep = state.sweeps.find((x) => String(x.id) === String(state.sweep));
  if (!sweep?.request?.adaptive) {
    if (state.plan || state.planFor) { state.plan = null; state.planFor = null; render(page); }
    return;
  }
  if (state.planFor === state.sweep && performance.now() - state.planAt < PLAN_MS) return;
  const id = state.sweep;
  state.planAt = performance.now();
  try {
    const plan = await api.sweepPlan(id);
    if (!page.alive || id !== state.sweep) return;
    state.plan = plan;
    state.planFor = id;
  } catch (e) {
    state.plan = null;
    state.planFor = id; // the initial grid is still known from the request
    page.el.plan.title = `plan: ${e.message}`;
  }
  render(page);
}

// The captions under the map: the view, the numerics shown, an adaptive sweep's plan.
function renderNotes(page, added, pts) {
  const { state, el } = page;
  el.reset.disabled = !state.view;
  el.viewText.textContent = state.view
    ? `log10 S ${state.view.S[0].toFixed(2)} to ${state.view.S[1].toFixed(2)}, log10 R ${state.view.R[0].toFixed(2)} to ${state.view.R[1].toFixed(2)}`
    : 'wheel or pinch: zoom · drag: pan';
  el.numerics.textContent = numericsCaption(numericsChoice(state), state.points);
  const n = added ? pts.filter(added).length : 0;
  el.plan.hidden = !added;
  el.plan.innerHTML = added ? planCaption(state.plan, n, pts.length - n) : '';
}

// The phis of every sweep and the chosen one (without one: the newest sweep's first, else 0.4).
function fillPhiOptions(state, select) {
  const phis = new Set();
  for (const s of state.sweeps) for (const p of s.phis || []) phis.add(Number(p.toPrecision(12)));
  if (state.phi === null) {
    const newest = state.sweeps[0]?.phis?.[0];
    state.phi = Number.isFinite(newest) ? newest : 0.4;
  }
  phis.add(state.phi);
  const sorted = [...phis].sort((a, b) => a - b);
  select.replaceChildren(...sorted.map((p) => new Option(`φ = ${p}`, p, false, p === state.phi)));
}

function fillSweepOptions(state, select) {
  const keep = state.sweep;
  select.replaceChildren(new Option('all sweeps', ''), ...state.sweeps.map((s) => new Option(`#${s.id} ${s.name}`, s.id)));
  select.value = keep;
}

// A grid as its cells per unit cell and across a strut, with the preset's name when a preset
// gives it: the fewest cells per unit cell that reach the preset's cells across the strut, so
// the grid's own count is at most one strut's share of a cell above the preset's.
function presetName(state, cpu) {
  const pt = state.runs.find((x) => x.cells_per_unit === cpu);
  const cps = pt ? pt.cells_per_strut : null;
  const share = cps ? cps / cpu : 0;
  const p = cps ? state.presets.find((x) => cps >= x.cells_per_strut - 1e-9 && cps - share < x.cells_per_strut - 1e-9) : null;
  const what = cps ? `${cpu} cells/unit, ${cps.toFixed(1)} across a strut` : `${cpu} cells/unit`;
  return p ? `${p.name} (${what})` : what;
}

// The grids of the runs, and the chosen one even when no run has it.
function fillCpuOptions(state, select) {
  const cpus = [...new Set(state.runs.map((p) => p.cells_per_unit))].sort((a, b) => a - b);
  const keep = numericsChoice(state);
  select.replaceChildren(new Option('finest run per point', FINEST), new Option('all resolutions', 'all'), ...cpus.map((c) => new Option(presetName(state, c), String(c))));
  if (keep !== 'all' && keep !== FINEST && !cpus.includes(Number(keep))) select.append(new Option(presetName(state, Number(keep)), keep));
  select.value = keep;
}

// The runs of the chosen grid (what the regions are read from), and its points (a point's runs
// share their grid), robust ones only when asked.
const ofGrid = (state, list) => (state.cpu === 'all' ? list : list.filter((p) => String(p.cells_per_unit) === String(state.cpu)));
const visibleRuns = (state) => ofGrid(state, state.runs);
// The numerics control's choice: FINEST (every grid, each place's finest), 'all' or one grid.
const numericsChoice = (state) => (state.cpu === 'all' && state.finest ? FINEST : state.cpu);
const pointsOfNumerics = (state) => ofNumerics(numericsChoice(state), state.points);
function visiblePoints(state) {
  const pts = pointsOfNumerics(state);
  return state.robust ? pts.filter((p) => p.robust) : pts;
}

const regionFilters = (state) => JSON.stringify([state.phi, state.sweep, state.cpu, state.geometry]);

// What the regions answer depends on: the filters, the labelled runs and the box's extent.
function regionKey(state) {
  let lo = [Infinity, Infinity], hi = [-Infinity, -Infinity];
  const labels = [];
  for (const p of visibleRuns(state)) {
    lo = [Math.min(lo[0], p.S), Math.min(lo[1], p.R)]; hi = [Math.max(hi[0], p.S), Math.max(hi[1], p.R)];
    if (p.class) labels.push([p.job_id, p.state, p.status, p.class, p.confidence, p.runner_up]);
  }
  return JSON.stringify([regionFilters(state), lo, hi, labels]);
}

// Reads the regions when what they depend on changed (not at every progress heartbeat).
async function loadRegions(page) {
  const { state } = page;
  if (!state.regions) return;
  const key = regionKey(state);
  if (key === state.regionKey) return;
  try {
    const data = await api.regions(state.phi, state.sweep, state.cpu === 'all' ? '' : state.cpu, undefined, state.geometry);
    if (!page.alive || key !== regionKey(state)) return; // the filters changed meanwhile
    state.regionKey = key;
    state.regionFor = regionFilters(state);
    state.regionData = data;
    render(page);
  } catch (e) {
    state.regionData = null; // no background; the map itself still shows
    page.el.live.title = `predicted regions: ${e.message}`;
  }
}

// The figure's size for the page's width and the window's height (on a phone's narrow page, as
// wide as the card and about square).
function figureSize(plotBox) {
  const width = Math.max(300, Math.min(1100, plotBox.clientWidth || 760));
  return { width, height: Math.round(Math.min(width * (width < 500 ? 1 : 0.68), Math.max(480, window.innerHeight - 250))) };
}

// A new plot in the box, replacing the last: log S against log R, each axis the view's (decades)
// or, without one, spanning the points with room at its ends for markers of radius r.
function newPlot(plotBox, phi, pts, r, view) {
  const { width, height } = figureSize(plotBox);
  const margin = { l: 78, r: 24, t: 18, b: 60 };
  const xDom = view ? view.S.map((v) => 10 ** v) : fitMarkers(logExtent(pts.map((p) => p.S), [1e-4, 1]), pts.map((p) => p.S), width - margin.l - margin.r, r);
  const yDom = view ? view.R.map((v) => 10 ** v) : fitMarkers(logExtent(pts.map((p) => p.R), [1e-6, 1]), pts.map((p) => p.R), height - margin.t - margin.b, r);
  plotBox.replaceChildren();
  return new Plot(plotBox, {
    width, height, canvas: true, title: `phase map at phi = ${phi}`,
    margin,
    x: { kind: 'log', domain: xDom, label: 'Mach number S = V / √(E/ρ)' },
    y: { kind: 'log', domain: yDom, label: 'relative strength R = q_{y} / E' },
  });
}

// The note in an empty plot: why nothing shows.
function drawEmptyNote(plot, state) {
  const t = svgEl('text', { x: plot.m.l + plot.pw / 2, y: plot.m.t + plot.ph / 2, 'text-anchor': 'middle', class: 'empty-note' }, plot.front);
  t.textContent = state.error ? `could not load: ${state.error}`
    : state.robust && pointsOfNumerics(state).length ? `No robust point at φ = ${state.phi}: none has two replicates that all agree.`
      : `No runs at φ = ${state.phi} yet: start a sweep on the Sweeps page.`;
}

// The map of the visible points (the regions under the markers, the markers, the overlays), the
// legend, keys and summary beside it; keeps what it drew for the mouse and the export.
function render(page) {
  const t0 = performance.now();
  const { state, el, shown } = page;
  const pts = visiblePoints(state);
  // The axes span every point of the grid: "robust only" hides markers, it does not move them
  // (nor leave the regions, read over every run, short of the axes).
  const all = pointsOfNumerics(state);
  const plot = (shown.plot = newPlot(el.plotBox, state.phi, all, markerRadius(pts.length), state.view));
  page.view?.settle();
  // Until new regions arrive the last ones of the same filters stay (no flicker on updates).
  const regionData = state.regions && all.length && state.regionFor === regionFilters(state) ? state.regionData : null;
  const drawnRegions = drawRegions(plot, regionData);
  shown.regions = drawnRegions ? { ...drawnRegions, data: regionData } : null;
  const sizes = inView(plot, pts);
  const inside = sizes.shown;
  const added = planAdded(state);
  const marks = drawPoints(plot, inside, pts, sizes, added);
  shown.drawn = marks.drawn;
  shown.positions = marks.positions;
  if (state.buckling) drawBuckling(plot, state.answer?.model);
  if (!pts.length) drawEmptyNote(plot, state);
  plot.canvas.dataset.count = String(marks.drawn.length);
  plot.canvas.dataset.counts = JSON.stringify(marks.counts);
  wireCanvas(page, plot);
  renderLegend(el.legend, marks.counts);
  const keys = keyItems(shown.regions, state.points.some((p) => p.runs.length > 1), marks.markers.some((m) => m.added));
  renderKeys(el.keys, keys);
  const hidden = all.length - pts.length;
  el.summary.innerHTML = summaryHtml(marks.counts, pts, state.phi, marks.places, hidden) + (state.view ? ` · <span class="in-view">${inside.length.toLocaleString()} in the view</span>` : '');
  renderNotes(page, added, pts);
  shown.figure = figureOf(state, plot, marks, shown.regions, keys);
  refreshPinned(page, inside);
  page.root.querySelector('#map-to-runs').href = runsHashOfMap(state);
  publishRender(page.root, state, performance.now() - t0, plot, marks, shown.regions);
}

// What the export draws of a render: the plot, its markers and regions, the legend with counts
// (the states only where some run has them) and the keys, a title and a note of the filters.
function figureOf(state, plot, marks, regions, keys) {
  return {
    plot, markers: marks.markers, regions,
    legend: [...Object.entries(CLASSES).map(([k, c]) => ({ cat: k, name: `${k} ${c.name}`, count: marks.counts[k] || 0 })),
      ...Object.entries(STATES).filter(([k]) => marks.counts[k]).map(([k, s]) => ({ cat: k, name: s.name, count: marks.counts[k] })),
      ...keys.map((k) => ({ mark: k.mark, color: k.color, name: k.text.replace(', ringed by its runner-up', ', ring: runner-up') }))],
    title: `Phase map at phi = ${state.phi}`,
    note: [`φ = ${state.phi}${state.geometry ? `, ${state.geometry}` : ''}${state.sweep ? `, sweep ${state.sweep}` : ''}${state.cpu !== 'all' ? `, ${state.cpu} cells per unit cell` : state.finest ? ', finest run per point' : ''}${state.robust ? ', robust points only' : ''}`,
      ...(state.view ? [`view: log10 S ${state.view.S.join(' to ')}, log10 R ${state.view.R.join(' to ')}`] : []),
      ...(regions ? [`regions from ${regions.data.runs} labelled runs`] : [])],
  };
}

// Hover and click on a new canvas; the handlers read the page's last render when they run.
function wireCanvas(page, plot) {
  plot.canvas.addEventListener('mousemove', (ev) => onMove(page, ev));
  plot.canvas.addEventListener('mouseleave', () => { if (!page.pinned) page.tooltip.hidden = true; page.shown.plot.canvas.style.cursor = ''; });
  plot.canvas.addEventListener('click', (ev) => onClick(page, ev));
}

function exportName(state, ext) {
  const parts = [`phase-map-phi${state.phi}`];
  if (state.sweep) parts.push(`sweep${state.sweep}`);
  if (state.cpu !== 'all') parts.push(`cpu${state.cpu}`);
  if (state.view) parts.push('zoomed');
  if (state.robust) parts.push('robust');
  return `${parts.join('-')}.${ext}`;
}

async function exportFigure(page, kind) {
  const { figure } = page.shown;
  if (!figure) return;
  // The export's code (mapexport.js, svgcanvas.js) loads on the first export, not with the page.
  const { download, mapSvg, pngBlob, svgText } = await import('../mapexport.js');
  const svg = mapSvg(figure);
  if (kind === 'svg') download(new Blob([svgText(svg)], { type: 'image/svg+xml' }), exportName(page.state, 'svg'));
  else download(await pngBlob(svg), exportName(page.state, 'png'));
}

// The index of the drawn point within 14 px of the mouse, the topmost of the nearest; -1: none.
function nearest(shown, ev) {
  const { plot, drawn, positions } = shown;
  if (!positions) return -1;
  const rect = plot.canvas.getBoundingClientRect();
  const mx = ev.clientX - rect.left, my = ev.clientY - rect.top;
  let best = -1, bd = 14 * 14;
  for (let i = drawn.length - 1; i >= 0; i--) { // topmost first
    const dx = positions[2 * i] - mx, dy = positions[2 * i + 1] - my;
    const d = dx * dx + dy * dy;
    if (d < bd) { bd = d; best = i; }
  }
  return best;
}

// The tooltip of the point under the mouse, else of the predicted region there, else none; a
// pinned tooltip stays until it is closed.
function onMove(page, ev) {
  const { shown, tooltip } = page;
  const { plot } = shown;
  if (page.dragging) return;
  const i = nearest(shown, ev);
  if (page.pinned) { plot.canvas.style.cursor = i < 0 ? '' : 'pointer'; return; }
  if (i < 0) {
    plot.canvas.style.cursor = '';
    const rect = plot.canvas.getBoundingClientRect();
    const cell = shown.regions && cellAt(plot, shown.regions.data, ev.clientX - rect.left, ev.clientY - rect.top);
    if (!cell) { tooltip.hidden = true; return; }
    tooltip.innerHTML = regionTipHtml(cell);
    placeTooltip(tooltip, ev);
    return;
  }
  plot.canvas.style.cursor = 'pointer';
  tooltip.innerHTML = tipOf(page, shown.drawn[i].p, false);
  placeTooltip(tooltip, ev);
}

// A point of one run shows that run's numbers; a point of several its replicates'.
function tipOf(page, p, pinned) {
  const added = planAdded(page.state);
  const numerics = presetName(page.state, p.cells_per_unit) + (added ? `<br><span class="muted-tt">${added(p) ? 'added by the adaptive planner' : 'of the initial grid'}</span>` : '');
  return p.runs.length === 1 ? tooltipHtml(p.runs[0], p.cat, numerics) : pointTipHtml(p, numerics, pinned);
}

// A click on a point of one run opens the run; on a point of several it pins the point's
// tooltip (its runs' links can then be clicked); elsewhere it closes a pinned tooltip.
function onClick(page, ev) {
  const { shown } = page;
  if (page.view?.wasDrag()) return; // the end of a pan, not a click
  const i = nearest(shown, ev);
  if (i < 0) { unpin(page); page.tooltip.hidden = true; return; }
  const { p } = shown.drawn[i];
  if (p.runs.length === 1) { location.hash = `#/run/${p.runs[0].job_id}`; return; }
  unpin(page);
  page.pinned = p;
  page.tooltip.innerHTML = tipOf(page, p, true);
  page.tooltip.classList.add('pinned');
  page.tooltip.dataset.point = String(p.id);
  wireClose(page);
  placeTooltip(page.tooltip, ev);
}

// After a redraw a pinned tooltip shows its point's new numbers where it is, or closes when the
// point is no longer shown.
function refreshPinned(page, pts) {
  if (!page.pinned) return;
  const p = pts.find((q) => q.id === page.pinned.id && q.runs.length > 1);
  if (!p) { unpin(page); page.tooltip.hidden = true; return; }
  page.pinned = p;
  page.tooltip.innerHTML = tipOf(page, p, true);
  wireClose(page);
  // Beside the point where the view now draws it.
  const i = page.shown.drawn.findIndex((d) => d.p === p);
  const rect = page.shown.plot.canvas.getBoundingClientRect();
  if (i >= 0) placeTooltip(page.tooltip, { clientX: rect.left + page.shown.positions[2 * i], clientY: rect.top + page.shown.positions[2 * i + 1] });
}

function wireClose(page) {
  page.tooltip.querySelector('.tt-close')?.addEventListener('click', () => { unpin(page); page.tooltip.hidden = true; });
}

function unpin(page) {
  if (!page.pinned) return;
  page.pinned = null;
  page.tooltip.classList.remove('pinned');
  delete page.tooltip.dataset.point;
}

function showLive(live, state) {
  live.innerHTML = `<span class="pulse"></span>live · updated ${state.updated.toLocaleTimeString()}`;
  live.className = 'live';
}

function showOffline(live, state) {
  live.textContent = `offline: ${state.error}; retrying`;
  live.className = 'live off';
}

// Takes a /phase-map answer; redraws (with the numerics' options) only when its points changed.
function takeAnswer(page, data) {
  const { state } = page;
  state.error = null;
  state.updated = new Date();
  // An unchanged map comes back as the same object (a 304 to If-None-Match).
  const sig = data === state.answer ? state.signature : JSON.stringify([data.points, data.summaries]);
  state.answer = data;
  if (sig !== state.signature) {
    state.signature = sig;
    state.runs = data.points;
    state.points = mapPoints(data);
    fillCpuOptions(state, page.el.cpu);
    render(page);
  }
}

// Reads /phase-map while the tab is visible and redraws only when the answer changed.
async function poll(page) {
  if (!page.alive) return;
  clearTimeout(page.timer);
  if (!document.hidden) {
    const { state, el } = page;
    try {
      const data = await api.phaseMap(state.phi, state.sweep, '', state.geometry);
      if (!page.alive) return;
      takeAnswer(page, data);
      showLive(el.live, state);
      await loadRegions(page);
      await loadPlan(page);
    } catch (e) {
      state.error = e.message;
      showOffline(el.live, state);
    }
  }
  if (page.alive) page.timer = setTimeout(() => poll(page), POLL_MS);
}

// The controls start from the query and write back to it. Another phi or sweep is another
// answer of the server (read now); another grid or the overlays redraw what the page has.
function wireControls(page) {
  const { state, el } = page;
  el.buckling.checked = state.buckling;
  el.regions.checked = state.regions;
  el.robust.checked = state.robust;
  el.phi.addEventListener('change', () => { state.phi = Number(el.phi.value); state.signature = ''; state.answer = null; syncUrl(state); poll(page); });
  el.cpu.addEventListener('change', () => {
    const v = el.cpu.value;
    state.cpu = v === FINEST ? 'all' : v;
    state.finest = v === FINEST;
    syncUrl(state); render(page); loadRegions(page);
  });
  el.reset.addEventListener('click', () => setView(page, null));
  el.geometry.value = state.geometry;
  el.geometry.addEventListener('change', () => { state.geometry = el.geometry.value; state.signature = ''; state.answer = null; syncUrl(state); poll(page); });
  el.sweep.addEventListener('change', () => { state.sweep = el.sweep.value; state.signature = ''; state.answer = null; state.plan = null; state.planFor = null; syncUrl(state); poll(page); });
  el.buckling.addEventListener('change', () => { state.buckling = el.buckling.checked; syncUrl(state); render(page); });
  el.regions.addEventListener('change', () => { state.regions = el.regions.checked; syncUrl(state); render(page); loadRegions(page); });
  // Robust only hides points; the regions stay those of every labelled run.
  el.robust.addEventListener('change', () => { state.robust = el.robust.checked; syncUrl(state); render(page); });
  page.onKey = (ev) => { if (ev.key === 'Escape' && page.pinned) { unpin(page); page.tooltip.hidden = true; } };
  document.addEventListener('keydown', page.onKey);
  el.exportSvg.addEventListener('click', () => exportFigure(page, 'svg'));
  el.exportPng.addEventListener('click', () => exportFigure(page, 'png'));
}

// Redraws after a resize only when the figure's size or the canvas's pixel density changes
// (a zoom), not for every window event.
function watchResize(page) {
  page.onResize = () => {
    clearTimeout(page.resizeTimer);
    page.resizeTimer = setTimeout(() => {
      if (!page.alive) return;
      const { plot } = page.shown;
      const { width, height } = figureSize(page.el.plotBox);
      const dpr = window.devicePixelRatio || 1;
      if (!plot || width !== plot.opts.width || height !== plot.opts.height || plot.canvas.width !== Math.round(plot.pw * dpr)) render(page);
    }, 150);
  };
  window.addEventListener('resize', page.onResize);
}

// The sweeps (their phis and names) and the presets (the grids' names) fill the controls; then
// the first render and the polling.
async function start(page) {
  const [sw, pr] = await Promise.allSettled([api.sweeps(1000), api.presets()]);
  if (!page.alive) return;
  const { state, el } = page;
  state.sweeps = sw.status === 'fulfilled' ? sw.value.sweeps : [];
  state.presets = pr.status === 'fulfilled' ? pr.value.presets : [];
  fillPhiOptions(state, el.phi);
  fillSweepOptions(state, el.sweep);
  fillCpuOptions(state, el.cpu);
  render(page);
  poll(page);
}

function stop(page) {
  page.alive = false;
  clearTimeout(page.timer);
  clearTimeout(page.resizeTimer);
  window.removeEventListener('resize', page.onResize);
  document.removeEventListener('keydown', page.onKey);
  page.view?.remove();
  unpin(page);
  page.tooltip.hidden = true;
}

export function mount(root, params) {
  const page = createPage(root, params);
  wireControls(page);
  wireZoom(page);
  watchResize(page);
  start(page);
  return () => stop(page);
}
