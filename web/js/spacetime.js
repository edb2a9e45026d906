// A run's space-time map (spacetime.npy over frames.csv's strains) and the loading of the two
// files, shared by the run page (js/pages/run.js) and the compare page (js/pages/compare.js): the
// map is drawn the same way on both, on its own colour scale on a run page and on one scale for
// every run compared.
import { fetchArtifact } from './api.js';
import { parseNpy } from './npy.js';
import { parseCsv } from './csv.js';
import { Plot, colormap, colorBar } from './plot.js';
import { RATE_LABEL } from './particles.js';
import { fixed } from './format.js';

// How many ticks a strain axis of px pixels asks for: one per 60 px (a label such as "0.025"
// and its gap), at most the 7 of a wide figure.
export const strainTicks = (px) => Math.max(2, Math.min(7, Math.floor(px / 60)));

// frames.csv of run id parsed (null when the run has none or it cannot be read); names: the
// names of the run's artifacts.
export async function loadFrames(id, names) {
  if (!names.has('frames.csv')) return null;
  try {
    return parseCsv(await fetchArtifact(id, 'frames.csv', 'text'));
  } catch (e) {
    console.error('frames.csv', e);
    return null;
  }
}

// spacetime.npy of run id parsed (null when the run has none or it cannot be read).
export async function loadSpacetime(id, names) {
  if (!names.has('spacetime.npy')) return null;
  try {
    return parseNpy(await fetchArtifact(id, 'spacetime.npy'));
  } catch (e) {
    console.error('spacetime.npy', e);
    return null;
  }
}

// The map's colour quantity, log10(1 + rate) as in spacetime.png, a value a cell.
function spacetimeValues(npy) {
  const vals = new Float32Array(npy.data.length);
  for (let i = 0; i < vals.length; i++) vals[i] = Math.log10(1 + Math.max(0, npy.data[i]));
  return vals;
}

// The map's colour quantity and its extent: lo the lowest value, hi the 99.5th percentile (the
// top 0.5 % clipped, so one spike does not wash the map out).
export function spacetimeLevels(npy) {
  const vals = spacetimeValues(npy);
  const sorted = Float32Array.from(vals).sort();
  const lo = sorted.length ? sorted[0] : 0;
  const hi = Math.max(sorted.length ? sorted[Math.floor(0.995 * (sorted.length - 1))] : 0, 1e-6);
  return { vals, lo, hi };
}

// The space-time map of spacetime.npy as an image of height against imposed strain. opts:
// scale {lo, hi} of the colour quantity (default: the map's own, from 0 to its clipping top);
// colorBar (default true), caption (default true), width and height (default: the box's width,
// 400 px), ids of the canvas and the plate's line, title. Returns {plot, lo, hi}.
export function drawSpacetime(box, npy, summary, frames, id, opts = {}) {
  const [nf, nr] = npy.shape;
  const h0 = summary.params?.h0 || 1;
  const rowH = summary.spacetime?.row_height || h0 / nr;
  const dEps = summary.params?.d_eps || 0.002;
  const epsAt = (i) => (frames && frames.columns.eps && frames.rows === nf ? frames.columns.eps[i] : (i + 1) * dEps);
  const eps1 = epsAt(nf - 1);
  const eps0 = Math.max(0, eps1 - (nf === 1 ? dEps : (epsAt(nf - 1) - epsAt(0)) * nf / (nf - 1)));
  const top = (nr * rowH) / h0;
  // The map's own extent (a sort of its values) only when the caller gives no scale.
  const levels = opts.scale ? null : spacetimeLevels(npy);
  const { lo, hi } = opts.scale || { lo: 0, hi: levels.hi };
  const span = hi - lo || 1;
  const vals = levels ? levels.vals : spacetimeValues(npy);
  const lut = colormap('inferno');
  const img = new ImageData(nf, nr);
  for (let f = 0; f < nf; f++) {
    // Rows whose bottom is at or above the top plate, h0 (1 - ε), hold no particles (their 0
    // is no measurement): they stay transparent, the plot's background, not the colour of 0.
    const firstEmpty = Math.ceil(((1 - epsAt(f)) * h0) / rowH - 1e-9);
    for (let r = 0; r < nr; r++) {
      const o = ((nr - 1 - r) * nf + f) * 4; // height up
      if (r >= firstEmpty) continue;
      const k = Math.max(0, Math.min(255, Math.round(((vals[f * nr + r] - lo) / span) * 255))) * 3;
      img.data[o] = lut[k]; img.data[o + 1] = lut[k + 1]; img.data[o + 2] = lut[k + 2]; img.data[o + 3] = 255;
    }
  }
  const off = document.createElement('canvas');
  off.width = nf; off.height = nr;
  off.getContext('2d').putImageData(img, 0, 0);
  box.replaceChildren();
  const bar = opts.colorBar !== false;
  // A phone's card: 340 px, 160 of them the map beside its colour bar.
  const width = opts.width || Math.max(340, Math.min(1160, box.clientWidth || 900));
  const plot = new Plot(box, {
    width, height: opts.height || 400, canvas: true, margin: { l: 70, r: bar ? 110 : 16, t: 12, b: 56 }, title: opts.title || 'space-time map',
    x: { kind: 'linear', domain: [eps0, eps1], label: 'imposed strain ε = Vt / h_{0}', ticks: strainTicks(plot0Width(width, bar)) },
    y: { kind: 'linear', domain: [0, top], label: 'height y / h_{0}' },
  });
  plot.canvas.id = opts.canvasId ?? 'st-canvas';
  plot.ctx.imageSmoothingEnabled = nf < plot.pw / 3 ? false : true;
  plot.ctx.drawImage(off, 0, 0, plot.pw, plot.ph);
  if (bar) colorBar(plot.svg, { x: plot.m.l + plot.pw + 14, y: plot.m.t, w: 14, h: plot.ph, lut, lo, hi, label: RATE_LABEL });
  // The top plate, y/h0 = 1 - ε: the map's upper edge in the current configuration.
  plot.line([eps0, eps1], [1 - eps0, 1 - eps1], { class: 'plate-line', ...(opts.plateId === null ? {} : { id: opts.plateId ?? 'st-plate' }), 'clip-path': plot.clipRect() });
  plot.canvas.dataset.frames = nf;
  plot.canvas.dataset.rows = nr;
  if (opts.caption !== false) {
    const cap = document.createElement('p');
    cap.className = 'caption';
    cap.innerHTML = `Row-averaged plastic Hencky strain-rate magnitude, ${nf} frames × ${nr} rows (row height ${fixed(rowH / h0 * 1000, 2)}·10<sup>−3</sup> h<sub>0</sub>). A compaction band is a bright line; its slope is the band speed. Above the top plate (the line) there is no material. <a href="/api/v1/jobs/${id}/artifacts/spacetime.npy">spacetime.npy</a>`;
    box.append(cap);
  }
  return { plot, lo, hi };
}

// The plot area's width of a map of width px (its margins: 70 px left, the colour bar's 110 or 16).
const plot0Width = (width, bar) => width - 70 - (bar ? 110 : 16);
