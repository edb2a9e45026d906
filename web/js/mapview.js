// The phase map's view: which part of the (log10 S, log10 R) plane the plot shows, kept in the
// URL (S=lo,hi&R=lo,hi in decades: log10 of the axis ends) so that a reload or a shared link
// shows the same part; zoom about the cursor with the wheel, pan by dragging, and on a touch
// screen pan with a finger and pinch with two (the page scrolls from outside the plot). The
// marker radius is read
// from the points' spacing on screen, so that dense points stay apart.

// A view: { S: [lo, hi], R: [lo, hi] } in decades, or null for the points' own extent.
const DIGITS = 4; // decades in the URL: 1e-4 decade, a fraction of a pixel on any screen
const MIN_SPAN = 0.02; // the narrowest axis in decades (a tenth of the finest adaptive step, 1/64 decade, is below any run's use)
const MAX_SPAN = 12; // the widest: the scene's S and R lie in (0, 1)
const WHEEL_RATE = 0.0015; // zoom per wheel pixel: a mouse notch (100 px) zooms by e^0.15, 16 %
const DRAG_FROM = 4; // px the pointer moves before a press becomes a drag (less: a click)

const round = (v) => Number(v.toFixed(DIGITS));
const pair = (a, b) => [round(a), round(b)];

// The view of the URL's query, or null when it has none (or a broken one).
export function viewOf(params) {
  const axis = (s) => {
    const v = String(s || '').split(',').map(Number);
    return v.length === 2 && v.every(Number.isFinite) && v[1] - v[0] >= MIN_SPAN / 2 && v[1] - v[0] <= MAX_SPAN ? v : null;
  };
  const S = axis(params.S), R = axis(params.R);
  return S && R ? { S, R } : null;
}

// The view as URL parameters (empty for none, which the router leaves out).
export const viewParams = (view) => (view ? { S: view.S.join(','), R: view.R.join(',') } : { S: '', R: '' });

// The view a plot shows (its axes' domains in decades).
export const plotView = (plot) => ({ S: [Math.log10(plot.x.d0), Math.log10(plot.x.d1)], R: [Math.log10(plot.y.d0), Math.log10(plot.y.d1)] });

// The view with the data point (u, v) (decades) at (px, py) (pixels from the plot area's top
// left, w x h), each axis `span` decades long, clamped to [MIN_SPAN, MAX_SPAN].
function viewAt(u, v, px, py, spanS, spanR, w, h) {
  const sS = Math.min(MAX_SPAN, Math.max(MIN_SPAN, spanS)), sR = Math.min(MAX_SPAN, Math.max(MIN_SPAN, spanR));
  const S0 = u - (px / w) * sS, R1 = v + (py / h) * sR;
  return { S: pair(S0, S0 + sS), R: pair(R1 - sR, R1) };
}

// The data point (decades) under a pixel of the plot area of a view.
const dataAt = (view, px, py, w, h) => [view.S[0] + (px / w) * (view.S[1] - view.S[0]), view.R[1] - (py / h) * (view.R[1] - view.R[0])];

// The view zoomed by `factor` (< 1: in) about the pixel (px, py): the data point there stays.
export function zoomAbout(view, px, py, factor, w, h) {
  const [u, v] = dataAt(view, px, py, w, h);
  return viewAt(u, v, px, py, (view.S[1] - view.S[0]) * factor, (view.R[1] - view.R[0]) * factor, w, h);
}

// The view moved so that what was at (px0, py0) is at (px1, py1), zoomed by factor about it.
function moved(view, px0, py0, px1, py1, factor, w, h) {
  const [u, v] = dataAt(view, px0, py0, w, h);
  return viewAt(u, v, px1, py1, (view.S[1] - view.S[0]) * factor, (view.R[1] - view.R[0]) * factor, w, h);
}

// Wheel, drag and pinch on the plot box (it outlives the plot's canvas, which every render
// replaces). opts: plot() the current Plot, onView(view) for every new view (the caller redraws,
// at most once a frame), onDrag(dragging) when a drag starts and ends. A press that moved
// less than DRAG_FROM px stays a click; after a drag, wasDrag() is true until the click that
// ends it has been dispatched. Returns a function that removes the listeners.
export function wireView(box, { plot, onView, onDrag }) {
  const area = (ev) => {
    const p = plot();
    if (!p?.canvas) return null;
    const r = p.canvas.getBoundingClientRect();
    const x = ev.clientX - r.left, y = ev.clientY - r.top;
    return x >= 0 && y >= 0 && x <= r.width && y <= r.height ? { x, y, w: r.width, h: r.height, p } : null;
  };
  let frame = 0, next = null;
  const show = (view) => {
    next = view;
    if (!frame) frame = requestAnimationFrame(() => { frame = 0; onView(next); });
  };
  const current = () => next || plotView(plot());

  const onWheel = (ev) => {
    const a = area(ev);
    if (!a || ev.ctrlKey && ev.deltaMode === 0 && Math.abs(ev.deltaY) < 1) return;
    ev.preventDefault();
    const dy = ev.deltaY * (ev.deltaMode === 1 ? 33 : ev.deltaMode === 2 ? a.h : 1);
    show(zoomAbout(current(), a.x, a.y, Math.exp(dy * WHEEL_RATE), a.w, a.h));
  };

  // Pointers down on the plot area: id -> {x, y} now; a gesture starts from their first places.
  const down = new Map();
  let start = null, dragged = false, clickAfterDrag = false;
  const centre = () => {
    const v = [...down.values()];
    const x = v.reduce((s, q) => s + q.x, 0) / v.length, y = v.reduce((s, q) => s + q.y, 0) / v.length;
    const d = v.length > 1 ? Math.hypot(v[0].x - v[1].x, v[0].y - v[1].y) : 0;
    return { x, y, d };
  };
  const begin = () => { start = { view: current(), ...centre() }; };
  const onDown = (ev) => {
    const a = area(ev);
    if (!a || (ev.pointerType === 'mouse' && ev.button !== 0)) return;
    if (ev.pointerType === 'mouse') { down.clear(); dragged = false; } // a press whose release was missed
    if (down.size >= 2) return; // a third finger changes nothing
    down.set(ev.pointerId, { x: a.x, y: a.y });
    begin(); // a second finger starts a pinch from here
  };
  const onMove = (ev) => {
    const q = down.get(ev.pointerId);
    if (!q || !start) return;
    const r = plot().canvas.getBoundingClientRect();
    q.x = ev.clientX - r.left; q.y = ev.clientY - r.top;
    const c = centre();
    if (!dragged && Math.hypot(c.x - start.x, c.y - start.y) < DRAG_FROM && Math.abs(c.d - start.d) < DRAG_FROM) return;
    if (!dragged) {
      dragged = true;
      // Captured only once it is a drag: a capture at the press would send the click of a plain
      // press to the box instead of the marker's canvas.
      for (const id of down.keys()) try { box.setPointerCapture(id); } catch { /* gone */ }
      onDrag(true);
    }
    const factor = start.d > 0 && c.d > 0 ? start.d / c.d : 1;
    show(moved(start.view, start.x, start.y, c.x, c.y, factor, r.width, r.height));
  };
  const onUp = (ev) => {
    if (!down.delete(ev.pointerId)) return;
    if (down.size && start) { begin(); return; } // one finger of two lifted: go on from here
    start = null;
    if (dragged) { dragged = false; clickAfterDrag = true; setTimeout(() => { clickAfterDrag = false; }, 0); onDrag(false); }
  };
  const listeners = [['wheel', onWheel, { passive: false }], ['pointerdown', onDown], ['pointermove', onMove], ['pointerup', onUp], ['pointercancel', onUp]];
  for (const [k, f, o] of listeners) box.addEventListener(k, f, o);
  return {
    wasDrag: () => clickAfterDrag || dragged,
    // The view asked for but not drawn yet (a render in between takes it).
    settle: () => { next = null; },
    remove: () => { cancelAnimationFrame(frame); for (const [k, f, o] of listeners) box.removeEventListener(k, f, o); },
  };
}

// Marker radii from the points' spacing on screen: each place's markers get RADIUS_SHARE of the
// distance to its nearest neighbouring place, between MIN_RADIUS (a shape still reads) and
// `most` (the radius for the count), so that a dense scan (1/20 decade) stays a set of markers
// while the sparse rest of the map keeps full-size ones; zoomed in, the dense part grows too.
// places: Float32Array [x, y, ...] of distinct places in pixels; shared[i]: place i holds several
// points (set around it, so it needs about SHARED_ROOM times the room; a pair of places shares
// the room of both). Returns a radius per place.
const RADIUS_SHARE = 0.45;
const SHARED_ROOM = 2.2;
export const MIN_RADIUS = 2.4;
export function spacingRadii(places, most, shared) {
  const n = places.length / 2;
  const room = Array.from({ length: n }, (_, i) => (shared[i] ? SHARED_ROOM : 1));
  const cap = (most / RADIUS_SHARE) * SHARED_ROOM; // farther than this: the full radius
  const order = Array.from({ length: n }, (_, i) => i).sort((a, b) => places[2 * a] - places[2 * b]);
  const nn = new Float64Array(n).fill(cap); // the nearest distance over the pair's mean room
  for (let k = 0; k < n; k++) {
    const i = order[k], x = places[2 * i], y = places[2 * i + 1];
    for (let j = k + 1; j < n; j++) {
      const o = order[j], dx = places[2 * o] - x;
      if (dx >= cap) break;
      const d = Math.hypot(dx, places[2 * o + 1] - y) / ((room[i] + room[o]) / 2);
      if (d < nn[i]) nn[i] = d;
      if (d < nn[o]) nn[o] = d;
    }
  }
  return Array.from(nn, (d) => Math.max(MIN_RADIUS, Math.min(most, RADIUS_SHARE * d)));
}
