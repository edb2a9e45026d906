// Phase map: log10 S against log10 R at one phi, one marker per run coloured by its class
// (Fig. 2 of the paper), live while sweeps run. Canvas for the markers (10,000 stay fast), SVG
// for axes and overlays. Hover: a tooltip with the run's numbers; click: the run's page.
import { api } from '../api.js';
import { CLASSES, STATES, category, drawMarker, label, look, swatch } from '../classes.js';
import { Plot, logExtent, svgEl, richText } from '../plot.js';
import { bucklingR, strutAspectRatio } from '../physics.js';
import { sci, sciText, fixed, escapeHtml } from '../format.js';
import { sweepPhis } from '../sweepmath.js';
import { setParams } from '../router.js';

const POLL_MS = 2000;
// Draw order: pending below finished, labelled on top.
const ORDER = { cancelled: 0, queued: 1, failed: 2, running: 3, unclassified: 4, unstable: 5 };

function pageHtml() {
  return `
    <div class="page-head">
      <h1>Phase map</h1>
      <p class="sub">Pattern of compaction of every run in the plane of the Mach number
        <i>S</i> = <i>V</i>/√(<i>E</i>/ρ) and the relative strength <i>R</i> = <i>q</i><sub>y</sub>/<i>E</i>,
        at one solid fraction φ.</p>
    </div>
    <div class="layout-map">
      <section class="card figure">
        <div class="figure-plot" id="map-plot"></div>
        <div class="figure-foot"><span id="map-summary" class="summary"></span><span id="map-live" class="live"></span></div>
      </section>
      <aside class="card controls">
        <label class="field">Solid fraction φ
          <select id="map-phi" aria-label="solid fraction phi"></select></label>
        <label class="field">Numerics
          <select id="map-cpu" aria-label="numerics preset"><option value="all">all resolutions</option></select></label>
        <label class="field">Sweep
          <select id="map-sweep" aria-label="sweep"><option value="">all sweeps</option></select></label>
        <label class="check"><input type="checkbox" id="map-buckling"><span>buckling onset <i>R</i><sub>crit</sub> = π²<i>a</i>²/12</span></label>
        <h2 class="legend-title">Legend</h2>
        <ul class="legend" id="map-legend"></ul>
        <p class="hint">Hover a marker for its numbers, click it to open the run.</p>
      </aside>
    </div>`;
}

// Markers of the visible points in a stable draw order (categories by ORDER, classes last; finer
// resolution over coarser); returns the drawn points, their canvas positions and the counts.
function drawPoints(plot, pts) {
  const r = markerRadius(pts.length);
  const drawn = pts.map((p) => ({ p, cat: category(p) }));
  drawn.sort((a, b) => (ORDER[a.cat] ?? 9) - (ORDER[b.cat] ?? 9) || a.p.cells_per_unit - b.p.cells_per_unit);
  const positions = new Float32Array(drawn.length * 2); // [x, y] per drawn point (canvas pixels)
  const counts = {};
  for (let i = 0; i < drawn.length; i++) {
    const { p, cat } = drawn[i];
    const x = plot.cx(p.S), y = plot.cy(p.R);
    positions[2 * i] = x; positions[2 * i + 1] = y;
    counts[cat] = (counts[cat] || 0) + 1;
    const progress = p.progress_eps !== null && p.eps_end > 0 ? p.progress_eps / p.eps_end : 0;
    drawMarker(plot.ctx, cat, x, y, r, progress);
  }
  return { drawn, positions, counts, radius: r };
}

function markerRadius(n) {
  return n > 3000 ? 2.6 : n > 600 ? 3.6 : n > 150 ? 5 : 7;
}

// The buckling onset R_crit at phi as a dashed line with its label, when it is inside the plot.
function drawBuckling(plot, phi) {
  const Rc = bucklingR(phi);
  if (!(Rc > plot.y.d0 && Rc < plot.y.d1)) return;
  const y = plot.y.map(Rc);
  svgEl('line', { x1: plot.m.l, x2: plot.m.l + plot.pw, y1: y, y2: y, class: 'overlay-line' }, plot.front);
  const t = svgEl('text', { x: plot.m.l + plot.pw - 8, y: y - 7, 'text-anchor': 'end', class: 'overlay-label' }, plot.front);
  richText(t, `buckling onset R_{crit} = π²a²/12 ≈ ${sciText(Rc, 2)}   (strut aspect ratio a = ${strutAspectRatio(phi).toFixed(3)})`);
}

// One legend line per class, then per state, each with its count.
function renderLegend(legend, counts) {
  legend.replaceChildren();
  const item = (cat, text, note) => {
    const li = document.createElement('li');
    li.dataset.cat = cat;
    li.dataset.count = String(counts[cat] || 0);
    if (!counts[cat]) li.classList.add('zero');
    li.append(swatch(cat));
    const name = document.createElement('span');
    name.className = 'legend-name';
    name.innerHTML = text;
    if (note) name.title = note;
    const n = document.createElement('span');
    n.className = 'legend-count';
    n.textContent = counts[cat] || 0;
    li.append(name, n);
    legend.append(li);
  };
  for (const [k, c] of Object.entries(CLASSES)) item(k, `<b>${k}</b> ${c.name}`);
  const sep = document.createElement('li');
  sep.className = 'legend-sep';
  legend.append(sep);
  for (const [k, s] of Object.entries(STATES)) item(k, s.name, s.note);
}

function summaryHtml(counts, total, phi) {
  const labelled = Object.keys(CLASSES).reduce((a, k) => a + (counts[k] || 0), 0);
  const pending = (counts.queued || 0) + (counts.running || 0);
  return `<b>${total.toLocaleString()}</b> runs at φ = ${phi} · ${labelled} labelled · ${pending} pending`;
}

function tooltipHtml(p, cat, numerics) {
  const rows = [
    ['S', sci(p.S)], ['R', sci(p.R)], ['φ', p.phi],
    ['class', CLASSES[cat] ? `<span class="dot" style="background:${CLASSES[cat].color}"></span>${escapeHtml(label(cat))}` : escapeHtml(look(cat).name)],
    ['confidence', p.confidence === null ? '—' : fixed(p.confidence, 2)],
    ['runner-up', p.runner_up ? escapeHtml(label(p.runner_up)) : '—'],
    ['<i>N</i><sub>r</sub>', p.n_reflections ?? '—'],
    ['<i>c</i><sub>b</sub>/<i>V</i>', p.band_speed_ratio === null ? '—' : fixed(p.band_speed_ratio, 3)],
    ['state', escapeHtml(p.state) + (p.state === 'running' && p.progress_eps !== null ? `, ε = ${fixed(p.progress_eps, 3)} of ${fixed(p.eps_end, 2)}` : '')],
    ['numerics', numerics],
  ];
  return `<div class="tt-head">run ${p.job_id}</div><table>${rows.map(([k, v]) => `<tr><th>${k}</th><td>${v}</td></tr>`).join('')}</table>`;
}

// Shows the tooltip beside the mouse, on the other side when it would leave the window.
function placeTooltip(tooltip, ev) {
  tooltip.hidden = false;
  const w = tooltip.offsetWidth, h = tooltip.offsetHeight;
  let x = ev.clientX + 16, y = ev.clientY + 14;
  if (x + w > window.innerWidth - 8) x = ev.clientX - w - 16;
  if (y + h > window.innerHeight - 8) y = ev.clientY - h - 14;
  tooltip.style.left = `${x + window.scrollX}px`;
  tooltip.style.top = `${y + window.scrollY}px`;
}

// For the browser tests and the render benchmark (bench/dashboard).
function publishRender(root, phi, ms, { drawn, positions, counts, radius }) {
  const hook = (window.__dashboard ||= { renders: [] });
  hook.renders.push(ms);
  hook.renderedAt = performance.now();
  hook.phaseMap = {
    phi, count: drawn.length, counts, renderMs: ms, radius,
    points: drawn.map(({ p, cat }, i) => ({ job_id: p.job_id, cat, color: look(cat).color, x: positions[2 * i], y: positions[2 * i + 1] })),
  };
  root.dispatchEvent(new CustomEvent('phasemap:rendered', { bubbles: true, detail: { ms, count: drawn.length } }));
}

export function mount(root, params) {
  const state = {
    phi: params.phi ? Number(params.phi) : null,
    cpu: params.cpu || 'all',
    sweep: params.sweep || '',
    buckling: params.buckling !== '0',
    points: [], signature: '', presets: [], sweeps: [], updated: null, error: null,
  };
  root.innerHTML = pageHtml();
  const $ = (id) => root.querySelector(`#${id}`);
  const plotBox = $('map-plot');
  const phiSel = $('map-phi'), cpuSel = $('map-cpu'), sweepSel = $('map-sweep'), buck = $('map-buckling');
  buck.checked = state.buckling;
  const tooltip = document.getElementById('tooltip');
  let positions = null; // Float32Array [x, y] per drawn point (canvas pixels)
  let drawn = [];
  let plot = null;
  let timer = null;
  let alive = true;

  function syncUrl() {
    setParams({ phi: state.phi, cpu: state.cpu === 'all' ? '' : state.cpu, sweep: state.sweep, buckling: state.buckling ? '' : '0' });
  }

  function fillPhiOptions() {
    const phis = new Set();
    for (const s of state.sweeps) for (const p of sweepPhis(s.request)) phis.add(Number(p.toPrecision(12)));
    if (state.phi === null) {
      const newest = state.sweeps[0] && sweepPhis(state.sweeps[0].request)[0];
      state.phi = Number.isFinite(newest) ? newest : 0.4;
    }
    phis.add(state.phi);
    const sorted = [...phis].sort((a, b) => a - b);
    phiSel.replaceChildren(...sorted.map((p) => new Option(`φ = ${p}`, p, false, p === state.phi)));
  }

  function fillSweepOptions() {
    const keep = state.sweep;
    sweepSel.replaceChildren(new Option('all sweeps', ''), ...state.sweeps.map((s) => new Option(`#${s.id} ${s.name}`, s.id)));
    sweepSel.value = keep;
  }

  // A grid as its cells per unit cell and across a strut, with the preset's name when a preset
  // gives it: the fewest cells per unit cell that reach the preset's cells across the strut, so
  // the grid's own count is at most one strut's share of a cell above the preset's.
  function presetName(cpu) {
    const pt = state.points.find((x) => x.cells_per_unit === cpu);
    const cps = pt ? pt.cells_per_strut : null;
    const share = cps ? cps / cpu : 0;
    const p = cps ? state.presets.find((x) => cps >= x.cells_per_strut - 1e-9 && cps - share < x.cells_per_strut - 1e-9) : null;
    const what = cps ? `${cpu} cells/unit, ${cps.toFixed(1)} across a strut` : `${cpu} cells/unit`;
    return p ? `${p.name} (${what})` : what;
  }

  function fillCpuOptions() {
    const cpus = [...new Set(state.points.map((p) => p.cells_per_unit))].sort((a, b) => a - b);
    const keep = state.cpu;
    cpuSel.replaceChildren(new Option('all resolutions', 'all'), ...cpus.map((c) => new Option(presetName(c), String(c))));
    if (keep !== 'all' && !cpus.includes(Number(keep))) cpuSel.append(new Option(presetName(Number(keep)), keep));
    cpuSel.value = keep;
  }

  function visiblePoints() {
    const pts = state.cpu === 'all' ? state.points : state.points.filter((p) => String(p.cells_per_unit) === String(state.cpu));
    return pts;
  }

  function render() {
    const t0 = performance.now();
    const pts = visiblePoints();
    const width = Math.max(560, Math.min(1100, plotBox.clientWidth || 760));
    const height = Math.round(Math.min(width * 0.68, Math.max(480, window.innerHeight - 250)));
    const xDom = logExtent(pts.map((p) => p.S), [1e-4, 1]);
    const yDom = logExtent(pts.map((p) => p.R), [1e-6, 1]);
    plotBox.replaceChildren();
    plot = new Plot(plotBox, {
      width, height, canvas: true, title: `phase map at phi = ${state.phi}`,
      margin: { l: 78, r: 24, t: 18, b: 60 },
      x: { kind: 'log', domain: xDom, label: 'Mach number S = V / √(E/ρ)' },
      y: { kind: 'log', domain: yDom, label: 'relative strength R = q_{y} / E' },
    });
    const marks = drawPoints(plot, pts);
    ({ drawn, positions } = marks);
    if (state.buckling) drawBuckling(plot, state.phi);
    if (!pts.length) {
      const t = svgEl('text', { x: plot.m.l + plot.pw / 2, y: plot.m.t + plot.ph / 2, 'text-anchor': 'middle', class: 'empty-note' }, plot.front);
      t.textContent = state.error ? `could not load: ${state.error}` : `No runs at φ = ${state.phi} yet: start a sweep on the Sweeps page.`;
    }
    plot.canvas.dataset.count = String(drawn.length);
    plot.canvas.dataset.counts = JSON.stringify(marks.counts);
    plot.canvas.addEventListener('mousemove', onMove);
    plot.canvas.addEventListener('mouseleave', () => { tooltip.hidden = true; plot.canvas.style.cursor = ''; });
    plot.canvas.addEventListener('click', onClick);
    renderLegend($('map-legend'), marks.counts);
    $('map-summary').innerHTML = summaryHtml(marks.counts, pts.length, state.phi);
    publishRender(root, state.phi, performance.now() - t0, marks);
  }

  function nearest(ev) {
    if (!positions) return -1;
    const rect = plot.canvas.getBoundingClientRect();
    const mx = ev.clientX - rect.left, my = ev.clientY - rect.top;
    let best = -1, bd = 14 * 14;
    for (let i = drawn.length - 1; i >= 0; i--) { // topmost first
      const dx = positions[2 * i] - mx, dy = positions[2 * i + 1] - my;
      const d = dx * dx + dy * dy;
      if (d < bd) { bd = d; best = i; }
    }
    return best;
  }

  function onMove(ev) {
    const i = nearest(ev);
    if (i < 0) { tooltip.hidden = true; plot.canvas.style.cursor = ''; return; }
    plot.canvas.style.cursor = 'pointer';
    const { p, cat } = drawn[i];
    tooltip.innerHTML = tooltipHtml(p, cat, presetName(p.cells_per_unit));
    placeTooltip(tooltip, ev);
  }

  function onClick(ev) {
    const i = nearest(ev);
    if (i >= 0) location.hash = `#/run/${drawn[i].p.job_id}`;
  }

  function showLive() {
    $('map-live').innerHTML = `<span class="pulse"></span>live · updated ${state.updated.toLocaleTimeString()}`;
    $('map-live').className = 'live';
  }

  function showOffline() {
    $('map-live').textContent = `offline: ${state.error}; retrying`;
    $('map-live').className = 'live off';
  }

  // Reads /phase-map while the tab is visible and redraws only when the answer changed.
  async function poll() {
    if (!alive) return;
    clearTimeout(timer);
    if (!document.hidden) {
      try {
        const data = await api.phaseMap(state.phi, state.sweep);
        if (!alive) return;
        const sig = JSON.stringify(data.points);
        state.error = null;
        state.updated = new Date();
        if (sig !== state.signature) {
          state.signature = sig;
          state.points = data.points;
          fillCpuOptions();
          render();
        }
        showLive();
      } catch (e) {
        state.error = e.message;
        showOffline();
      }
    }
    if (alive) timer = setTimeout(poll, POLL_MS);
  }

  phiSel.addEventListener('change', () => { state.phi = Number(phiSel.value); state.signature = ''; syncUrl(); poll(); });
  cpuSel.addEventListener('change', () => { state.cpu = cpuSel.value; syncUrl(); render(); });
  sweepSel.addEventListener('change', () => { state.sweep = sweepSel.value; state.signature = ''; syncUrl(); poll(); });
  buck.addEventListener('change', () => { state.buckling = buck.checked; syncUrl(); render(); });
  const onResize = () => { clearTimeout(onResize.t); onResize.t = setTimeout(() => alive && render(), 150); };
  window.addEventListener('resize', onResize);

  (async () => {
    const [sw, pr] = await Promise.allSettled([api.sweeps(1000), api.presets()]);
    if (!alive) return;
    state.sweeps = sw.status === 'fulfilled' ? sw.value.sweeps : [];
    state.presets = pr.status === 'fulfilled' ? pr.value.presets : [];
    fillPhiOptions();
    fillSweepOptions();
    fillCpuOptions();
    render();
    poll();
  })();

  return () => { alive = false; clearTimeout(timer); clearTimeout(onResize.t); window.removeEventListener('resize', onResize); tooltip.hidden = true; };
}
