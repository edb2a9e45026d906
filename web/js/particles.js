// A figure of the particles of a run coloured by plastic strain rate, as snapshot_<eps>.png
// draws them but with axes and the colour bar of the space-time map: height y/h0 up, x/h0
// across (pseudo-1D: `copies` periods side by side), inferno on log10(1 + |ε̇_P| h0/V) over
// [0, vmax]. Each particle is a square of its spacing (at least a pixel); where several fall on
// one pixel the fastest shows. Pixels without a particle keep the plot's background.
import { Plot, colorBar } from './plot.js';

export const RATE_LABEL = 'log_{10}(1 + |ε̇_{P}| h_{0}/V)';
const PLOT_HEIGHT = 420;

// opts: width and h0 of the specimen [m], copies, spacing (particle spacing [m]), vmax, lut.
export function particleFigure(box, { width, h0, copies, spacing, vmax, lut, title }) {
  const aspect = (copies * width) / h0;
  const m = { l: 58, r: 90, t: 10, b: 52 };
  const pw = Math.max(40, Math.round(PLOT_HEIGHT * aspect));
  const plot = new Plot(box, {
    width: pw + m.l + m.r, height: PLOT_HEIGHT + m.t + m.b, canvas: true, margin: m, title,
    x: { kind: 'linear', domain: [0, aspect], label: 'x / h_{0}', ticks: 2 },
    y: { kind: 'linear', domain: [0, 1], label: 'height y / h_{0}' },
  });
  colorBar(plot.svg, { x: m.l + plot.pw + 12, y: m.t, w: 12, h: plot.ph, lut, lo: 0, hi: vmax, label: RATE_LABEL });
  const W = plot.canvas.width, H = plot.canvas.height;
  const img = new ImageData(W, H);
  const best = new Int16Array(W * H);
  const dot = Math.max(1, Math.ceil((spacing / h0) * H));
  const period = W / copies;
  const sx = period / width, sy = H / h0;

  // n particles; x(i), y(i) in metres, t(i) the colour in [0, 1].
  function draw(n, x, y, t) {
    best.fill(-1);
    for (let i = 0; i < n; i++) {
      const level = Math.round(Math.min(1, Math.max(0, t(i) || 0)) * 255);
      const px0 = Math.floor(x(i) * sx - dot / 2);
      const py0 = Math.floor(H - y(i) * sy - dot / 2);
      for (let c = 0; c < copies; c++) {
        const cx = px0 + Math.round(c * period);
        for (let py = Math.max(0, py0); py < Math.min(H, py0 + dot); py++) {
          for (let px = Math.max(0, cx); px < Math.min(W, cx + dot); px++) {
            const k = py * W + px;
            if (level > best[k]) best[k] = level;
          }
        }
      }
    }
    const d = img.data;
    for (let k = 0; k < best.length; k++) {
      const o = k * 4, l = best[k];
      if (l < 0) { d[o + 3] = 0; continue; }
      d[o] = lut[l * 3]; d[o + 1] = lut[l * 3 + 1]; d[o + 2] = lut[l * 3 + 2]; d[o + 3] = 255;
    }
    plot.ctx.putImageData(img, 0, 0);
  }
  return { plot, draw };
}
