// The phase map's background: the classes GET /phase-map/regions predicts from the labelled
// runs (server/plan/phase_regions.hpp), tinted in the class colours, greyed where the prediction is
// uncertain (near a boundary, at low confidences, far from any run), as the paper's Fig. 2
// shades its regions.
import { CLASSES } from './classes.js';

// A cell's look over the white plot area: its class colour at TINT x (1 - uncertainty), then a
// grey wash at WASH x uncertainty, so a certain cell is a light tint of its class, an uncertain
// one light grey, and markers (full colour, white outline) stay readable over either.
export const TINT = 0.4;
export const WASH = 0.35;
export const WASH_RGB = [150, 155, 163];
const WHITE = [255, 255, 255];

const rgb = (hex) => [1, 3, 5].map((i) => parseInt(hex.slice(i, i + 2), 16));
const mix = (a, b, t) => a.map((v, k) => v + (b[k] - v) * t);

// The colour ([r, g, b], 0-255) of a cell of class cls ('.' or unknown: none) and uncertainty u.
export function cellColor(cls, u) {
  const c = CLASSES[cls];
  const tinted = c ? mix(WHITE, rgb(c.color), TINT * (1 - u)) : WHITE;
  return mix(tinted, WASH_RGB, WASH * u).map(Math.round);
}

// Draws the regions on the plot's canvas (under the markers: call first). Returns where the
// box landed in canvas pixels, or null when there is nothing to draw.
export function drawRegions(plot, data) {
  if (!data || !data.grid) return null;
  const n = data.grid;
  const off = document.createElement('canvas');
  off.width = n; off.height = n;
  const octx = off.getContext('2d');
  const img = octx.createImageData(n, n);
  for (let j = 0; j < n; j++) {
    const row = data.classes[j], u = data.uncertainty[j];
    const y = n - 1 - j; // rows come from the smallest R up
    for (let i = 0; i < n; i++) {
      const [r, g, b] = cellColor(row[i], u[i]);
      const k = 4 * (y * n + i);
      img.data[k] = r; img.data[k + 1] = g; img.data[k + 2] = b; img.data[k + 3] = 255;
    }
  }
  octx.putImageData(img, 0, 0);
  const x0 = plot.cx(10 ** data.S.log_min), x1 = plot.cx(10 ** data.S.log_max);
  const y0 = plot.cy(10 ** data.R.log_max), y1 = plot.cy(10 ** data.R.log_min);
  const ctx = plot.ctx;
  ctx.save();
  ctx.imageSmoothingEnabled = true;
  ctx.imageSmoothingQuality = 'high';
  ctx.drawImage(off, x0, y0, x1 - x0, y1 - y0);
  ctx.restore();
  return { x0, y0, x1, y1, image: off };
}

// The cell of the regions under canvas pixel (x, y) of the plot: {cls, u}, or null outside.
export function cellAt(plot, data, x, y) {
  if (!data || !data.grid) return null;
  const n = data.grid;
  const lx = Math.log10(plot.x.invert(x + plot.m.l)), ly = Math.log10(plot.y.invert(y + plot.m.t));
  const i = Math.floor(((lx - data.S.log_min) / (data.S.log_max - data.S.log_min)) * n);
  const j = Math.floor(((ly - data.R.log_min) / (data.R.log_max - data.R.log_min)) * n);
  if (i < 0 || j < 0 || i >= n || j >= n) return null;
  return { cls: data.classes[j][i], u: data.uncertainty[j][i] };
}
