// Plate stresses against imposed strain from frames.csv, shared by the run page (a run's two
// plates, js/pages/run.js) and the compare page (one plate of several runs, js/pages/compare.js).
// On a log axis by default: the top plate's stress reaches thousands of q_y in an inertial run
// while the plateau the paper discusses lies near 1-10 q_y, a flat line at the foot of a linear
// axis; the log axis leaves out the frames at zero stress.
import { Plot, linearExtent, logExtent } from './plot.js';
import { strainTicks } from './spacetime.js';

// The foot of the log axis [q_y]: a plate reached by the elastic precursor's first ripples only
// carries stresses down to 1e-150 q_y (round-off), which would stretch the axis over 150 decades;
// what a reader needs starts well below first yield (~0.2 q_y for buckling struts).
export const STRESS_LOG_FLOOR = 1e-3;

// The strains and the two plates' stresses over q_y of a parsed frames.csv (null without them).
export function plateStresses(frames) {
  if (!frames || !frames.columns.eps) return null;
  const c = frames.columns;
  return { eps: Array.from(c.eps), top: Array.from(c.sigma_top_over_qy || []), bottom: Array.from(c.sigma_bottom_over_qy || []) };
}

// A row of toggle buttons (class "tabs"): choices [[key, text]], the one on, onPick(key).
export function toggleTabs(label, choices, on, onPick, cls = '') {
  const tabs = document.createElement('div');
  tabs.className = `tabs ${cls}`.trim();
  tabs.setAttribute('role', 'group');
  tabs.setAttribute('aria-label', label);
  for (const [k, t] of choices) {
    const b = document.createElement('button');
    b.type = 'button';
    b.dataset.scale = k;
    b.textContent = t;
    b.className = on === k ? 'on' : '';
    b.setAttribute('aria-pressed', String(on === k));
    b.addEventListener('click', () => onPick(k));
    tabs.append(b);
  }
  return tabs;
}

// Whether a log axis can show the values (some at or above the floor).
export const logShows = (values) => values.some((v) => v >= STRESS_LOG_FLOOR);

// The plot of series [{eps, values, attrs}] (each from 0 stress at ε = 0) on a log (log: true,
// when logShows) or linear y axis. width: px; svgId: the SVG's id. Returns the Plot.
export function stressPlot(box, series, { log, width, svgId }) {
  const all = series.flatMap((s) => s.values);
  const epsMax = Math.max(0, ...series.map((s) => s.eps[s.eps.length - 1] || 0)) || 1;
  const yd = log ? logExtent(all.filter((v) => v >= STRESS_LOG_FLOOR), [0.1, 10], 1) : linearExtent(all.concat([0]), [0, 1], 0.06);
  const plot = new Plot(box, {
    width, height: 360, margin: { l: 70, r: 16, t: 14, b: 56 }, title: 'plate stress',
    x: { kind: 'linear', domain: [0, epsMax], label: 'imposed strain ε = Vt / h_{0}', ticks: strainTicks(width - 86) },
    y: { kind: log ? 'log' : 'linear', domain: yd, label: 'plate stress σ / q_{y}' },
  });
  if (svgId) plot.svg.id = svgId;
  plot.svg.dataset.scale = log ? 'log' : 'linear';
  const clip = plot.clipRect();
  const shown = (v) => (log && !(v >= STRESS_LOG_FLOOR) ? NaN : v); // below the floor: a gap
  for (const s of series) plot.line([0, ...s.eps], [0, ...s.values].map(shown), { 'clip-path': clip, ...s.attrs });
  return plot;
}

// The caption's words on the axis: q_y in N/m, and the floor of a log axis.
export function stressAxisText(qy, log) {
  return `in units of the yield strength <i>q</i><sub>y</sub>${qy === undefined ? '' : ` = ${qy} N/m`}${log ? ', on a log axis (from 10<sup>−3</sup> <i>q</i><sub>y</sub>: frames below it, at zero stress or in round-off, are left out)' : ''}`;
}
