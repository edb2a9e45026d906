// The movie player of the run page: movie.bin's frames (web/js/movie.js) drawn one at a time in
// a particle figure (web/js/particles.js), with play/pause, a slider over the frames and the
// imposed strain of the frame shown. The top plate is drawn at y/h0 = 1 - ε.
import { PERIODIC_X } from './movie.js';
import { particleFigure } from './particles.js';
import { fixed } from './format.js';

const FRAME_MS = 150;

// movie: parseMovie's answer; vmax: the top of the colour scale on log10(1 + rate), the
// space-time map's; spacing: the particle spacing [m]. Returns a function that stops playing.
export function mountPlayer(box, movie, { vmax, lut, spacing }) {
  const { header, frames } = movie;
  const copies = header.flags & PERIODIC_X ? 8 : 1;
  const width = header.xHi - header.xLo, h0 = header.yHi - header.yLo;
  box.replaceChildren();
  const { plot, draw } = particleFigure(box, { width, h0, copies, spacing, vmax, lut, title: 'movie' });
  plot.canvas.id = 'movie-canvas';
  plot.canvas.dataset.frames = frames.length;
  const aspect = (copies * width) / h0;
  const plate = plot.line([0, aspect], [1, 1], { class: 'plate-line', 'clip-path': plot.clipRect() });

  const bar = document.createElement('div');
  bar.className = 'player';
  bar.innerHTML = `<button type="button" id="movie-play" aria-label="play">▶</button>
    <input type="range" id="movie-slider" min="0" max="${frames.length - 1}" step="1" value="0" aria-label="frame">
    <span id="movie-eps" class="player-eps"></span>`;
  box.append(bar);
  const button = bar.querySelector('#movie-play');
  const slider = bar.querySelector('#movie-slider');
  const label = bar.querySelector('#movie-eps');

  const sx = width / 65535, sy = h0 / 65535, rate = header.rateLog10Max / 255 / vmax;
  let shown = -1, timer = null;
  function show(k) {
    const f = frames[k];
    draw(header.n, (i) => header.xLo + f.x[i] * sx, (i) => header.yLo + f.y[i] * sy, (i) => f.level[i] * rate);
    const top = 1 - f.eps;  // the plate's height / h0 at the frame
    plate.setAttribute('d', `M${plot.x.map(0)},${plot.y.map(top)}L${plot.x.map(aspect)},${plot.y.map(top)}`);
    slider.value = String(k);
    label.innerHTML = `ε = ${fixed(f.eps, 3)} <span class="muted">· frame ${k + 1} of ${frames.length}</span>`;
    plot.canvas.dataset.frame = k;
    plot.canvas.dataset.eps = f.eps;
    shown = k;
  }
  function pause() {
    clearInterval(timer);
    timer = null;
    button.textContent = '▶';
    button.setAttribute('aria-label', 'play');
  }
  function play() {
    if (shown >= frames.length - 1) show(0);
    button.textContent = '❚❚';
    button.setAttribute('aria-label', 'pause');
    timer = setInterval(() => (shown + 1 < frames.length ? show(shown + 1) : pause()), FRAME_MS);
  }
  button.addEventListener('click', () => (timer ? pause() : play()));
  slider.addEventListener('input', () => { pause(); show(Number(slider.value)); });
  show(0);
  return pause;
}
