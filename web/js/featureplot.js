// A plot of any numeric column of the run table against any other (the Plots page,
// js/pages/plots.js): the rows of GET /api/v1/jobs?format=csv for the table's filters, parsed
// into columns; which variables there are, their axes (linear or log: a log axis leaves out
// values <= 0 and says how many), the colour of a marker (the class, the label that counts, or
// a number: N_r as the band-speed page colours it, any other over viridis), and the drawing on
// a Plot's canvas (markers of one colour filled in short shared paths) and as an SVG for export.
import { CLASSES, STATES, category, drawMarker, look, shapePath } from './classes.js';
import { colormap, cssColor, linearExtent, logExtent, Plot } from './plot.js';
import { NR_MAX, nrColor } from './reflections.js';
import { stressRatio } from './physics.js';
import { escapeHtml } from './format.js';

// ---- the rows ----

// Columns that name a row, not a quantity: never offered as an axis.
const IDENTIFIERS = ['id', 'sweep', 'point_id', 'source_job'];
// Text columns, kept as text (for colours and the tooltip), even when every cell is empty.
const TEXTS = ['state', 'status', 'class', 'label', 'human_label', 'runner_up', 'preset', 'source_database', 'geometry'];

// One CSV line's cells; quotes (a cell with a comma or a quote, doubled inside) taken apart.
function cellsOf(line) {
  if (!line.includes('"')) return line.split(',');
  const out = [];
  let cell = '', quoted = false;
  for (let i = 0; i < line.length; i++) {
    const c = line[i];
    if (quoted) {
      if (c === '"' && line[i + 1] === '"') { cell += '"'; i++; } else if (c === '"') quoted = false; else cell += c;
    } else if (c === '"') quoted = true;
    else if (c === ',') { out.push(cell); cell = ''; } else cell += c;
  }
  out.push(cell);
  return out;
}

// Cell j of a CSV line (quotes taken apart when the line has any).
function cellAt(line, j) {
  if (line.includes('"')) return cellsOf(line)[j] ?? '';
  let pos = 0;
  for (let k = 0; k < j; k++) {
    pos = line.indexOf(',', pos) + 1;
    if (pos === 0) return '';
  }
  const end = line.indexOf(',', pos);
  const c = end < 0 ? line.slice(pos) : line.slice(pos, end);
  return end < 0 && c.endsWith('\r') ? c.slice(0, -1) : c;
}

// The run table's CSV (a header of its columns, a line a run) as columns, each read from the
// lines when first asked for (a plot needs five or six of the 21; reading all of 100 000 lines
// took 0.5 to 1 s, one column takes about 10 ms): numeric[name] a Float64Array (NaN: no value;
// null when the column holds a cell that is not a number), text[name] of the columns of TEXTS an
// array of strings ('' none), numeric.R_S2 = R/S^2. { n, names, numeric, text }.
export function parseRunsCsv(csv) {
  const lines = csv.split('\n');
  if (lines.length && lines[lines.length - 1] === '') lines.pop();
  const names = lines.length ? cellsOf(lines[0].replace(/\r$/, '')) : [];
  const n = Math.max(0, lines.length - 1);
  const numeric = {}, text = {};
  const lazy = (obj, name, read) => {
    let v;
    Object.defineProperty(obj, name, { enumerable: true, get: () => (v === undefined ? (v = read()) : v) });
  };
  names.forEach((name, j) => {
    if (TEXTS.includes(name)) {
      lazy(text, name, () => { const col = new Array(n); for (let i = 0; i < n; i++) col[i] = cellAt(lines[i + 1], j); return col; });
      return;
    }
    lazy(numeric, name, () => {
      const col = new Float64Array(n);
      for (let i = 0; i < n; i++) {
        const c = cellAt(lines[i + 1], j);
        const v = c === '' ? NaN : +c;
        if (v !== v && c !== '') return null; // NaN of a cell that is not empty: not a number column
        col[i] = v;
      }
      return col;
    });
  });
  // R/S^2 = q_y/(rho V^2), the paper's Fig. 3 axis.
  if (names.includes('S') && names.includes('R')) {
    lazy(numeric, 'R_S2', () => {
      const S = numeric.S, R = numeric.R;
      if (!S || !R) return null;
      const col = new Float64Array(n);
      for (let i = 0; i < n; i++) col[i] = stressRatio(S[i], R[i]);
      return col;
    });
  }
  return { n, names, numeric, text };
}

// ---- the variables ----

// How each variable is named: in the controls (HTML), on an axis (plot.js's _{} ^{} markup) and
// in text. A numeric column not listed is offered by its name.
const VARIABLES = {
  R_S2: { html: '<i>R</i>/<i>S</i>² = <i>q</i><sub>y</sub>/(ρ<i>V</i>²)', axis: 'R / S^{2} = q_{y} / (ρV^{2})', text: 'R/S²', log: true },
  band_speed_ratio: { html: '<i>c</i><sub>b</sub>/<i>V</i> (band speed)', axis: 'band speed c_{b} / V', text: 'c_b/V', log: true },
  n_reflections: { html: '<i>N</i><sub>r</sub> (reflections)', axis: 'reflections N_{r}', text: 'N_r', log: false },
  S: { html: '<i>S</i> (Mach number)', axis: 'S = V / √(E/ρ)', text: 'S', log: true },
  R: { html: '<i>R</i> (relative strength)', axis: 'R = q_{y} / E', text: 'R', log: true },
  phi: { html: 'φ (solid fraction)', axis: 'solid fraction φ', text: 'φ', log: false },
  confidence: { html: 'confidence (classifier)', axis: "the classifier's confidence", text: 'confidence', log: false },
  cells_per_unit: { html: 'cells per unit cell', axis: 'cells per unit cell', text: 'cells/unit', log: false },
  cells_per_strut: { html: 'cells per strut', axis: 'cells across a strut', text: 'cells/strut', log: false },
  seed: { html: 'seed (replicate)', axis: 'seed', text: 'seed', log: false },
  // The run's and the classifier's numbers (features.hpp of engine/classify says how each is read).
  deflection_before_yield: { html: 'strut deflection before yield', axis: 'strut deflection before yield / thickness', text: 'deflection before yield', log: true },
  deflection_growth: { html: 'strut deflection growth (decades)', axis: 'deflection growth [decades]', text: 'deflection growth', log: false },
  coherence: { html: 'coherence (activity in fronts)', axis: 'coherence', text: 'coherence', log: false },
  stress_ratio: { html: 'top / bottom stress', axis: 'σ_{top} / σ_{bottom}', text: 'top/bottom stress', log: true },
  speed_excess: { html: 'band speed excess', axis: 'c_{b}(1 − φ)/V − 1', text: 'speed excess', log: false },
  band_speed_early: { html: '<i>c</i><sub>b</sub>/<i>V</i>, early band middle', axis: 'c_{b} / V (early, middle)', text: 'c_b/V early', log: true },
  band_speed_lead: { html: '<i>c</i><sub>b</sub>/<i>V</i>, leading edge', axis: 'c_{b} / V (leading edge)', text: 'c_b/V lead', log: true },
  eps_first_yield: { html: 'ε at first yield', axis: 'strain at first yield', text: 'ε first yield', log: true },
  eps_reached: { html: 'ε reached', axis: 'strain reached', text: 'ε reached', log: false },
  wall_seconds: { html: 'wall time (s)', axis: 'wall time [s]', text: 'wall time', log: true },
};
const ORDER = Object.keys(VARIABLES);

// The variables of the run table (GET /limits: jobs.columns) as axes and numeric colours: its
// numeric columns and R/S², in ORDER, then the others by name.
export function variablesOf(columns) {
  const have = [...columns.filter((k) => !IDENTIFIERS.includes(k) && !TEXTS.includes(k)), ...(columns.includes('S') && columns.includes('R') ? ['R_S2'] : [])];
  return [...ORDER.filter((k) => have.includes(k)), ...have.filter((k) => !ORDER.includes(k)).sort()];
}

// The columns a plot of `spec` reads (GET /jobs?columns=): the run's id, S, R and φ (the
// tooltip), its state, status, class and label (the colours by category), and its axes and
// numeric colour; R/S² from S and R.
export function columnsFor(spec) {
  const base = ['id', 'S', 'R', 'phi', 'state', 'status', 'class', 'label'];
  const more = [spec.x, spec.y, spec.color].filter((k) => k !== 'R_S2' && !CATEGORY_COLOURS[k]);
  return [...new Set([...base, ...more])];
}

export const varHtml = (k) => VARIABLES[k]?.html ?? escapeHtml(k);
export const varText = (k) => VARIABLES[k]?.text ?? k;
const varAxis = (k) => VARIABLES[k]?.axis ?? k;

// Colours other than a numeric variable: the classifier's class or the label that counts.
export const CATEGORY_COLOURS = { class: "class (classifier's)", label: 'label that counts' };

// ---- the plot's state (the page's URL holds it beside the table's filters) ----

export const PLOT_KEYS = ['x', 'y', 'xscale', 'yscale', 'color'];
export const DEFAULT_SPEC = { x: 'R_S2', y: 'band_speed_ratio', xscale: 'log', yscale: 'log', color: 'class' };

// Saved views: each sets the axes, their scales and the colour; filters: the table's filters it
// sets (the others stay).
export const VIEWS = [
  { key: 'fig3', name: 'Fig. 3', title: "the paper's Fig. 3: c_b/V against R/S² of the bands (a, b), log-log, coloured by N_r",
    spec: { x: 'R_S2', y: 'band_speed_ratio', xscale: 'log', yscale: 'log', color: 'n_reflections' }, filters: { class: 'a,b' } },
  { key: 'reflections', name: 'N_r against R/S²', title: 'reflections against R/S², coloured by class',
    spec: { x: 'R_S2', y: 'n_reflections', xscale: 'log', yscale: 'linear', color: 'class' } },
  { key: 'confidence', name: 'confidence against S', title: "the classifier's confidence against S, coloured by class",
    spec: { x: 'S', y: 'confidence', xscale: 'log', yscale: 'linear', color: 'class' } },
  { key: 'map', name: 'R against S', title: 'the phase map\'s axes: R against S, log-log, coloured by the label that counts',
    spec: { x: 'S', y: 'R', xscale: 'log', yscale: 'log', color: 'label' } },
];

// The plot's part of the hash's parameters, each checked against the variables (null: the rows
// have not come; then any name is kept); problems: what was replaced by a default.
export function readSpec(params, variables = null) {
  const spec = { ...DEFAULT_SPEC };
  const problems = [];
  const okVar = (v) => !variables || variables.includes(v);
  for (const k of ['x', 'y']) if (params[k] !== undefined && params[k] !== '') {
    if (okVar(params[k])) spec[k] = params[k]; else problems.push(`${k}=${params[k]} is not a numeric column of the table`);
  }
  for (const k of ['xscale', 'yscale']) if (params[k] !== undefined && params[k] !== '') {
    if (params[k] === 'log' || params[k] === 'linear') spec[k] = params[k]; else problems.push(`${k} must be log or linear`);
  }
  if (params.color !== undefined && params.color !== '') {
    if (CATEGORY_COLOURS[params.color] || okVar(params.color)) spec.color = params.color; else problems.push(`color=${params.color} is not a class or a numeric column`);
  }
  return { spec, problems };
}

// The view a spec and filters are (its key), or ''.
export function viewOf(spec, filters) {
  const v = VIEWS.find((w) => PLOT_KEYS.every((k) => w.spec[k] === spec[k]) && Object.entries(w.filters || {}).every(([k, t]) => filters[k] === t));
  return v ? v.key : '';
}

// ---- colours ----

const VIRIDIS_BINS = 8;
let viridis = null;
const binColor = (b) => cssColor((viridis ||= colormap('viridis')), (b / (VIRIDIS_BINS - 1)) * 0.92);
const NO_VALUE = '#b8bcc2';

// The category a row is drawn as when coloured by a label column (class or label): the map's
// rule (classes.js category) with that column as the letter.
function categoryOf(data, col, i) {
  return category({ state: data.text.state?.[i], status: data.text.status?.[i], class: data.text[col]?.[i] });
}

// The colour key of each row and the legend: [{key, name, color, cat?, count}] in the order of
// drawing. A categorical key is the category (a class letter or a state); a numeric one the
// bin ('n3' of N_r = 3; 'b0'..'b7' of viridis bins over [lo, hi]; 'none' without a value).
export function colourKeys(data, color, rows) {
  const keys = new Array(rows.length);
  const legend = new Map();
  const add = (key, make) => { let e = legend.get(key); if (!e) legend.set(key, (e = { key, count: 0, ...make() })); e.count++; return key; };
  if (CATEGORY_COLOURS[color]) {
    rows.forEach((i, k) => {
      const cat = categoryOf(data, color, i);
      keys[k] = add(cat, () => ({ cat, name: CLASSES[cat] ? `${cat} · ${CLASSES[cat].name}` : look(cat).name, color: look(cat).color }));
    });
    const order = [...Object.keys(CLASSES), ...Object.keys(STATES)];
    return { keys, legend: [...legend.values()].sort((a, b) => order.indexOf(a.key) - order.indexOf(b.key)) };
  }
  const v = data.numeric[color] || []; // a column that did not parse as numbers: no value
  if (color === 'n_reflections') {
    rows.forEach((i, k) => {
      const x = v[i];
      if (!Number.isFinite(x)) { keys[k] = add('none', () => ({ name: 'no value', color: NO_VALUE })); return; }
      const n = Math.max(0, Math.min(NR_MAX, Math.round(x)));
      keys[k] = add(`n${n}`, () => ({ name: n === NR_MAX ? `${n} or more` : `${n}${n === 0 ? ' (no reflection)' : ''}`, color: nrColor(n), order: n }));
    });
  } else {
    let lo = Infinity, hi = -Infinity;
    for (const i of rows) if (Number.isFinite(v[i])) { lo = Math.min(lo, v[i]); hi = Math.max(hi, v[i]); }
    const width = (hi - lo) / VIRIDIS_BINS || 1;
    rows.forEach((i, k) => {
      const x = v[i];
      if (!Number.isFinite(x)) { keys[k] = add('none', () => ({ name: 'no value', color: NO_VALUE })); return; }
      const b = Math.min(VIRIDIS_BINS - 1, Math.floor((x - lo) / width));
      const a = lo + b * width;
      keys[k] = add(`b${b}`, () => ({ name: `${Number(a.toPrecision(3))} to ${Number((a + width).toPrecision(3))}`, color: binColor(b), order: b }));
    });
  }
  const list = [...legend.values()].sort((a, b) => (a.key === 'none') - (b.key === 'none') || a.order - b.order);
  return { keys, legend: list };
}

// ---- the figure ----

// The rows a spec can place: those with both values (and > 0 on a log axis); the others counted
// by reason: {rows: [index], leftOff: [{reason, axis, count}]}.
export function placeable(data, spec) {
  const xs = data.numeric[spec.x], ys = data.numeric[spec.y];
  const rows = [];
  const miss = { x: 0, y: 0 }, nonPos = { x: 0, y: 0 };
  for (let i = 0; i < data.n; i++) {
    const x = xs ? xs[i] : NaN, y = ys ? ys[i] : NaN;
    if (!Number.isFinite(x)) { miss.x++; continue; }
    if (!Number.isFinite(y)) { miss.y++; continue; }
    if (spec.xscale === 'log' && x <= 0) { nonPos.x++; continue; }
    if (spec.yscale === 'log' && y <= 0) { nonPos.y++; continue; }
    rows.push(i);
  }
  const leftOff = [];
  for (const a of ['x', 'y']) {
    if (miss[a]) leftOff.push({ reason: 'missing', axis: a, count: miss[a] });
    if (nonPos[a]) leftOff.push({ reason: 'nonPositive', axis: a, count: nonPos[a] });
  }
  return { rows, leftOff };
}

// Marker radius for the number of markers (fewer: larger).
export const markerRadius = (n) => (n > 20000 ? 1.8 : n > 3000 ? 2.6 : n > 300 ? 3.6 : 5);

// A new Plot in box of the spec's axes spanning the rows placed (fallback spans without rows).
export function newFeaturePlot(box, size, data, spec, rows) {
  const values = (k) => { const c = data.numeric[k]; return c ? rows.map((i) => c[i]) : []; };
  const extent = (k, kind) => (kind === 'log' ? logExtent(values(k), [0.1, 10]) : linearExtent(values(k), [0, 1]));
  const plot = new Plot(box, {
    ...size, canvas: true, margin: { l: 78, r: 24, t: 18, b: 60 }, title: `${varText(spec.y)} against ${varText(spec.x)}`,
    x: { kind: spec.xscale, domain: extent(spec.x, spec.xscale), label: varAxis(spec.x) },
    y: { kind: spec.yscale, domain: extent(spec.y, spec.yscale), label: varAxis(spec.y) },
  });
  plot.spec = spec;
  return plot;
}

// Markers a path: chromium fills one path of 100 000 spread circles in 0.8 s, paths of 20 in
// 0.2 s, a path each in 0.34 s (headless, software, 2 cores); the page's first plot at 100 000
// runs took 11 s as one path a colour.
const PATH_MARKERS = 24;

// The markers on the plot's canvas, paths of PATH_MARKERS of one colour key; returns their canvas positions
// (Float32Array px, py, in the order of rows).
export function drawFeatureMarkers(plot, data, rows, coloured, r) {
  const { keys, legend } = coloured;
  const xs = data.numeric[plot.spec.x], ys = data.numeric[plot.spec.y];
  const px = new Float32Array(rows.length), py = new Float32Array(rows.length);
  const byKey = new Map(legend.map((e) => [e.key, []]));
  rows.forEach((i, k) => { px[k] = plot.cx(xs[i]); py[k] = plot.cy(ys[i]); byKey.get(keys[k]).push(k); });
  const ctx = plot.ctx;
  const outline = rows.length <= 3000;
  for (const e of legend) {
    const shape = e.cat ? look(e.cat).shape : 'circle';
    const filled = !e.cat || CLASSES[e.cat] || STATES[e.cat]?.shape === 'circle';
    if (!filled) { // a state's own marker (hollow, ring, cross...): one at a time, as the map does
      for (const k of byKey.get(e.key)) drawMarker(ctx, e.cat, px[k], py[k], r, 0.6);
      continue;
    }
    ctx.fillStyle = e.color;
    ctx.lineWidth = e.cat ? 1 : 0.8;
    ctx.strokeStyle = e.cat ? 'rgba(255,255,255,0.9)' : '#1d2433';
    const ks = byKey.get(e.key);
    for (let s = 0; s < ks.length; s += PATH_MARKERS) {
      ctx.beginPath();
      for (let q = s; q < Math.min(ks.length, s + PATH_MARKERS); q++) shapePath(ctx, shape, px[ks[q]], py[ks[q]], r);
      ctx.fill();
      if (outline) ctx.stroke();
    }
  }
  return { px, py };
}

// How the SVG export draws one marker ({cat, color, x, y, r}): a class or a state as the map
// draws it, a numeric colour as a filled circle.
export function drawExportMark(ctx, m) {
  if (m.cat) { drawMarker(ctx, m.cat, m.x, m.y, m.r, 0.6); return; }
  ctx.beginPath();
  ctx.arc(m.x, m.y, m.r, 0, 2 * Math.PI);
  ctx.fillStyle = m.color;
  ctx.fill();
  ctx.lineWidth = 0.8;
  ctx.strokeStyle = '#1d2433';
  ctx.stroke();
}

// [r, g, b] of a CSS colour written as #rrggbb or rgb(r,g,b).
export function rgbOf(css) {
  if (css.startsWith('#')) return [1, 3, 5].map((i) => parseInt(css.slice(i, i + 2), 16));
  return css.match(/\d+/g).slice(0, 3).map(Number);
}
