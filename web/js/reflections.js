// The colours of the number of reflections N_r of a band (the paper's Fig. 3 colours its points
// by it): viridis at N_r = 0 .. NR_MAX - 1 and one colour for NR_MAX or more. The band-speed page
// (js/pages/bands.js) and the Plots page (js/pages/plots.js) draw with them.
import { colormap, cssColor } from './plot.js';

export const NR_MAX = 6; // colours for N_r = 0 .. 5 and "6 or more"
let colors = null; // NR_MAX + 1 CSS colours, made at the first call

export function nrColor(n) {
  if (!colors) {
    const lut = colormap('viridis');
    colors = Array.from({ length: NR_MAX + 1 }, (_, k) => cssColor(lut, (k / NR_MAX) * 0.92));
  }
  return colors[Math.max(0, Math.min(NR_MAX, Math.round(n)))];
}
