// Compare (#/compare?ids=12,15,40): two to MAX_COMPARE runs side by side. Their space-time maps
// drawn as on a run page (js/spacetime.js) on one colour scale with one colour bar, their plate
// stresses on one plot (js/stressplot.js) one curve a run, and their features in one table, the
// glossary's groups down and the runs across, with the parameters, numerics and class on top and
// the rows whose values differ marked. Each run links to its page and can be removed (the
// address changes, so Back brings it again). Reached from the Runs page's "Compare selected"
// and a run page's "compare these runs" (its replicates).
import { api } from '../api.js';
import { CLASSES, category, inkOn, label, look } from '../classes.js';
import { colormap, colorBar, svgEl } from '../plot.js';
import { RATE_LABEL } from '../particles.js';
import { effectiveLabel, featureHtml, groupFeatures, hasBand, loadGlossary } from '../glossary.js';
import { drawSpacetime, loadFrames, loadSpacetime, spacetimeLevels } from '../spacetime.js';
import { logShows, plateStresses, stressAxisText, stressPlot, toggleTabs } from '../stressplot.js';
import { MAX_COMPARE, compareHash, parseIds } from '../compareset.js';
import { escapeHtml, fixed, sci } from '../format.js';
import { parseHash } from '../router.js';
import { stressRatio } from '../physics.js';

// One colour a run, in the order of the address (Paul Tol's "bright" scheme, colour-blind safe):
// the curve, the swatch in the list and the column's head. A class keeps its own colours
// (js/classes.js) in the badges.
const RUN_COLORS = ['#4477AA', '#EE6677', '#228833', '#CCBB44', '#66CCEE', '#AA3377'];
const MAP_HEIGHT = 300; // px of each space-time map; its plot area is 232 px high
const MAP_MIN_WIDTH = 300, MAP_MAX_WIDTH = 560;
const BAR_WIDTH = 96; // px of the one colour bar's figure

function pageHtml() {
  return `
    <div class="page-head">
      <a class="back" href="#/runs">← runs</a>
      <h1>Compare runs</h1>
      <p class="sub" id="cmp-sub">loading…</p>
      <div class="cmp-notes" id="cmp-notes"></div>
    </div>
    <div class="cmp-body" id="cmp-body" hidden>
      <section class="card"><h2>Runs</h2><ul class="cmp-runs" id="cmp-runs"></ul></section>
      <section class="card" id="cmp-st-card"><h2>Space-time maps of the plastic strain rate</h2>
        <div class="cmp-st"><div class="cmp-maps" id="cmp-maps"></div><div class="cmp-bar" id="cmp-bar"></div></div>
        <div id="cmp-no-maps"></div><p class="caption" id="cmp-scale"></p></section>
      <section class="card" id="cmp-stress-card"><h2>Plate stress</h2><div class="fig" id="cmp-stress"></div></section>
      <section class="card" id="cmp-features-card"><h2>Parameters and features</h2>
        <label class="cmp-diff-only"><input type="checkbox" id="cmp-diff-only"> only the rows that differ</label>
        <div class="cmp-scroll" id="cmp-features"></div></section>
    </div>`;
}

function createPage(root, params) {
  root.innerHTML = pageHtml();
  const $ = (x) => root.querySelector(`#${x}`);
  const { ids, bad } = parseIds(params.ids);
  return {
    root,
    asked: ids.slice(0, MAX_COMPARE), // the ids compared, in the address's order
    left: ids.slice(MAX_COMPARE), // past MAX_COMPARE: not compared
    bad,
    runs: [], // [{id, job, color, names, frames, npy, absent}] of the runs found
    missing: [], // ids without a run
    failed: [], // [{id, message}]: the runs that could not be read
    glossary: null,
    plate: 'top', // the plate whose stress is plotted: 'top' or 'bottom'
    stressScale: 'log',
    alive: true,
    el: {
      sub: $('cmp-sub'), notes: $('cmp-notes'), body: $('cmp-body'), runs: $('cmp-runs'), maps: $('cmp-maps'), noMaps: $('cmp-no-maps'), bar: $('cmp-bar'),
      scale: $('cmp-scale'), stress: $('cmp-stress'), features: $('cmp-features'), diffOnly: $('cmp-diff-only'),
    },
  };
}

// The address without run id (the page is mounted again from it): every other id of the
// address in its order, those past MAX_COMPARE too (the first of them is then compared).
function without(page, id) {
  return compareHash([...page.asked, ...page.left].filter((x) => x !== id));
}

// A job of the API with what the page reads of it; the run's files when it has any.
async function loadRun(page, id, color) {
  let job;
  try {
    job = await api.job(id);
  } catch (e) {
    if (e.status === 404) page.missing.push(id);
    else page.failed.push({ id, message: e.message });
    return null;
  }
  let list = [];
  if (job.result) {
    try { list = (await api.artifacts(id)).artifacts; } catch { list = []; }
  }
  const names = new Set(list.map((a) => a.name));
  const [frames, npy] = await Promise.all([loadFrames(id, names), loadSpacetime(id, names)]);
  // An imported run whose export carried no files (artifacts=none): its results and features
  // only (docs/dashboard.md, "Imported runs").
  const absent = Boolean(job.result?.origin) && !list.length;
  return { id, job, color, names, frames, npy, absent };
}

async function start(page) {
  const { el } = page;
  document.title = `compare runs ${page.asked.join(', ')} · compaction-sweep`;
  const loaded = await Promise.all([loadGlossary(), ...page.asked.map((id, i) => loadRun(page, id, RUN_COLORS[i]))]);
  if (!page.alive) return;
  page.glossary = loaded[0];
  page.runs = loaded.slice(1).filter(Boolean);
  renderNotes(page);
  if (page.runs.length < 2) {
    el.sub.innerHTML = tooFewHtml(page);
    return;
  }
  el.sub.innerHTML = `${page.runs.length} runs side by side: their space-time maps on one colour scale, their plate stresses on one plot, their features in one table. At most ${MAX_COMPARE} runs; <a href="#/runs">the Runs page</a> picks them.`;
  el.body.hidden = false;
  renderRuns(page);
  renderMaps(page);
  renderStress(page);
  renderFeatures(page);
  el.diffOnly.addEventListener('change', () => el.features.classList.toggle('diff-only', el.diffOnly.checked));
}

// What is wrong with the address: entries that are no run ids, runs past the limit, ids
// without a run, runs that could not be read; each a line, with a link to leave it out.
function renderNotes(page) {
  const notes = [];
  if (page.bad.length) notes.push(`<span>${page.bad.map((b) => `“${escapeHtml(b)}”`).join(', ')} ${page.bad.length === 1 ? 'is not a run id' : 'are not run ids'}: left out.</span>`);
  if (page.left.length) notes.push(`<span>At most ${MAX_COMPARE} runs are compared: run${page.left.length === 1 ? '' : 's'} ${page.left.join(', ')} left out.</span>`);
  for (const id of page.missing) notes.push(`<span data-missing="${id}">There is no run ${id}. <a href="${without(page, id)}">Leave it out</a></span>`);
  for (const f of page.failed) notes.push(`<span data-failed="${f.id}">Run ${f.id} could not be loaded: ${escapeHtml(f.message)}. <a href="${without(page, f.id)}">Leave it out</a></span>`);
  page.el.notes.innerHTML = notes.map((n) => `<p class="error cmp-note">${n}</p>`).join('');
}

function tooFewHtml(page) {
  const one = page.runs[0];
  const have = page.runs.length === 1 ? ` Only <a href="#/run/${one.id}">run ${one.id}</a> is here.` : '';
  return `<span class="cmp-too-few">Comparing needs two runs or more (at most ${MAX_COMPARE}), as <code>#/compare?ids=12,15</code>.${have} Pick them with the checkboxes of <a href="#/runs">the Runs page</a>, or open a run with replicates and follow “compare these runs”.</span>`;
}

// A run's class (a person's label first) as a badge in its colour, else its state.
function badgeHtml(job) {
  const cat = category({ ...job, class: job.result?.class ?? null, status: job.result?.status ?? null, human_label: job.human_label?.label ?? null });
  const lk = look(cat);
  return CLASSES[cat]
    ? `<span class="badge cls" style="--c:${lk.color};color:${inkOn(lk.color)}" title="${job.human_label ? "a person's label" : "the classifier's label"}">${escapeHtml(label(cat))}</span>`
    : `<span class="badge state-${cat}">${escapeHtml(lk.name)}</span>`;
}

// A run's parameters and numerics in one line.
function paramsText(job) {
  return `<i>S</i> = ${sci(job.S)}, <i>R</i> = ${sci(job.R)}, φ = ${job.phi} · ${job.cells_per_unit} cells/unit (${fixed(job.cells_per_strut, 1)} across a strut)`;
}

const swatch = (color) => `<span class="cmp-swatch" style="background:${color}" aria-hidden="true"></span>`;

function filesNote(r) {
  if (r.absent) return 'imported without its files, which are not on this server';
  if (!r.job.result) return `no result yet (${escapeHtml(r.job.state)})`;
  return '';
}

// The list of runs: colour, link, class, parameters, and "remove".
function renderRuns(page) {
  page.el.runs.innerHTML = page.runs.map((r) => {
    const note = filesNote(r);
    return `<li data-run="${r.id}">${swatch(r.color)}<a href="#/run/${r.id}" class="cmp-run-link">run ${r.id}</a> ${badgeHtml(r.job)}
      <span class="cmp-params">${paramsText(r.job)}</span>${note ? ` <span class="muted cmp-files">${note}</span>` : ''}
      <a class="cmp-remove" href="${without(page, r.id)}" title="remove run ${r.id} from the comparison">remove</a></li>`;
  }).join('');
}

// The maps' colour scale: the lowest value of any map and the highest of their clipping tops
// (each map's own 99.5th percentile, as a run page clips it), so that one colour is one rate on
// every map and no map is clipped more than on its own page.
function commonScale(runs) {
  let lo = Infinity, hi = -Infinity;
  for (const r of runs) {
    const l = spacetimeLevels(r.npy);
    lo = Math.min(lo, l.lo);
    hi = Math.max(hi, l.hi);
  }
  return { lo, hi };
}

// The width of each map: as many in a row as fit at MAP_MIN_WIDTH beside the colour bar (under
// them on a phone), rows as even as can be.
function mapWidth(container, n) {
  const row = container.parentElement;
  const beside = getComputedStyle(row).flexDirection === 'row';
  const cw = Math.max(MAP_MIN_WIDTH, (row.clientWidth || 900) - (beside ? BAR_WIDTH + 8 : 0));
  const gap = 16;
  const most = Math.max(1, Math.min(n, Math.floor((cw + gap) / (MAP_MIN_WIDTH + gap))));
  const cols = Math.ceil(n / Math.ceil(n / most));
  return Math.max(MAP_MIN_WIDTH, Math.min(MAP_MAX_WIDTH, Math.floor((cw - (cols - 1) * gap) / cols)));
}

function renderMaps(page) {
  const { el, runs } = page;
  const drawn = runs.filter((r) => r.npy);
  const scale = drawn.length ? commonScale(drawn) : null;
  // A figure for each run with a map (or its picture); a line under them for each run without.
  const figured = runs.filter((r) => r.npy || r.names.has('spacetime.png'));
  el.maps.innerHTML = figured.map((r) => `<figure class="cmp-map" data-run="${r.id}"><figcaption>${swatch(r.color)}<a href="#/run/${r.id}">run ${r.id}</a> ${badgeHtml(r.job)}</figcaption><div class="cmp-map-fig"></div></figure>`).join('');
  el.noMaps.innerHTML = runs.filter((r) => !figured.includes(r)).map((r) => `<p class="muted cmp-no-map" data-run="${r.id}">${swatch(r.color)}<a href="#/run/${r.id}">run ${r.id}</a>: no space-time map: ${filesNote(r) || 'none in its result'}.</p>`).join('');
  const width = mapWidth(el.maps, figured.length);
  for (const r of figured) {
    const box = el.maps.querySelector(`.cmp-map[data-run="${r.id}"] .cmp-map-fig`);
    box.style.width = `${width}px`;
    if (r.npy) {
      try {
        drawSpacetime(box, r.npy, r.job.result?.summary || {}, r.frames, r.id, {
          scale, colorBar: false, caption: false, width, height: MAP_HEIGHT, canvasId: `cmp-st-${r.id}`, plateId: null, title: `space-time map of run ${r.id}`,
        });
        continue;
      } catch (e) { console.error(`spacetime.npy of run ${r.id}`, e); }
    }
    box.innerHTML = `<img class="artifact-img" alt="space-time map of run ${r.id}" src="${api.artifactUrl(r.id, 'spacetime.png')}"><p class="muted small">its picture, on its own colour scale (no readable spacetime.npy)</p>`;
  }
  if (!scale) {
    el.bar.hidden = true;
    el.scale.textContent = 'None of these runs has a space-time map on this server.';
    return;
  }
  el.bar.hidden = false;
  el.bar.replaceChildren();
  const svg = svgEl('svg', { width: BAR_WIDTH, height: MAP_HEIGHT, id: 'cmp-colorbar', class: 'plot-svg', role: 'img', 'data-lo': String(scale.lo), 'data-hi': String(scale.hi) }, el.bar);
  svgEl('title', {}, svg).textContent = 'the colour scale of every map';
  colorBar(svg, { x: 8, y: 12, w: 14, h: MAP_HEIGHT - 12 - 56, lut: colormap('inferno'), lo: scale.lo, hi: scale.hi, label: RATE_LABEL });
  const noMap = runs.filter((r) => !r.npy).map((r) => r.id);
  el.scale.innerHTML = `One colour scale for the ${drawn.length} maps: log<sub>10</sub>(1 + |ε̇<sub>P</sub>| h<sub>0</sub>/V) from <b id="cmp-scale-lo">${sci(scale.lo, 4)}</b> to <b id="cmp-scale-hi">${sci(scale.hi, 4)}</b>, the lowest value of any map and the highest of their tops (each map clipped at its own 99.5th percentile, as on its run page), so one colour is one rate on every map. Above the top plate (the dashed line) there is no material.${noMap.length ? ` Run${noMap.length === 1 ? '' : 's'} ${noMap.join(', ')}: no map.` : ''}`;
}

// One curve a run: the stress of the chosen plate over q_y against imposed strain.
function renderStress(page) {
  const box = page.el.stress;
  const withFrames = page.runs.map((r) => ({ r, p: plateStresses(r.frames) })).filter((x) => x.p && x.p[page.plate].length);
  box.replaceChildren();
  const controls = document.createElement('div');
  controls.className = 'cmp-controls';
  const values = withFrames.flatMap((x) => x.p[page.plate]);
  const log = page.stressScale === 'log' && logShows(values);
  controls.append(
    toggleTabs('plate', [['top', 'top plate (moving)'], ['bottom', 'bottom plate (fixed)']], page.plate, (k) => { page.plate = k; renderStress(page); }, 'cmp-plate'),
    toggleTabs('stress axis', [['log', 'log axis'], ['linear', 'linear axis']], log ? 'log' : 'linear', (k) => { page.stressScale = k; renderStress(page); }, 'stress-scale'),
  );
  box.append(controls);
  if (!withFrames.length) {
    box.insertAdjacentHTML('beforeend', '<p class="muted">None of these runs has plate stresses (frames.csv) on this server.</p>');
    return;
  }
  const width = Math.max(300, Math.min(820, box.clientWidth || 720));
  stressPlot(box, withFrames.map(({ r, p }) => ({
    eps: p.eps, values: p[page.plate], attrs: { class: 'series cmp-series', style: `stroke:${r.color}`, 'data-series': String(r.id) },
  })), { log, width, svgId: 'cmp-stress-svg' });
  const lg = document.createElement('ul');
  lg.className = 'cmp-legend';
  lg.id = 'cmp-stress-legend';
  lg.innerHTML = page.runs.map((r) => {
    const has = withFrames.some((x) => x.r === r);
    return `<li data-run="${r.id}"${has ? '' : ' class="muted"'}><svg width="24" height="10" aria-hidden="true"><line x1="0" x2="24" y1="5" y2="5" class="series" style="stroke:${has ? r.color : 'transparent'}"></line></svg><a href="#/run/${r.id}">run ${r.id}</a> ${badgeHtml(r.job)} <span class="cmp-params">${paramsText(r.job)}</span>${has ? '' : ` <span class="muted">(${filesNote(r) || 'no frames.csv'})</span>`}</li>`;
  }).join('');
  box.append(lg);
  const qys = [...new Set(withFrames.map(({ r }) => r.job.result?.summary?.params?.q_y ?? r.job.scene?.q_y).filter((q) => q !== undefined && q !== null))];
  const cap = document.createElement('p');
  cap.className = 'caption';
  cap.innerHTML = `Compressive stress on the ${page.plate === 'top' ? 'top (moving)' : 'bottom (fixed)'} plate, averaged over each frame, ${stressAxisText(qys.length === 1 ? qys[0] : undefined, log)}${qys.length > 1 ? ' (each run\'s own q<sub>y</sub>)' : ''}.`;
  box.append(cap);
}

// The rows on top: the parameters, the numerics and the class, each [name, key, (job) => [html, same-key]].
const PARAM_ROWS = [
  ['<i>S</i>', 'S', (j) => sci(j.S, 4)],
  ['<i>R</i>', 'R', (j) => sci(j.R, 4)],
  ['φ', 'phi', (j) => String(j.phi)],
  ['<i>R</i>/<i>S</i>²', 'R_over_S2', (j) => sci(stressRatio(j.S, j.R), 3)],
  ['cells per unit cell', 'cells_per_unit', (j) => String(j.cells_per_unit)],
  ['cells across a strut', 'cells_per_strut', (j) => fixed(j.cells_per_strut, 2)],
  ['preset', 'preset', (j) => escapeHtml(j.scene?.preset ?? j.preset ?? '—')],
  ['final strain ε<sub>end</sub>', 'eps_end', (j) => String(j.eps_end)],
  ['structure · seed', 'structure', (j) => escapeHtml([j.scene?.structure ?? 'regular', j.scene?.seed ?? null].filter((x) => x !== null).join(' · '))],
  ['class', 'class', (j) => badgeHtml(j)],
  ["classifier's class · confidence", 'classifier', (j) => (j.result?.class ? `${escapeHtml(j.result.class)} · ${fixed(j.result.confidence, 2)}` : '—')],
  ['state', 'state', (j) => escapeHtml(j.state)],
];

// A row of the table: its head, and a cell a run; marked "differs" when the cells' texts differ.
function rowHtml(head, attrs, cells) {
  const texts = cells.filter((c) => !c.blank).map((c) => c.html);
  const differs = new Set(texts).size > 1;
  return `<tr ${attrs}${differs ? ' class="differs"' : ''}><th scope="row">${head}</th>${cells.map((c) => `<td data-run="${c.id}"${c.value !== undefined ? ` data-value="${escapeHtml(JSON.stringify(c.value))}"` : ''}>${c.html}</td>`).join('')}</tr>`;
}

// The table: the runs across; the parameters on top, then the features in the glossary's groups
// (js/glossary.js) over every feature any of the runs has. A band's speeds read "no band" for a
// run without one, as on its page.
function renderFeatures(page) {
  const { runs, glossary } = page;
  const head = `<thead><tr><th scope="col">run</th>${runs.map((r) => `<th scope="col" data-run="${r.id}">${swatch(r.color)}<a href="#/run/${r.id}">run ${r.id}</a></th>`).join('')}</tr></thead>`;
  // (a row no run has a value of, as preset for runs made before jobs named it, is left out)
  const params = `<tbody class="cmp-params-rows">${PARAM_ROWS.map(([name, key, f]) => [name, key, runs.map((r) => ({ id: r.id, html: f(r.job) }))])
    .filter(([, , cells]) => cells.some((c) => c.html !== '—'))
    .map(([name, key, cells]) => rowHtml(name, `data-param="${key}"`, cells)).join('')}</tbody>`;
  const all = {};
  for (const r of runs) Object.assign(all, Object.fromEntries(Object.keys(r.job.result?.features || {}).map((k) => [k, null])));
  const groups = groupFeatures(glossary, all).map(({ group, rows }) => {
    const body = rows.map(({ key, entry }) => {
      const cells = runs.map((r) => {
        const f = r.job.result?.features;
        if (!f) return { id: r.id, html: '<span class="muted">no result</span>', blank: true };
        if (!(key in f)) return { id: r.id, html: '<span class="muted">—</span>', blank: true };
        const band = hasBand(glossary, effectiveLabel(r.job), r.job.result.band_speed_ratio);
        if (entry?.band && !band) return { id: r.id, value: f[key], html: '<span class="muted" title="no band in this run: its front speeds are no band speeds">no band</span>', blank: true };
        const error = entry?.error ? f[entry.error] : undefined;
        const unit = entry?.unit ? ` <span class="unit">${escapeHtml(entry.unit)}</span>` : '';
        return { id: r.id, value: f[key], html: `${featureHtml(f[key])}${typeof error === 'number' ? ` ± ${sci(error, 3)}` : ''}${unit}` };
      });
      const name = `${escapeHtml(entry?.name || key)} <code>${escapeHtml(key)}</code>`;
      return rowHtml(`<span title="${escapeHtml(entry?.text || '')}">${name}</span>`, `data-feature="${escapeHtml(key)}"`, cells);
    }).join('');
    return `<tbody data-group="${escapeHtml(group.id)}"><tr class="cmp-group"><th colspan="${runs.length + 1}" scope="rowgroup">${escapeHtml(group.title)} <span class="muted">${escapeHtml(group.text)}</span></th></tr>${body}</tbody>`;
  }).join('');
  const none = runs.every((r) => !r.job.result?.features) ? `<tbody><tr><td colspan="${runs.length + 1}" class="muted">None of these runs has features yet.</td></tr></tbody>` : '';
  page.el.features.innerHTML = `<table class="cmp-table" id="cmp-table">${head}${params}${groups}${none}</table>
    <p class="hint">A marked row differs between the runs (a run without the value is left out of that test). Hover a feature's name for its explanation (docs/classifier.md).</p>`;
}

export function mount(root, params) {
  const page = createPage(root, params || parseHash().params);
  start(page);
  return () => { page.alive = false; };
}
