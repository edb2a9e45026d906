// The six pattern classes (Blatny et al., PRL 128, 228002, 2022), their fixed colour-blind-safe
// colours (Okabe-Ito) and marker shapes, and the looks of points that carry no label yet.

export const CLASSES = {
  a: { name: 'non-reflecting band', color: '#0072B2', shape: 'circle' },
  b: { name: 'reflecting band', color: '#56B4E9', shape: 'square' },
  c: { name: 'crossing bands', color: '#009E73', shape: 'diamond' },
  d: { name: 'erratic', color: '#E69F00', shape: 'triangle' },
  e: { name: 'explosive compaction', color: '#D55E00', shape: 'triangleDown' },
  f: { name: 'buckling', color: '#CC79A7', shape: 'hexagon' },
};

// Points without a class: what the job is doing, or why it has no label.
export const STATES = {
  unclassified: { name: 'done, unclassified', color: '#8a8f98', shape: 'circle', note: 'succeeded; the classifier gave no label' },
  unstable: { name: 'unstable', color: '#3d3d3d', shape: 'bang', note: 'numerically unstable run (a result, flagged)' },
  running: { name: 'running', color: '#1d2433', shape: 'ring', note: 'leased by a worker; the arc shows progress' },
  queued: { name: 'queued', color: '#6b7280', shape: 'hollow', note: 'waiting for a worker' },
  failed: { name: 'failed', color: '#1d2433', shape: 'cross', note: 'failed after its attempts' },
  cancelled: { name: 'cancelled', color: '#b8bcc2', shape: 'dash', note: 'cancelled' },
};

// Text colour readable on a class colour (dark on the light ones: b, d, f).
export function inkOn(hex) {
  const [r, g, b] = [1, 3, 5].map((i) => parseInt(hex.slice(i, i + 2), 16) / 255);
  return 0.2126 * r + 0.7152 * g + 0.0722 * b > 0.45 ? '#1d2433' : '#ffffff';
}

// The category a phase-map point is drawn as: a class letter, or one of STATES.
export function category(p) {
  if (p.state === 'succeeded') {
    if (p.status === 'unstable') return 'unstable';
    // A person's label (a class letter on the map's points) goes before the classifier's.
    const cls = typeof p.human_label === 'string' ? p.human_label : p.class;
    return cls && CLASSES[cls] ? cls : 'unclassified';
  }
  return STATES[p.state] ? p.state : 'queued';
}

export function look(cat) {
  return CLASSES[cat] || STATES[cat] || STATES.queued;
}

export function label(cat) {
  return CLASSES[cat] ? `${cat} · ${CLASSES[cat].name}` : look(cat).name;
}

// How much a label's marker fades towards white at confidence c (the classifier's gap between
// its best and runner-up scores): up to LOW_CONFIDENCE_FADE at c = 0, nothing at c = 1 or
// without a confidence. A faded marker is outlined in its class colour, so its shape and class
// stay readable.
export const LOW_CONFIDENCE_FADE = 0.75;
const OUTLINE_FROM_FADE = 0.15; // c below 0.8: outline in the class colour, not white
export function confidenceFade(c) {
  return c === null || c === undefined || !Number.isFinite(c) ? 0 : LOW_CONFIDENCE_FADE * (1 - Math.max(0, Math.min(1, c)));
}

// The colour hex faded towards white by t, in steps of 1/FADE_STEPS (at most 255/64 = 4 levels
// of a channel off the exact mix), each computed once: a new colour string per marker made the
// canvas parse one per marker and doubled the render of 10,000 points.
const FADE_STEPS = 64;
const faded = new Map();
export function fadeColor(hex, t) {
  const step = Math.round(t * FADE_STEPS);
  const key = `${hex}${step}`;
  let c = faded.get(key);
  if (!c) {
    const [r, g, b] = [1, 3, 5].map((i) => parseInt(hex.slice(i, i + 2), 16));
    const m = (v) => Math.round(v + ((255 - v) * step) / FADE_STEPS);
    c = `rgb(${m(r)},${m(g)},${m(b)})`;
    faded.set(key, c);
  }
  return c;
}

// Adds the outline of a class's filled shape (circle, square, diamond, triangle, triangleDown,
// hexagon; anything else a circle) centred at (x, y) with radius r to ctx's path, as a subpath
// of its own (several shapes may share one path: the Plots page fills a colour's markers a few
// dozen to a path).
export function shapePath(ctx, shape, x, y, r) {
  switch (shape) {
    case 'square': ctx.rect(x - r * 0.88, y - r * 0.88, r * 1.76, r * 1.76); break;
    case 'diamond': ctx.moveTo(x, y - r * 1.2); ctx.lineTo(x + r * 1.2, y); ctx.lineTo(x, y + r * 1.2); ctx.lineTo(x - r * 1.2, y); ctx.closePath(); break;
    case 'triangle': ctx.moveTo(x, y - r * 1.2); ctx.lineTo(x + r * 1.1, y + r * 0.8); ctx.lineTo(x - r * 1.1, y + r * 0.8); ctx.closePath(); break;
    case 'triangleDown': ctx.moveTo(x, y + r * 1.2); ctx.lineTo(x + r * 1.1, y - r * 0.8); ctx.lineTo(x - r * 1.1, y - r * 0.8); ctx.closePath(); break;
    case 'hexagon':
      for (let k = 0; k < 6; k++) {
        const a = Math.PI / 6 + (k * Math.PI) / 3;
        k ? ctx.lineTo(x + r * 1.1 * Math.cos(a), y + r * 1.1 * Math.sin(a)) : ctx.moveTo(x + r * 1.1 * Math.cos(a), y + r * 1.1 * Math.sin(a));
      }
      ctx.closePath(); break;
    default: ctx.moveTo(x + r, y); ctx.arc(x, y, r, 0, 2 * Math.PI); // a subpath of its own
  }
}

// The circle inside each filled shape of shapePath, in units of r: its centre's offset down
// [dy] and its radius [inradius] (the triangles' incircles sit towards their bases).
export const INCIRCLE = {
  circle: [0, 1], square: [0, 0.88], diamond: [0, 0.85], triangle: [0.15, 0.65], triangleDown: [-0.15, 0.65], hexagon: [0, 0.95],
};

// Draws one marker of a category centred at (x, y) with radius r on a 2D canvas context (or an
// SvgPathContext). fade: towards white (confidenceFade); ring: a class whose colour rings the
// marker (an unclassified run's runner-up).
export function drawMarker(ctx, cat, x, y, r, progress = 0, fade = 0, ring = null) {
  const lk = look(cat);
  if (ring && CLASSES[ring]) {
    ctx.beginPath();
    ctx.arc(x, y, r + 1.6, 0, 2 * Math.PI);
    ctx.lineWidth = 2.2; ctx.strokeStyle = CLASSES[ring].color; ctx.stroke();
  }
  ctx.beginPath();
  switch (lk.shape) {
    case 'hollow':
      ctx.arc(x, y, r * 0.9, 0, 2 * Math.PI);
      ctx.fillStyle = '#ffffff'; ctx.fill();
      ctx.setLineDash([2.5, 2]); ctx.lineWidth = 1.6; ctx.strokeStyle = lk.color; ctx.stroke(); ctx.setLineDash([]);
      return;
    case 'ring':
      ctx.arc(x, y, r * 0.85, 0, 2 * Math.PI);
      ctx.fillStyle = '#ffffff'; ctx.fill();
      ctx.lineWidth = 1.2; ctx.strokeStyle = '#9aa0a8'; ctx.stroke();
      ctx.beginPath();
      ctx.arc(x, y, r * 0.85, -Math.PI / 2, -Math.PI / 2 + 2 * Math.PI * Math.max(0.08, Math.min(1, progress)));
      ctx.lineWidth = 2.6; ctx.strokeStyle = lk.color; ctx.stroke();
      return;
    case 'cross':
      ctx.moveTo(x - r, y - r); ctx.lineTo(x + r, y + r); ctx.moveTo(x + r, y - r); ctx.lineTo(x - r, y + r);
      ctx.lineWidth = 2.4; ctx.strokeStyle = lk.color; ctx.stroke();
      return;
    case 'dash':
      ctx.moveTo(x - r, y); ctx.lineTo(x + r, y); ctx.lineWidth = 2; ctx.strokeStyle = lk.color; ctx.stroke();
      return;
    case 'bang':
      ctx.moveTo(x, y - r * 1.25); ctx.lineTo(x + r * 1.15, y + r * 0.9); ctx.lineTo(x - r * 1.15, y + r * 0.9); ctx.closePath();
      ctx.fillStyle = '#ffffff'; ctx.fill(); ctx.lineWidth = 1.6; ctx.strokeStyle = lk.color; ctx.stroke();
      ctx.beginPath(); ctx.moveTo(x, y - r * 0.45); ctx.lineTo(x, y + r * 0.2); ctx.moveTo(x, y + r * 0.45); ctx.lineTo(x, y + r * 0.55); ctx.stroke();
      return;
    default: shapePath(ctx, lk.shape, x, y, r);
  }
  ctx.fillStyle = fade > 0 ? fadeColor(lk.color, fade) : lk.color;
  ctx.fill();
  const outline = fade >= OUTLINE_FROM_FADE;
  ctx.lineWidth = outline ? 1.5 : 1;
  ctx.strokeStyle = outline ? lk.color : 'rgba(255,255,255,0.9)';
  ctx.stroke();
}

// A small canvas swatch for legends (HTML).
export function swatch(cat, size = 16) {
  const c = document.createElement('canvas');
  const dpr = window.devicePixelRatio || 1;
  c.width = size * dpr; c.height = size * dpr;
  c.style.width = `${size}px`; c.style.height = `${size}px`;
  c.className = 'swatch';
  const ctx = c.getContext('2d');
  ctx.scale(dpr, dpr);
  drawMarker(ctx, cat, size / 2, size / 2, size * 0.32, 0.6);
  return c;
}
