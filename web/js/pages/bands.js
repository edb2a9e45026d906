// Band speed: c_b/V against q_y/(rho V^2) = R/S^2 on log-log axes, coloured by the number of
// reflections N_r (Fig. 3 of the paper), from the labelled runs of one phi.
import { api } from '../api.js';
import { CLASSES, label } from '../classes.js';
import { Plot, logExtent, svgEl, colormap, cssColor } from '../plot.js';
import { nonReflectingSpeed, stressRatio } from '../physics.js';
import { sci, fixed, escapeHtml } from '../format.js';
import { sweepPhis } from '../sweepmath.js';
import { setParams } from '../router.js';

const POLL_MS = 4000;
const NR_MAX = 6; // colours for N_r = 0 .. 5 and "6 or more"

export function nrColor(n) {
  const lut = colormap('viridis');
  return cssColor(lut, Math.min(n, NR_MAX) / NR_MAX * 0.92);
}

export function mount(root, params) {
  const state = { phi: params.phi ? Number(params.phi) : null, points: [], sig: '' };
  let alive = true, timer = null, drawn = [], plot = null;
  root.innerHTML = `
    <div class="page-head">
      <h1>Band speed</h1>
      <p class="sub">Speed of the compaction band <i>c</i><sub>b</sub>/<i>V</i> against the ratio of yield to inertial stress
        <i>q</i><sub>y</sub>/(ρ<i>V</i>²) = <i>R</i>/<i>S</i>², for every labelled run with a measured band speed at one φ.</p>
    </div>
    <div class="layout-map">
      <section class="card figure"><div class="figure-plot" id="bands-plot"></div><div class="figure-foot"><span id="bands-summary" class="summary"></span></div></section>
      <aside class="card controls">
        <label class="field">Solid fraction φ <select id="bands-phi" aria-label="solid fraction phi"></select></label>
        <h2 class="legend-title">Reflections <i>N</i><sub>r</sub></h2>
        <ul class="legend" id="bands-legend"></ul>
        <p class="hint">Dashed: a non-reflecting band, <i>c</i><sub>b</sub>/<i>V</i> = 1/(1 − φ). Reflecting bands are faster and grow as a power law of <i>R</i>/<i>S</i>².</p>
      </aside>
    </div>`;
  const $ = (x) => root.querySelector(`#${x}`);
  const tooltip = document.getElementById('tooltip');

  function render() {
    const pts = state.points.filter((p) => p.class && Number.isFinite(p.band_speed_ratio) && p.band_speed_ratio > 0);
    const box = $('bands-plot');
    box.replaceChildren();
    const width = Math.max(560, Math.min(1100, box.clientWidth || 760));
    const xs = pts.map((p) => stressRatio(p.S, p.R));
    const ys = pts.map((p) => p.band_speed_ratio).concat([nonReflectingSpeed(state.phi)]);
    plot = new Plot(box, {
      width, height: Math.round(Math.min(width * 0.62, Math.max(460, window.innerHeight - 260))), canvas: true, margin: { l: 78, r: 24, t: 18, b: 60 }, title: 'band speed',
      x: { kind: 'log', domain: logExtent(xs, [1e-2, 1e3]), label: 'q_{y} / (ρV^{2}) = R / S^{2}' },
      y: { kind: 'log', domain: logExtent(ys, [0.5, 50]), label: 'band speed c_{b} / V' },
    });
    const c0 = nonReflectingSpeed(state.phi);
    const y = plot.y.map(c0);
    svgEl('line', { x1: plot.m.l, x2: plot.m.l + plot.pw, y1: y, y2: y, class: 'overlay-line' }, plot.front);
    svgEl('text', { x: plot.m.l + plot.pw - 8, y: y + 16, 'text-anchor': 'end', class: 'overlay-label' }, plot.front).textContent = `non-reflecting band 1/(1 − φ) = ${c0.toFixed(3)}`;
    drawn = pts.map((p) => ({ p, x: plot.cx(stressRatio(p.S, p.R)), y: plot.cy(p.band_speed_ratio) }));
    const counts = {};
    for (const d of drawn) {
      const n = Math.min(d.p.n_reflections ?? 0, NR_MAX);
      counts[n] = (counts[n] || 0) + 1;
      plot.ctx.beginPath();
      plot.ctx.arc(d.x, d.y, 6, 0, 2 * Math.PI);
      plot.ctx.fillStyle = nrColor(d.p.n_reflections ?? 0);
      plot.ctx.fill();
      plot.ctx.lineWidth = 1.2;
      plot.ctx.strokeStyle = '#1d2433';
      plot.ctx.stroke();
    }
    if (!pts.length) {
      svgEl('text', { x: plot.m.l + plot.pw / 2, y: plot.m.t + plot.ph / 2 + 30, 'text-anchor': 'middle', class: 'empty-note' }, plot.front)
        .textContent = `No labelled run with a band speed at φ = ${state.phi} yet.`;
    }
    plot.canvas.dataset.count = String(drawn.length);
    plot.canvas.addEventListener('mousemove', onMove);
    plot.canvas.addEventListener('mouseleave', () => { tooltip.hidden = true; });
    plot.canvas.addEventListener('click', (ev) => { const d = nearest(ev); if (d) location.hash = `#/run/${d.p.job_id}`; });
    const legend = $('bands-legend');
    legend.replaceChildren(...Array.from({ length: NR_MAX + 1 }, (_, n) => {
      const li = document.createElement('li');
      li.dataset.count = counts[n] || 0;
      if (!counts[n]) li.classList.add('zero');
      li.innerHTML = `<span class="dot big" style="background:${nrColor(n)}"></span><span class="legend-name">${n === NR_MAX ? `${n} or more` : n}${n === 0 ? ' (no reflection)' : ''}</span><span class="legend-count">${counts[n] || 0}</span>`;
      return li;
    }));
    $('bands-summary').innerHTML = `<b>${drawn.length}</b> of ${state.points.length} runs at φ = ${state.phi} have a band speed`;
  }

  function nearest(ev) {
    const r = plot.canvas.getBoundingClientRect();
    const mx = ev.clientX - r.left, my = ev.clientY - r.top;
    let best = null, bd = 12 * 12;
    for (const d of drawn) { const q = (d.x - mx) ** 2 + (d.y - my) ** 2; if (q < bd) { bd = q; best = d; } }
    return best;
  }

  function onMove(ev) {
    const d = nearest(ev);
    if (!d) { tooltip.hidden = true; plot.canvas.style.cursor = ''; return; }
    plot.canvas.style.cursor = 'pointer';
    const p = d.p;
    tooltip.innerHTML = `<div class="tt-head">run ${p.job_id}</div><table>
      <tr><th>S</th><td>${sci(p.S)}</td></tr><tr><th>R</th><td>${sci(p.R)}</td></tr>
      <tr><th>R/S²</th><td>${sci(stressRatio(p.S, p.R))}</td></tr>
      <tr><th><i>c</i><sub>b</sub>/<i>V</i></th><td>${fixed(p.band_speed_ratio, 3)}</td></tr>
      <tr><th><i>N</i><sub>r</sub></th><td>${p.n_reflections ?? '—'}</td></tr>
      <tr><th>class</th><td>${CLASSES[p.class] ? `<span class="dot" style="background:${CLASSES[p.class].color}"></span>` : ''}${escapeHtml(label(p.class))}</td></tr></table>`;
    tooltip.hidden = false;
    tooltip.style.left = `${ev.clientX + 16 + window.scrollX}px`;
    tooltip.style.top = `${ev.clientY + 14 + window.scrollY}px`;
  }

  async function poll() {
    clearTimeout(timer);
    if (!alive) return;
    try {
      const data = await api.phaseMap(state.phi);
      const sig = JSON.stringify(data.points);
      if (alive && sig !== state.sig) { state.sig = sig; state.points = data.points; render(); }
    } catch (e) { $('bands-summary').textContent = `offline: ${e.message}`; }
    if (alive) timer = setTimeout(poll, POLL_MS);
  }

  (async () => {
    let sweeps = [];
    try { sweeps = (await api.sweeps(1000)).sweeps; } catch { /* offline: only the default phi */ }
    if (!alive) return;
    const phis = new Set(sweeps.flatMap((s) => sweepPhis(s.request)).map((p) => Number(p.toPrecision(12))));
    if (state.phi === null) state.phi = sweeps.length ? sweepPhis(sweeps[0].request)[0] ?? 0.4 : 0.4;
    phis.add(state.phi);
    const sel = $('bands-phi');
    sel.replaceChildren(...[...phis].sort((a, b) => a - b).map((p) => new Option(`φ = ${p}`, p, false, p === state.phi)));
    sel.addEventListener('change', () => { state.phi = Number(sel.value); state.sig = ''; setParams({ phi: state.phi }); poll(); });
    render();
    poll();
  })();
  return () => { alive = false; clearTimeout(timer); tooltip.hidden = true; };
}
