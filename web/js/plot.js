// Plotting without a library: scales with ticks, SVG axes with labels and units, a canvas layer
// for many points or images, colour maps and a colour bar. Every figure is a Plot.

const SVG_NS = 'http://www.w3.org/2000/svg';

export function svgEl(tag, attrs = {}, parent = null) {
  const e = document.createElementNS(SVG_NS, tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (parent) parent.appendChild(e);
  return e;
}

// A scale maps data [d0, d1] to pixels [r0, r1]; kind 'log' maps log10 of the value.
export function scale(kind, d0, d1, r0, r1) {
  const f = kind === 'log' ? Math.log10 : (v) => v;
  const a = f(d0), b = f(d1);
  const k = (r1 - r0) / (b - a || 1);
  const map = (v) => r0 + (f(v) - a) * k;
  const invert = (px) => {
    const u = a + (px - r0) / k;
    return kind === 'log' ? 10 ** u : u;
  };
  return { kind, d0, d1, r0, r1, map, invert };
}

// Ticks of a linear axis: about `count` round values.
export function linearTicks(lo, hi, count = 6) {
  const span = hi - lo;
  if (!(span > 0)) return { major: [lo], minor: [] };
  const raw = span / count;
  const mag = 10 ** Math.floor(Math.log10(raw));
  const step = [1, 2, 2.5, 5, 10].map((m) => m * mag).find((s) => span / s <= count) || 10 * mag;
  const major = [];
  for (let v = Math.ceil(lo / step - 1e-9) * step; v <= hi + step * 1e-9; v += step) major.push(Math.abs(v) < step * 1e-9 ? 0 : v);
  return { major, minor: [], step };
}

// Ticks of a log axis: every decade labelled (every second one when there are many), 2..9 minor.
export function logTicks(lo, hi) {
  const a = Math.floor(Math.log10(lo) + 1e-9), b = Math.ceil(Math.log10(hi) - 1e-9);
  const major = [], minor = [];
  const every = b - a > 8 ? 2 : 1;
  const few = Math.log10(hi / lo) < 2.5; // a short axis: label 2 and 5 too
  for (let e = a; e <= b; e++) {
    const v = 10 ** e;
    if (v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9) && (e % every === 0)) major.push(v);
    for (let m = 2; m < 10; m++) {
      const w = m * v;
      if (w > lo && w < hi && b - a <= 8) (few && (m === 2 || m === 5) ? major : minor).push(w);
    }
  }
  // A zoomed axis of a fraction of a decade: round values of the mantissa (0.035, 0.04, ...).
  if (major.length < 3 && Math.log10(hi / lo) < 1) return { major: linearTicks(lo, hi, 5).major.filter((v) => v > 0), minor: [] };
  return { major, minor };
}

// A log axis's labelled ticks thinned to at least `gap` px apart (a phone's narrow axis ran its
// "2×10^-3" into "5×10^-3"): the 2s and 5s become minor ticks first, then every second decade.
function spacedLogTicks(t, sc, gap) {
  const crowded = (vs) => vs.some((v, i) => i > 0 && Math.abs(sc.map(v) - sc.map(vs[i - 1])) < gap);
  if (!crowded(t.major)) return t;
  const isDecade = (v) => Math.abs(Math.log10(v) - Math.round(Math.log10(v))) < 1e-9;
  let major = t.major.filter(isDecade);
  const minor = [...t.minor, ...t.major.filter((v) => !isDecade(v))];
  if (major.length > 2 && crowded(major)) major = major.filter((v) => Math.round(Math.log10(v)) % 2 === 0);
  return major.length ? { major, minor } : t;
}

function fmtLinear(v, step) {
  const d = Math.max(0, -Math.floor(Math.log10(step || 1) + 1e-9));
  return v.toFixed(Math.min(d, 6));
}

// Places a label at an SVG text node: on a log axis "10^e" (a superscript) for a decade and
// "m×10^e" between decades (2 and 5 on a short axis), the same notation on the whole axis (a
// plain "0.02" beside "10^-2" read as two notations); 1 and 10 and their multiples are plain.
function setTickText(text, v, kind, step) {
  if (kind === 'log') {
    const e = Math.floor(Math.log10(v) + 1e-9);
    const m = Number((v / 10 ** e).toPrecision(3)); // 3: a zoomed axis's 3.25; a decade's 2 and 5 print as before
    if (e === 0 || e === 1) { text.textContent = String(Number((m * 10 ** e).toPrecision(2))); return; }
    text.textContent = m === 1 ? '10' : `${m}×10`;
    const sup = svgEl('tspan', { dy: '-0.5em', 'font-size': '0.78em' }, text);
    sup.textContent = String(e).replace('-', '−');
  } else {
    text.textContent = fmtLinear(v, step).replace('-', '−');
  }
}

// The least and greatest finite value of `values` (only those > 0 with `positive`), or null
// without one. A loop: spreading over ~125 000 values into Math.min overflows the stack.
export function valueRange(values, positive = false) {
  let lo = Infinity, hi = -Infinity;
  for (const x of values) if (Number.isFinite(x) && (!positive || x > 0)) { if (x < lo) lo = x; if (x > hi) hi = x; }
  return lo <= hi ? [lo, hi] : null;
}

// Data range of a log axis padded by a fraction of a decade (ticks stay on whole decades),
// at least `minDecades` wide; `fallback` when there is no positive value.
export function logExtent(values, fallback, minDecades = 1) {
  const range = valueRange(values, true);
  if (!range) return fallback;
  let a = Math.log10(range[0]), b = Math.log10(range[1]);
  if (b - a < minDecades) { const c = (a + b) / 2; a = c - minDecades / 2; b = c + minDecades / 2; }
  const pad = Math.max(0.12, 0.04 * (b - a));
  return [10 ** (a - pad), 10 ** (b + pad)];
}

export function linearExtent(values, fallback, pad = 0.05) {
  const range = valueRange(values);
  if (!range) return fallback;
  let [lo, hi] = range;
  if (hi === lo) { hi += Math.abs(hi) * 0.1 || 1; lo -= Math.abs(lo) * 0.1 || 1; }
  const p = (hi - lo) * pad;
  return [lo - p, hi + p];
}

// A figure: fixed-size SVG with axes, a plot area, optional canvas over the plot area.
// opts: width, height, margin {l, r, t, b}, x {kind, domain, label}, y {kind, domain, label}, canvas
export class Plot {
  constructor(parent, opts) {
    this.opts = opts;
    const { width, height } = opts;
    const m = { l: 74, r: 20, t: 16, b: 56, ...(opts.margin || {}) };
    this.m = m;
    this.pw = width - m.l - m.r;
    this.ph = height - m.t - m.b;
    this.root = document.createElement('div');
    this.root.className = 'plot';
    this.root.style.width = `${width}px`;
    this.root.style.height = `${height}px`;
    parent.appendChild(this.root);
    this.svg = svgEl('svg', { width, height, viewBox: `0 0 ${width} ${height}`, class: 'plot-svg', role: 'img' }, this.root);
    if (opts.title) svgEl('title', {}, this.svg).textContent = opts.title;
    this.x = scale(opts.x.kind, opts.x.domain[0], opts.x.domain[1], m.l, m.l + this.pw);
    this.y = scale(opts.y.kind, opts.y.domain[0], opts.y.domain[1], m.t + this.ph, m.t);
    this.back = svgEl('g', { class: 'plot-back' }, this.svg);
    if (opts.canvas) {
      const dpr = window.devicePixelRatio || 1;
      this.canvas = document.createElement('canvas');
      this.canvas.width = Math.round(this.pw * dpr);
      this.canvas.height = Math.round(this.ph * dpr);
      Object.assign(this.canvas.style, { position: 'absolute', left: `${m.l}px`, top: `${m.t}px`, width: `${this.pw}px`, height: `${this.ph}px` });
      this.canvas.className = 'plot-canvas';
      this.root.appendChild(this.canvas);
      this.ctx = this.canvas.getContext('2d');
      this.ctx.scale(dpr, dpr);
      this.dpr = dpr;
    }
    // Overlays above the canvas (lines, annotations) live in a second SVG.
    this.over = svgEl('svg', { width, height, class: 'plot-over' }, this.root);
    this.front = svgEl('g', {}, this.over);
    this.drawAxes();
  }

  // Canvas coordinates (relative to the plot area) of a data point.
  cx(v) { return this.x.map(v) - this.m.l; }
  cy(v) { return this.y.map(v) - this.m.t; }

  drawAxes() {
    const { m, pw, ph, opts } = this;
    const g = this.back;
    svgEl('rect', { x: m.l, y: m.t, width: pw, height: ph, class: 'plot-area' }, g);
    const grid = svgEl('g', { class: 'plot-grid' }, g);
    const axes = svgEl('g', { class: 'plot-axes' }, this.svg);
    const xt = opts.x.kind === 'log' ? spacedLogTicks(logTicks(...opts.x.domain), this.x, 52) : linearTicks(...opts.x.domain, opts.x.ticks || 7);
    const yt = opts.y.kind === 'log' ? spacedLogTicks(logTicks(...opts.y.domain), this.y, 20) : linearTicks(...opts.y.domain, opts.y.ticks || 6);
    const y0 = m.t + ph, x0 = m.l;
    for (const v of xt.minor) {
      const px = this.x.map(v);
      svgEl('line', { x1: px, x2: px, y1: y0, y2: y0 + 3, class: 'tick minor' }, axes);
    }
    for (const v of xt.major) {
      const px = this.x.map(v);
      svgEl('line', { x1: px, x2: px, y1: m.t, y2: y0, class: 'gridline' }, grid);
      svgEl('line', { x1: px, x2: px, y1: y0, y2: y0 + 6, class: 'tick' }, axes);
      setTickText(svgEl('text', { x: px, y: y0 + 21, 'text-anchor': 'middle', class: 'ticklabel' }, axes), v, opts.x.kind, xt.step);
    }
    for (const v of yt.minor) {
      const py = this.y.map(v);
      svgEl('line', { x1: x0 - 3, x2: x0, y1: py, y2: py, class: 'tick minor' }, axes);
    }
    for (const v of yt.major) {
      const py = this.y.map(v);
      svgEl('line', { x1: x0, x2: x0 + pw, y1: py, y2: py, class: 'gridline' }, grid);
      svgEl('line', { x1: x0 - 6, x2: x0, y1: py, y2: py, class: 'tick' }, axes);
      setTickText(svgEl('text', { x: x0 - 10, y: py + 4.5, 'text-anchor': 'end', class: 'ticklabel' }, axes), v, opts.y.kind, yt.step);
    }
    svgEl('rect', { x: m.l, y: m.t, width: pw, height: ph, class: 'plot-frame' }, axes);
    const xl = svgEl('text', { x: m.l + pw / 2, y: m.t + ph + 46, 'text-anchor': 'middle', class: 'axislabel' }, axes);
    richText(xl, opts.x.label);
    // The y label clears the widest tick label ("0.0005" is wider than the margin assumes).
    let widest = 0;
    for (const t of axes.querySelectorAll('text.ticklabel[text-anchor="end"]')) widest = Math.max(widest, t.getBBox().width);
    const ylx = Math.max(14, Math.min(m.l - 52, x0 - 10 - widest - 12));
    const yl = svgEl('text', { transform: `translate(${ylx}, ${m.t + ph / 2}) rotate(-90)`, 'text-anchor': 'middle', class: 'axislabel' }, axes);
    richText(yl, opts.y.label);
  }

  // A polyline of data (xs, ys arrays) in the overlay SVG.
  line(xs, ys, attrs = {}) {
    let d = '';
    let pen = false;
    for (let i = 0; i < xs.length; i++) {
      const ok = Number.isFinite(xs[i]) && Number.isFinite(ys[i]) && (this.x.kind !== 'log' || xs[i] > 0) && (this.y.kind !== 'log' || ys[i] > 0);
      if (!ok) { pen = false; continue; }
      d += `${pen ? 'L' : 'M'}${this.x.map(xs[i]).toFixed(2)},${this.y.map(ys[i]).toFixed(2)}`;
      pen = true;
    }
    return svgEl('path', { d, fill: 'none', ...attrs }, this.front);
  }

  clipRect() {
    if (!this._clip) {
      const id = `clip${Math.random().toString(36).slice(2, 8)}`;
      const defs = svgEl('defs', {}, this.over);
      svgEl('rect', { x: this.m.l, y: this.m.t, width: this.pw, height: this.ph }, svgEl('clipPath', { id }, defs));
      this._clip = `url(#${id})`;
    }
    return this._clip;
  }
}

// Text with simple markup: _{sub} and ^{sup} (e.g. "log_{10} S", "c_b / V").
export function richText(node, s) {
  const re = /([_^])\{([^}]*)\}/g;
  let last = 0, m;
  let shifted = 0;
  while ((m = re.exec(s))) {
    if (m.index > last) {
      const t = svgEl('tspan', shifted ? { dy: `${-shifted}em` } : {}, node);
      t.textContent = s.slice(last, m.index);
      shifted = 0;
    }
    const dy = m[1] === '_' ? 0.3 : -0.45;
    const t = svgEl('tspan', { dy: `${dy}em`, 'font-size': '0.75em' }, node);
    t.textContent = m[2];
    shifted = dy * 0.75; // the tspan's em is 0.75 of the parent's
    last = re.lastIndex;
  }
  const t = svgEl('tspan', shifted ? { dy: `${-shifted}em` } : {}, node);
  t.textContent = s.slice(last);
}

// Matplotlib's inferno and viridis, sampled at 11 points and interpolated linearly.
const MAPS = {
  inferno: ['#000004', '#160b39', '#420a68', '#6a176e', '#932667', '#bc3754', '#dd513a', '#f37819', '#fca50a', '#f6d746', '#fcffa4'],
  viridis: ['#440154', '#482475', '#414487', '#355f8d', '#2a788e', '#21918c', '#22a884', '#44bf70', '#7ad151', '#bddf26', '#fde725'],
};
const hex = (h) => [1, 3, 5].map((i) => parseInt(h.slice(i, i + 2), 16));

// 256-entry RGB lookup table of a colour map.
export function colormap(name) {
  const stops = MAPS[name].map(hex);
  const lut = new Uint8ClampedArray(256 * 3);
  for (let i = 0; i < 256; i++) {
    const t = (i / 255) * (stops.length - 1);
    const k = Math.min(stops.length - 2, Math.floor(t));
    const f = t - k;
    for (let c = 0; c < 3; c++) lut[i * 3 + c] = stops[k][c] + (stops[k + 1][c] - stops[k][c]) * f;
  }
  return lut;
}

export function cssColor(lut, t) {
  const i = Math.max(0, Math.min(255, Math.round(t * 255))) * 3;
  return `rgb(${lut[i]},${lut[i + 1]},${lut[i + 2]})`;
}

// A vertical colour bar at (x, y) of size w x h in an SVG, for values [lo, hi] (linear in the
// mapped quantity), with ticks and a label.
export function colorBar(svg, { x, y, w, h, lut, lo, hi, label, ticks }) {
  const g = svgEl('g', { class: 'colorbar' }, svg);
  const id = `cb${Math.random().toString(36).slice(2, 8)}`;
  const grad = svgEl('linearGradient', { id, x1: 0, y1: 1, x2: 0, y2: 0 }, svgEl('defs', {}, g));
  for (let i = 0; i <= 10; i++) svgEl('stop', { offset: i / 10, 'stop-color': cssColor(lut, i / 10) }, grad);
  svgEl('rect', { x, y, width: w, height: h, fill: `url(#${id})`, class: 'colorbar-rect' }, g);
  for (const v of ticks || linearTicks(lo, hi, 5).major) {
    const py = y + h - ((v - lo) / (hi - lo)) * h;
    if (py < y - 0.5 || py > y + h + 0.5) continue;
    svgEl('line', { x1: x + w, x2: x + w + 4, y1: py, y2: py, class: 'tick' }, g);
    const t = svgEl('text', { x: x + w + 7, y: py + 4, class: 'ticklabel' }, g);
    t.textContent = typeof v === 'number' ? Number(v.toPrecision(3)).toString() : v;
  }
  const t = svgEl('text', { transform: `translate(${x + w + 46}, ${y + h / 2}) rotate(-90)`, 'text-anchor': 'middle', class: 'axislabel' }, g);
  richText(t, label);
  return g;
}
