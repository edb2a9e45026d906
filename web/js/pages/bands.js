// Band speed: c_b/V against q_y/(rho V^2) = R/S^2 on log-log axes, coloured by the number of
// reflections N_r, with the uncertainty of each c_b/V as an error bar (Fig. 3 of the paper), from
// the points of one phi labelled as bands: a point of one run as that run (its c_b/V ± its
// uncertainty), a point of several runs (replicates, docs/replicates.md) at the mean of its
// majority's readings ± their standard deviation. Points that cannot be plotted are counted with
// the reason.
import { api } from '../api.js';
import { CLASSES, label } from '../classes.js';
import { majorityRuns, mapPoints, notRobustWhy, probabilitiesHtml, spreadText } from '../points.js';
import { Plot, logExtent, svgEl } from '../plot.js';
import { NR_MAX, nrColor } from '../reflections.js';
import { stressRatio } from '../physics.js';
import { sci, fixed, escapeHtml } from '../format.js';
import { setParams } from '../router.js';

const POLL_MS = 4000;
const CAP_PX = 4; // half the width of an error bar's cap
// ... and of a replicate mean's (± their standard deviation): wider than the marker (6 px), so
// that a bar of the spread of replicates reads apart from a run's own uncertainty.
const SD_CAP_PX = 9;

// The classes Fig. 3 plots: the bands, (a) non-reflecting and (b) reflecting.
export const BAND_CLASSES = ['a', 'b'];

// The readings of c_b/V the classifier gives (docs/classifier.md), each with its uncertainty: the
// first leg's, and the early stage's in the velocity map.
export const READINGS = {
  fit: { value: 'band_speed_ratio', error: 'band_speed_error', name: 'least-squares fit', note: 'slope of the leading edge, ± its standard error' },
  transit: { value: 'band_speed_transit', error: 'band_speed_transit_error', name: 'transit', note: 'travel over strain between the first and last points of the leg, each end ± a row and the edge\'s step of a unit cell' },
  early: { value: 'band_speed_early', error: 'band_speed_early_error', name: 'early stage, middle', note: 'the band\'s middle (rows at half the plate speed) over its first leg in the column\'s upper half, from the velocity map, ± its standard error' },
  lead: { value: 'band_speed_lead', error: 'band_speed_lead_error', name: 'early stage, leading edge', note: 'the band\'s leading edge (10 % of the step from the material ahead to the plate speed) over its first leg in the column\'s upper half, from the velocity map, ± its standard error' },
};

// Why a point at this phi is not on the plot, in the order the page lists them (what: "run" when
// every point is one run, else "point").
const LEFT_OFF = {
  missing: (n) => `${n} band${n === 1 ? '' : 's'} without a measured <i>c</i><sub>b</sub>/<i>V</i>`,
  nonPositive: (n) => `${n} band${n === 1 ? '' : 's'} with <i>c</i><sub>b</sub>/<i>V</i> ≤ 0 (a log axis cannot show ${n === 1 ? 'it' : 'them'})`,
  notBand: (n, what) => `${n} ${what}${n === 1 ? '' : 's'} of class c to f (not a band)`,
  unlabelled: (n, what) => `${n} ${what}${n === 1 ? '' : 's'} without a label (pending, failed, unstable or unclassified)`,
};

const finite = (x) => typeof x === 'number' && Number.isFinite(x);
const errorOf = (e) => (finite(e) && e >= 0 ? e : null);

// A point's reading: { label, v, e, n, kind, nr, run } or { label, v: null } when it has none. A
// point of one run reads as the run (its classifier's label, its value ± its uncertainty: kind
// 'run'); a point of several as the summary of its replicates: the majority's label, the mean of
// its runs' readings ± their sample standard deviation (kind 'sd', n >= 2), or, when only one of
// them has the reading, that run's value ± its uncertainty. nr: N_r (the mean of a point's),
// run: the run its marker opens.
export function pointReading(pt, reading = 'fit') {
  const { value, error } = READINGS[reading];
  if (pt.runs.length === 1) {
    const p = pt.runs[0];
    return { label: p.class, v: finite(p[value]) ? p[value] : null, e: errorOf(p[error]), n: 1, kind: 'run', nr: p.n_reflections ?? 0, run: p };
  }
  const { s } = pt;
  const majority = majorityRuns(pt);
  const spread = s[value];
  const nr = Math.round(s.n_reflections?.mean ?? 0);
  if (!spread || !finite(spread.mean)) return { label: s.label, v: null, run: majority[0] || pt.runs[0] };
  if (spread.n >= 2 && finite(spread.sd)) return { label: s.label, v: spread.mean, e: spread.sd, n: spread.n, kind: 'sd', nr, run: majority[0] };
  const one = majority.find((p) => finite(p[value])) || majority[0] || pt.runs[0];
  return { label: s.label, v: spread.mean, e: errorOf(one[error]), n: spread.n, kind: 'run', nr, run: one };
}

// Splits the points of one phi into the plotted bands and, per reason of LEFT_OFF, those left
// off. A plotted band's error is null when it has no finite, non-negative uncertainty.
export function splitPoints(points, reading = 'fit') {
  const shown = [];
  const leftOff = Object.fromEntries(Object.keys(LEFT_OFF).map((k) => [k, []]));
  for (const pt of points) {
    const r = pointReading(pt, reading);
    if (!r.label) leftOff.unlabelled.push(pt);
    else if (!BAND_CLASSES.includes(r.label)) leftOff.notBand.push(pt);
    else if (r.v === null) leftOff.missing.push({ pt, run: r.run });
    else if (r.v <= 0) leftOff.nonPositive.push({ pt, run: r.run });
    else shown.push({ pt, ...r });
  }
  return { shown, leftOff };
}

function pageHtml() {
  const readings = Object.entries(READINGS).map(([k, r]) => `<option value="${k}">${r.name}</option>`).join('');
  return `
    <div class="page-head">
      <h1>Band speed</h1>
      <p class="sub">Speed of the compaction band <i>c</i><sub>b</sub>/<i>V</i> against the ratio of yield to inertial stress
        <i>q</i><sub>y</sub>/(ρ<i>V</i>²) = <i>R</i>/<i>S</i>², for every point at one φ labelled as a band, (a) or (b), with the uncertainty of its band speed
        (a point run several times: the mean of its replicates ± their standard deviation).</p>
    </div>
    <div class="layout-map">
      <section class="card figure"><div class="figure-plot" id="bands-plot"></div>
        <div class="figure-foot"><span id="bands-summary" class="summary"></span></div>
        <ul class="left-off" id="bands-left-off"></ul></section>
      <aside class="card controls">
        <label class="field">Solid fraction φ <select id="bands-phi" aria-label="solid fraction phi"></select></label>
        <label class="field"><span>Reading of <i>c</i><sub>b</sub>/<i>V</i></span> <select id="bands-reading" aria-label="reading of the band speed">${readings}</select></label>
        <p class="hint" id="bands-reading-note"></p>
        <h2 class="legend-title">Reflections <i>N</i><sub>r</sub></h2>
        <ul class="legend" id="bands-legend"></ul>
        <p class="hint">Dashed: a non-reflecting band, <i>c</i><sub>b</sub>/<i>V</i> = 1/(1 − φ). Reflecting bands are faster and grow as a power law of <i>R</i>/<i>S</i>².
          Bars: ± the uncertainty of <i>c</i><sub>b</sub>/<i>V</i>; with wide caps, a point with replicates at their mean ± their standard deviation; a bar without a cap runs off the axis.
          Circles: regular structures; squares: random structures (as in the paper's Fig. 3).</p>
      </aside>
    </div>`;
}

// The dashed line of a non-reflecting band, c_b/V = 1/(1 - phi) (the engine's, from the phase
// map's answer), with its label.
function drawNonReflecting(plot, c0) {
  if (!(c0 > 0)) return;
  const y = plot.y.map(c0);
  svgEl('line', { x1: plot.m.l, x2: plot.m.l + plot.pw, y1: y, y2: y, class: 'overlay-line' }, plot.front);
  svgEl('text', { x: plot.m.l + plot.pw - 8, y: y + 16, 'text-anchor': 'end', class: 'overlay-label' }, plot.front).textContent = `non-reflecting band 1/(1 − φ) = ${c0.toFixed(3)}`;
}

// One vertical bar from c_b/V - e to c_b/V + e per band with an uncertainty, under the markers
// (in the SVG behind the canvas); an end beyond the plot area is cut at its edge and has no cap.
function drawErrorBars(plot, drawn) {
  const g = svgEl('g', { class: 'error-bars' }, plot.back);
  const top = plot.m.t, bottom = plot.m.t + plot.ph;
  for (const d of drawn) {
    if (d.e === null) continue;
    const x = plot.x.map(d.xv);
    const hi = plot.y.map(d.v + d.e);
    const lo = d.v - d.e > 0 ? plot.y.map(d.v - d.e) : Infinity;
    const y1 = Math.max(top, hi), y2 = Math.min(bottom, lo);
    const cap = d.kind === 'sd' ? SD_CAP_PX : CAP_PX;
    svgEl('line', { x1: x, x2: x, y1, y2, class: `error-bar ${d.kind}`, 'data-job': d.run.job_id, 'data-point': d.pt.id }, g);
    if (y1 === hi) svgEl('line', { x1: x - cap, x2: x + cap, y1, y2: y1, class: `error-cap ${d.kind}` }, g);
    if (y2 === lo) svgEl('line', { x1: x - cap, x2: x + cap, y1: y2, y2, class: `error-cap ${d.kind}` }, g);
  }
}

// A point's marker as the paper's Fig. 3 draws it: a square for a random structure, a circle for
// a regular one (and for results whose scene predates the structure key).
export const markerShape = (p) => (p.structure === 'random' ? 'square' : 'circle');

// The markers on the canvas, coloured by N_r; returns the count per colour of the legend.
function drawMarkers(plot, drawn) {
  const counts = {};
  const ctx = plot.ctx;
  for (const d of drawn) {
    const n = Math.min(d.nr, NR_MAX);
    counts[n] = (counts[n] || 0) + 1;
    ctx.beginPath();
    if (markerShape(d.run) === 'square') ctx.rect(d.x - 5.5, d.y - 5.5, 11, 11);
    else ctx.arc(d.x, d.y, 6, 0, 2 * Math.PI);
    ctx.fillStyle = nrColor(d.nr);
    ctx.fill();
    ctx.lineWidth = 1.2;
    ctx.strokeStyle = '#1d2433';
    ctx.stroke();
  }
  return counts;
}

function renderLegend(legend, counts) {
  legend.replaceChildren(...Array.from({ length: NR_MAX + 1 }, (_, n) => {
    const li = document.createElement('li');
    li.dataset.count = counts[n] || 0;
    if (!counts[n]) li.classList.add('zero');
    li.innerHTML = `<span class="dot big" style="background:${nrColor(n)}"></span><span class="legend-name">${n === NR_MAX ? `${n} or more` : n}${n === 0 ? ' (no reflection)' : ''}</span><span class="legend-count">${counts[n] || 0}</span>`;
    return li;
  }));
}

// How many bands are plotted of how many points (runs, when every point is one run), and every
// point left off with its reason; the bands left off link to their runs.
function renderSummary(summary, list, phi, points, shown, leftOff) {
  const bare = shown.filter((d) => d.e === null).length;
  const runs = points.reduce((a, p) => a + p.runs.length, 0);
  const single = runs === points.length;
  const sd = shown.filter((d) => d.kind === 'sd').length;
  summary.dataset.plotted = String(shown.length);
  summary.innerHTML = `<b>${shown.length}</b> band${shown.length === 1 ? '' : 's'} plotted of ${single ? `${runs} runs` : `${points.length} points (${runs} runs)`} at φ = ${phi}`
    + (sd ? ` · ${sd} replicate mean${sd === 1 ? '' : 's'} ± sd` : '')
    + (bare ? ` · ${bare} without an uncertainty (no bar)` : '');
  list.replaceChildren();
  for (const [reason, text] of Object.entries(LEFT_OFF)) {
    const items = leftOff[reason];
    if (!items.length) continue;
    const li = document.createElement('li');
    li.dataset.reason = reason;
    li.dataset.count = String(items.length);
    const link = ({ pt, run }) => `<a href="#/run/${run.job_id}">${pt.runs.length === 1 ? `run ${run.job_id}` : `point ${pt.id} (run ${run.job_id})`}</a>`;
    const links = reason === 'missing' || reason === 'nonPositive' ? `: ${items.map(link).join(', ')}` : '';
    li.innerHTML = `left off: ${text(items.length, single ? 'run' : 'point')}${links}`;
    list.append(li);
  }
}

// The tooltip of a plotted point: a point of one run as the run (tooltipHtml); a point of
// several with its majority and share and each reading as mean ± sd (n) over the replicates.
function pointTipHtml(d) {
  if (d.pt.runs.length === 1) return tooltipHtml(d.pt.runs[0]);
  const { s } = d.pt;
  const c = CLASSES[s.label];
  const rows = [
    ['S', sci(s.S)], ['R', sci(s.R)], ['R/S²', sci(stressRatio(s.S, s.R))],
    ...Object.entries(READINGS).map(([, r]) => [`<i>c</i><sub>b</sub>/<i>V</i> (${r.name.replace('least-squares ', '').replace('early stage, ', 'early, ')})`, spreadText(s[r.value], 3)]),
    ['<i>N</i><sub>r</sub>', spreadText(s.n_reflections, 2)],
    ['structure', markerShape(s) === 'square' ? 'random' : 'regular'],
    ['class', `${c ? `<span class="dot" style="background:${c.color}"></span>` : ''}${escapeHtml(label(s.label))} (share ${fixed(s.share, 2)})`],
    ['classes', probabilitiesHtml(s.probabilities)],
    ['runs', `${s.runs} (${s.robust ? 'robust' : `not robust: ${notRobustWhy(s)}`})`],
  ];
  return `<div class="tt-head">point ${s.point_id} · ${s.runs} runs · mean ± sd (<i>n</i>)</div><table>${rows.map(([k, v]) => `<tr><th>${k}</th><td>${v}</td></tr>`).join('')}</table>`;
}

function tooltipHtml(p) {
  const reading = (r) => {
    const v = p[r.value], e = p[r.error];
    return v === null || v === undefined ? '—' : `${fixed(v, 3)}${e === null || e === undefined ? '' : ` ± ${fixed(e, 3)}`}`;
  };
  return `<div class="tt-head">run ${p.job_id}</div><table>
      <tr><th>S</th><td>${sci(p.S)}</td></tr><tr><th>R</th><td>${sci(p.R)}</td></tr>
      <tr><th>R/S²</th><td>${sci(stressRatio(p.S, p.R))}</td></tr>
      <tr><th><i>c</i><sub>b</sub>/<i>V</i> (fit)</th><td>${reading(READINGS.fit)}</td></tr>
      <tr><th><i>c</i><sub>b</sub>/<i>V</i> (transit)</th><td>${reading(READINGS.transit)}</td></tr>
      <tr><th><i>c</i><sub>b</sub>/<i>V</i> (early, middle)</th><td>${reading(READINGS.early)}</td></tr>
      <tr><th><i>c</i><sub>b</sub>/<i>V</i> (early, leading edge)</th><td>${reading(READINGS.lead)}</td></tr>
      <tr><th><i>N</i><sub>r</sub></th><td>${p.n_reflections ?? '—'}</td></tr>
      <tr><th>structure</th><td>${markerShape(p) === 'square' ? 'random' : 'regular'}</td></tr>
      <tr><th>class</th><td>${CLASSES[p.class] ? `<span class="dot" style="background:${CLASSES[p.class].color}"></span>` : ''}${escapeHtml(label(p.class))}</td></tr></table>`;
}

// The phi values of every sweep (the planner's, `phis` of GET /sweeps), the chosen one included.
async function loadPhis(chosen) {
  let sweeps = [];
  try { sweeps = (await api.sweeps(1000)).sweeps; } catch { /* offline: only the default phi */ }
  const phis = new Set(sweeps.flatMap((s) => s.phis || []).map((p) => Number(p.toPrecision(12))));
  const phi = chosen ?? sweeps[0]?.phis?.[0] ?? 0.4;
  phis.add(phi);
  return { phi, phis: [...phis].sort((a, b) => a - b) };
}

// The page: its choices and data (state, from the query first), its boxes (el), what the last
// render drew (plot, drawn) and its timer. Every part below takes it explicitly.
function createPage(root, params) {
  root.innerHTML = pageHtml();
  const $ = (x) => root.querySelector(`#${x}`);
  return {
    state: {
      phi: params.phi ? Number(params.phi) : null,
      reading: READINGS[params.speed] ? params.speed : 'fit',
      points: [], // the points at phi (points.js: mapPoints), each with its runs
      sig: '',
      model: null, // the engine's predictions at phi, from the phase map's answer
    },
    el: {
      plotBox: $('bands-plot'), summary: $('bands-summary'), leftOff: $('bands-left-off'), legend: $('bands-legend'),
      phi: $('bands-phi'), reading: $('bands-reading'), readingNote: $('bands-reading-note'),
    },
    tooltip: document.getElementById('tooltip'),
    plot: null,
    drawn: [], // the plotted bands with their canvas positions (x, y)
    alive: true,
    timer: null, // the next poll
    resizeTimer: null, // the redraw a moment after the last resize
    onResize: null,
  };
}

// The figure's size for the page's width and the window's height (on a phone's narrow page, as
// wide as the card and about square).
function figureSize(box) {
  const width = Math.max(300, Math.min(1100, box.clientWidth || 760));
  return { width, height: Math.round(Math.min(width * (width < 500 ? 1 : 0.62), Math.max(460, window.innerHeight - 260))) };
}

// A new plot in the box, replacing the last: c_b/V of the bands (with their bars and the
// non-reflecting speed c0) against R/S^2 (xs), on log axes spanning them.
function newPlot(box, reading, shown, xs, c0) {
  box.replaceChildren();
  const ys = shown.flatMap((d) => (d.e === null ? [d.v] : [d.v, d.v + d.e, d.v - d.e])).concat(c0 > 0 ? [c0] : []);
  return new Plot(box, {
    ...figureSize(box), canvas: true, margin: { l: 78, r: 24, t: 18, b: 60 }, title: 'band speed',
    x: { kind: 'log', domain: logExtent(xs, [1e-2, 1e3]), label: 'q_{y} / (ρV^{2}) = R / S^{2}' },
    y: { kind: 'log', domain: logExtent(ys, [0.5, 50]), label: `band speed c_{b} / V (${READINGS[reading].name})` },
  });
}

// The plot of the bands at phi, the legend and the points left off; keeps what it drew for the
// mouse.
function render(page) {
  const { state, el } = page;
  const { shown, leftOff } = splitPoints(state.points, state.reading);
  const c0 = state.model?.nonreflecting_band_speed;
  const xs = shown.map((d) => stressRatio(d.pt.S, d.pt.R));
  const plot = (page.plot = newPlot(el.plotBox, state.reading, shown, xs, c0));
  drawNonReflecting(plot, c0);
  const drawn = (page.drawn = shown.map((d, i) => ({ ...d, xv: xs[i], x: plot.cx(xs[i]), y: plot.cy(d.v) })));
  drawErrorBars(plot, drawn);
  const counts = drawMarkers(plot, drawn);
  if (!shown.length) {
    svgEl('text', { x: plot.m.l + plot.pw / 2, y: plot.m.t + plot.ph / 2 + 30, 'text-anchor': 'middle', class: 'empty-note' }, plot.front)
      .textContent = `No band with a band speed at φ = ${state.phi} yet.`;
  }
  plot.canvas.dataset.count = String(drawn.length);
  wireCanvas(page, plot);
  renderLegend(el.legend, counts);
  renderSummary(el.summary, el.leftOff, state.phi, state.points, shown, leftOff);
  // For the browser tests: what was drawn and the y axis it was drawn on.
  const hook = (window.__dashboard ||= { renders: [] });
  hook.bands = {
    phi: state.phi, reading: state.reading, yDomain: [plot.y.d0, plot.y.d1],
    plotted: drawn.map((d) => ({ job_id: d.run.job_id, point_id: d.pt.id, jobs: d.pt.runs.map((p) => p.job_id), x: d.x, y: d.y, v: d.v, e: d.e, n: d.n, kind: d.kind, shape: markerShape(d.run) })),
  };
}

// Hover and click on a new canvas; the handlers read the page's last render when they run.
function wireCanvas(page, plot) {
  plot.canvas.addEventListener('mousemove', (ev) => onMove(page, ev));
  plot.canvas.addEventListener('mouseleave', () => { page.tooltip.hidden = true; });
  plot.canvas.addEventListener('click', (ev) => { const d = nearest(page, ev); if (d) location.hash = `#/run/${d.run.job_id}`; });
}

// The plotted band within 12 px of the mouse, the nearest; null: none.
function nearest(page, ev) {
  const r = page.plot.canvas.getBoundingClientRect();
  const mx = ev.clientX - r.left, my = ev.clientY - r.top;
  let best = null, bd = 12 * 12;
  for (const d of page.drawn) { const q = (d.x - mx) ** 2 + (d.y - my) ** 2; if (q < bd) { bd = q; best = d; } }
  return best;
}

function onMove(page, ev) {
  const { plot, tooltip } = page;
  const d = nearest(page, ev);
  if (!d) { tooltip.hidden = true; plot.canvas.style.cursor = ''; return; }
  plot.canvas.style.cursor = 'pointer';
  tooltip.innerHTML = pointTipHtml(d);
  tooltip.hidden = false;
  tooltip.style.left = `${ev.clientX + 16 + window.scrollX}px`;
  tooltip.style.top = `${ev.clientY + 14 + window.scrollY}px`;
}

// Reads /phase-map at phi and redraws when its runs or points changed.
async function poll(page) {
  clearTimeout(page.timer);
  if (!page.alive) return;
  const { state } = page;
  try {
    const data = await api.phaseMap(state.phi);
    const sig = JSON.stringify([data.points, data.summaries]);
    if (page.alive && sig !== state.sig) { state.sig = sig; state.points = mapPoints(data); state.model = data.model; render(page); }
  } catch (e) { page.el.summary.textContent = `offline: ${e.message}`; }
  if (page.alive) page.timer = setTimeout(() => poll(page), POLL_MS);
}

function syncUrl(state) {
  setParams({ phi: state.phi, speed: state.reading === 'fit' ? '' : state.reading });
}

// The controls start from the query and write back to it: another phi is another answer of the
// server (read now), another reading redraws what the page has.
function wireControls(page) {
  const { state, el } = page;
  const note = () => { el.readingNote.textContent = READINGS[state.reading].note; };
  el.reading.value = state.reading;
  note();
  el.phi.addEventListener('change', () => { state.phi = Number(el.phi.value); state.sig = ''; syncUrl(state); poll(page); });
  el.reading.addEventListener('change', () => { state.reading = el.reading.value; note(); syncUrl(state); render(page); });
}

// Redraws a moment after a resize that changes the figure's size (a phone turned, a window
// narrowed), not for every window event.
function watchResize(page) {
  page.onResize = () => {
    clearTimeout(page.resizeTimer);
    page.resizeTimer = setTimeout(() => {
      if (!page.alive || !page.plot) return;
      const { width, height } = figureSize(page.el.plotBox);
      if (width !== page.plot.opts.width || height !== page.plot.opts.height) render(page);
    }, 150);
  };
  window.addEventListener('resize', page.onResize);
}

// The phis of the sweeps fill the control; then the controls, the first render and the polling.
async function start(page) {
  const { state, el } = page;
  const { phi, phis } = await loadPhis(state.phi);
  if (!page.alive) return;
  state.phi = phi;
  el.phi.replaceChildren(...phis.map((p) => new Option(`φ = ${p}`, p, false, p === state.phi)));
  wireControls(page);
  watchResize(page);
  render(page);
  poll(page);
}

function stop(page) {
  page.alive = false;
  clearTimeout(page.timer);
  clearTimeout(page.resizeTimer);
  window.removeEventListener('resize', page.onResize);
  page.tooltip.hidden = true;
}

export function mount(root, params) {
  const page = createPage(root, params);
  start(page);
  return () => stop(page);
}
