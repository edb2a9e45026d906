// A stand-in for the few CanvasRenderingContext2D calls that drawMarker (classes.js) makes,
// writing SVG paths instead of pixels: the phase map's SVG export draws its markers with the
// same code as the canvas, as vectors.
import { svgEl } from './plot.js';

const f = (v) => Number(v.toFixed(2));

export class SvgPathContext {
  constructor(parent) {
    this.parent = parent;
    this.d = '';
    this.fillStyle = '#000000';
    this.strokeStyle = '#000000';
    this.lineWidth = 1;
    this.dash = [];
  }

  beginPath() { this.d = ''; }
  moveTo(x, y) { this.d += `M${f(x)},${f(y)}`; }
  lineTo(x, y) { this.d += `L${f(x)},${f(y)}`; }
  closePath() { this.d += 'Z'; }
  rect(x, y, w, h) { this.d += `M${f(x)},${f(y)}h${f(w)}v${f(h)}h${f(-w)}Z`; }
  setLineDash(d) { this.dash = d; }

  // Clockwise from angle a0 to a1 (radians, y down), as canvas draws it; a whole turn is two
  // half arcs (one SVG arc cannot start and end at the same point).
  arc(x, y, r, a0, a1) {
    const at = (a) => [x + r * Math.cos(a), y + r * Math.sin(a)];
    const [sx, sy] = at(a0);
    this.d += `${this.d ? 'L' : 'M'}${f(sx)},${f(sy)}`;
    const span = a1 - a0;
    if (span >= 2 * Math.PI - 1e-9) {
      const [mx, my] = at(a0 + Math.PI);
      this.d += `A${f(r)},${f(r)} 0 0 1 ${f(mx)},${f(my)}A${f(r)},${f(r)} 0 0 1 ${f(sx)},${f(sy)}`;
      return;
    }
    const [ex, ey] = at(a1);
    this.d += `A${f(r)},${f(r)} 0 ${span > Math.PI ? 1 : 0} 1 ${f(ex)},${f(ey)}`;
  }

  fill() { svgEl('path', { d: this.d, fill: this.fillStyle, stroke: 'none' }, this.parent); }

  stroke() {
    const a = { d: this.d, fill: 'none', stroke: this.strokeStyle, 'stroke-width': this.lineWidth };
    if (this.dash.length) a['stroke-dasharray'] = this.dash.join(' ');
    svgEl('path', a, this.parent);
  }
}
