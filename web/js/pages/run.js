// Run detail: what a run was asked (parameters), what happened to it (state, timings, worker,
// events), what it produced (space-time map, plate stresses, snapshot, movie), how it was
// labelled, and the other replicates of its point.
import { api, fetchArtifact } from '../api.js';
import { majorityCount, notRobustWhy, probabilitiesHtml, runStateText, spreadText } from '../points.js';
import { showRelabel } from '../relabel.js';
import { MAX_COMPARE, compareHash, picked, setPicked } from '../compareset.js';
import { CLASSES, category, inkOn, label, look } from '../classes.js';
import { colormap } from '../plot.js';
import { effectiveLabel, featureHtml, groupFeatures, hasBand, loadGlossary } from '../glossary.js';
import { parseNpy } from '../npy.js';
import { parseMovie } from '../movie.js';
import { particleFigure } from '../particles.js';
import { mountPlayer } from '../player.js';
import { drawSpacetime, loadFrames, loadSpacetime } from '../spacetime.js';
import { logShows, plateStresses, stressAxisText, stressPlot, toggleTabs } from '../stressplot.js';
import { stressRatio } from '../physics.js';
import { sci, fixed, when, duration, bytes, escapeHtml } from '../format.js';

const POLL_MS = 2000;
const UNITS = {
  S: 'Mach number V/√(E/ρ)', R: 'q_y / E', phi: 'solid fraction', rho: 'kg/m²', nu: 'Poisson ratio',
  q_y: 'N/m', h0: 'm', cells_per_strut: 'grid cells across the thinnest strut', cells_per_unit: 'grid cells per unit cell (0: from the strut)', particles_per_cell: 'per cell per direction',
  cfl: 'Courant number', eps_end: 'final imposed strain', d_eps: 'strain between frames', snapshot_eps: 'imposed strain', movie_d_eps: 'strain between movie frames (0: none)',
  perturbation: 'of the particle spacing', n_rows: 'unit cells high', n_cols: 'unit cells wide (full 2D)',
};

function pageHtml(id) {
  return `
    <div class="page-head">
      <a class="back" href="#/map">← phase map</a>
      <h1 id="run-title">Run ${id}</h1>
      <p class="sub" id="run-sub">loading…</p>
      <p class="run-compare" id="run-compare"></p>
      <div class="run-import" id="run-import" hidden></div>
      <div class="replicates" id="run-replicates" hidden></div>
    </div>
    <div class="grid-run">
      <section class="card span2" id="card-spacetime"><h2>Space-time map of the plastic strain rate</h2><div class="fig" id="st-fig"><p class="muted">waiting for the result…</p></div></section>
      <section class="card" id="card-stress"><h2>Plate stress</h2><div class="fig" id="stress-fig"><p class="muted">waiting for the result…</p></div></section>
      <section class="card" id="card-snapshot"><h2>Snapshot</h2><div id="snap-box"><p class="muted">waiting for the result…</p></div></section>
      <section class="card" id="card-movie"><h2>Movie</h2><div id="movie-box"><p class="muted">waiting for the result…</p></div></section>
      <section class="card" id="card-class"><h2>Classification</h2><div id="class-box"><p class="muted">—</p></div></section>
      <section class="card" id="card-label"><h2>Human label</h2><div id="label-box"><p class="muted">—</p></div></section>
      <section class="card" id="card-params"><h2>Parameters</h2><div id="params-box"></div></section>
      <section class="card" id="card-state"><h2>State and timings</h2><div id="state-box"></div>
        <h2 class="sub-h">Downloads</h2><div id="files-box"><p class="muted">no files yet</p></div></section>
    </div>`;
}

// The page: the run's id, its boxes (el), whether it is still shown, the next poll, the state
// whose artifacts are drawn and the stop of the movie playing. Every part below takes it.
function createPage(root, id) {
  root.innerHTML = pageHtml(id);
  const $ = (x) => root.querySelector(`#${x}`);
  return {
    id,
    el: {
      title: $('run-title'), sub: $('run-sub'), compare: $('run-compare'), imported: $('run-import'), replicates: $('run-replicates'), spacetime: $('st-fig'), stress: $('stress-fig'), snapshot: $('snap-box'), movie: $('movie-box'),
      classBox: $('class-box'), label: $('label-box'), params: $('params-box'), state: $('state-box'), files: $('files-box'),
    },
    alive: true,
    timer: null, // the next load while the run is queued or running
    shownState: null, // the job's state when its artifacts were last drawn
    stopMovie: () => {},
    glossary: null, // web/data/feature-glossary.json (glossary.js)
    provenance: undefined, // an imported run's: its imported sweep's `imported` (null: none found)
    stressScale: 'log', // the plate-stress plot's y axis: 'log' or 'linear'
    frames: null, // frames.csv, parsed (the stress plot redraws from it)
  };
}

// Reads the job and shows it; its artifacts once it has a result or has finished, and again
// when its state changes; again in a moment until it finishes.
async function load(page) {
  const { id, el } = page;
  clearTimeout(page.timer);
  if (!page.alive) return;
  let job;
  try {
    job = await api.job(id);
  } catch (e) {
    el.sub.textContent = e.status === 404 ? `There is no run ${id}.` : `Could not load run ${id}: ${e.message}`;
    if (e.status !== 404 && page.alive) page.timer = setTimeout(() => load(page), POLL_MS * 2);
    return;
  }
  if (!page.glossary) page.glossary = await loadGlossary();
  if (job.result?.origin && page.provenance === undefined) page.provenance = await importProvenance(job);
  if (!page.alive) return;
  renderHead(el, job);
  renderCompare(page);
  renderImport(el.imported, job, page.provenance);
  renderReplicates(page, job); // beside the rest: it reads the map, the page need not wait
  el.state.innerHTML = stateHtml(job);
  el.params.innerHTML = paramsHtml(job);
  el.classBox.innerHTML = classHtml(job, page.glossary);
  showRelabel(el.label, job, () => load(page));
  const finished = ['succeeded', 'failed', 'cancelled'].includes(job.state);
  if (job.state !== page.shownState && (job.result || finished)) {
    page.shownState = job.state;
    await renderArtifacts(page, job);
  }
  if (!finished && page.alive) page.timer = setTimeout(() => load(page), POLL_MS);
}

// The title with the run's class or state, the line of its parameters, and the window's title.
function renderHead(el, job) {
  const p = { ...job, class: job.result?.class ?? null, status: job.result?.status ?? null };
  const cat = category(p);
  const lk = look(cat);
  const badge = CLASSES[cat]
    ? `<span class="badge cls" style="--c:${lk.color};color:${inkOn(lk.color)}">${escapeHtml(label(cat))}</span>`
    : `<span class="badge state-${cat}">${escapeHtml(lk.name)}</span>`;
  el.title.innerHTML = `Run ${job.id} ${badge}`;
  const progress = job.state === 'running' && job.progress_eps !== null ? ` · ε = ${fixed(job.progress_eps, 3)} of ${fixed(job.eps_end, 2)}` : '';
  el.sub.innerHTML = `<i>S</i> = ${sci(job.S)} · <i>R</i> = ${sci(job.R)} · φ = ${job.phi} · <i>R</i>/<i>S</i>² = <i>q</i><sub>y</sub>/(ρ<i>V</i>²) = ${sci(stressRatio(job.S, job.R))} · ${job.cells_per_unit} cells per unit cell (${Number(job.cells_per_strut).toFixed(1)} across a strut)${progress}`;
  document.title = `run ${job.id} · compaction-sweep`;
}

// The runs picked for comparison (js/compareset.js, shared with the Runs page's checkboxes): this
// run added or removed, and the comparison of the picks once there are two.
function renderCompare(page) {
  const box = page.el.compare;
  const ids = picked();
  const here = ids.includes(page.id);
  const others = ids.filter((x) => x !== page.id);
  const full = !here && ids.length >= MAX_COMPARE;
  const button = `<button type="button" class="small" id="run-pick"${full ? ` disabled title="at most ${MAX_COMPARE} runs are compared"` : ''}>${here ? 'remove from comparison' : 'add to comparison'}</button>`;
  const link = ids.length >= 2 ? ` <a id="run-compare-link" href="${compareHash(ids)}">compare the ${ids.length} picked runs</a>`
    : others.length ? ` <span class="muted">picked: run ${others[0]}</span>` : '';
  box.innerHTML = button + link;
  box.querySelector('#run-pick').addEventListener('click', () => {
    setPicked(here ? others : [...ids, page.id]);
    renderCompare(page);
  });
}

// An imported run's provenance: the `imported` of the first of its sweeps that was imported
// (GET /sweeps/{id}: the exporting server, its sweep, when it was exported and imported), null
// when none of its sweeps says (the run is then still shown as imported, from result.origin).
async function importProvenance(job) {
  for (const id of job.sweeps || []) {
    try {
      const s = await api.sweep(id);
      if (s.imported) return { ...s.imported, local_sweep: s.id };
    } catch { /* the next one */ }
  }
  return null;
}

const shortId = (db) => `<code title="${escapeHtml(db)}">${escapeHtml(String(db).slice(0, 8))}…</code>`;

// The line under the title of an imported run: where it was computed (the database and job of
// result.origin), which server exported it and when it came here; its times are the source's.
function renderImport(box, job, prov) {
  const o = job.result?.origin;
  if (!o) { box.hidden = true; box.replaceChildren(); return; }
  box.hidden = false;
  const src = prov?.source;
  const via = src
    ? ` Source server <b id="run-source-server">${escapeHtml(src.server || 'unknown')}</b>${src.database && src.database !== o.database ? ` (database ${shortId(src.database)})` : ''}: exported from its sweep ${escapeHtml(prov.source_sweep ?? prov.sweep ?? '?')} on ${escapeHtml(when(prov.exported_at))}, imported here into <a href="#/sweeps">sweep #${prov.local_sweep}</a> on ${escapeHtml(when(o.imported_at ?? prov.imported_at))}.`
    : ` Imported here on ${escapeHtml(when(o.imported_at))}.`;
  box.innerHTML = `<b>Imported run.</b> Computed as <b id="run-source-job">job ${escapeHtml(o.job)}</b> of database ${shortId(o.database)} by worker ${escapeHtml(job.result.worker || '—')}.${via}
    Its times are the source's clock. <span id="run-import-files"></span>`;
}

// A replicate's point: how many runs it has, the point's majority, share and robustness with
// its c_b/V over the replicates (the map's summary of the point, GET /phase-map at the run's phi
// and grid), and a link to each other run (GET /jobs/{id}: replicates) with its label or state.
// Without replicates nothing shows.
async function renderReplicates(page, job) {
  const box = page.el.replicates;
  const others = job.replicates || [];
  if (!others.length) { box.hidden = true; box.replaceChildren(); return; }
  let runs = new Map(), s = null;
  try {
    const map = await api.phaseMap(job.phi, '', job.cells_per_unit, job.scene?.geometry);
    runs = new Map(map.points.map((p) => [p.job_id, p]));
    s = (map.summaries || []).find((x) => x.point_id === job.point_id) || null;
  } catch { /* the links alone */ }
  if (!page.alive) return;
  const total = s ? s.runs : others.length + 1;
  box.hidden = false;
  box.dataset.point = String(job.point_id);
  box.dataset.runs = String(total);
  const seed = job.scene?.seed, pert = job.scene?.perturbation;
  const what = [seed !== undefined ? `seed ${seed}` : '', pert ? `perturbation ${pert}` : ''].filter(Boolean).join(', ');
  const links = others.map((id) => `<li><a href="#/run/${id}" data-job="${id}">run ${id}</a>${runs.has(id) ? ` <span class="run-state">${runStateText(runs.get(id))}</span>` : ''}</li>`).join('');
  const all = [job.id, ...others];
  const cmp = `<a id="run-compare-replicates" href="${compareHash(all.slice(0, MAX_COMPARE))}">compare these runs</a>${all.length > MAX_COMPARE ? ` <span class="muted">(the first ${MAX_COMPARE})</span>` : ''}`;
  box.innerHTML = `<div class="rep-head">Replicate${what ? ` (${what})` : ''} of point ${job.point_id}: <b>${total} runs</b> · ${cmp}</div>
    ${s ? `<div class="rep-point">${pointLine(page, s)}</div>` : ''}
    <div class="rep-others"><span class="muted">the other ${others.length === 1 ? 'run' : `${others.length} runs`}:</span><ul class="siblings">${links}</ul></div>`;
}

// The point's majority and share (its classes when they split), robustness and c_b/V over its
// replicates.
function pointLine(page, s) {
  if (!s.label) return `the point: ${s.finished} of ${s.runs} finished, none labelled yet`;
  const c = CLASSES[s.label];
  const classes = s.share < 1 ? `; ${probabilitiesHtml(s.probabilities)}` : '';
  const robust = s.robust ? '<b class="robust">robust</b>' : `not robust <span class="muted">(${notRobustWhy(s)})</span>`;
  const speed = s.band_speed_ratio && hasBand(page.glossary, s.label, s.band_speed_ratio.mean) ? ` · <i>c</i><sub>b</sub>/<i>V</i> ${spreadText(s.band_speed_ratio, 3)}` : '';
  return `the point: <span class="dot" style="background:${c.color}"></span>${escapeHtml(label(s.label))} in ${majorityCount(s)} of ${s.labelled} labelled (share ${fixed(s.share, 2)}${classes}) · ${robust}${speed}`;
}

// The downloads, then the figures in turn: the space-time map (its colour scale is the others'),
// the plate stresses, the snapshot and the movie.
async function renderArtifacts(page, job) {
  const { id, el } = page;
  let list = [];
  try { list = (await api.artifacts(id)).artifacts; } catch { list = []; }
  if (!page.alive) return;
  const names = new Set(list.map((a) => a.name));
  // An imported run whose export carried no files (artifacts=none): one card says so in place
  // of the four figures, instead of reasons that are not true of the run (docs/dashboard.md,
  // "Imported runs").
  page.absent = job.result?.origin && !list.length ? 'not on this server: this run was imported without its files' : null;
  el.files.innerHTML = filesHtml(list, job, id, page.absent);
  for (const box of [el.stress, el.snapshot, el.movie]) box.closest('.card').hidden = Boolean(page.absent);
  el.spacetime.closest('.card').querySelector('h2').textContent = page.absent ? 'Figures' : 'Space-time map of the plastic strain rate';
  if (page.absent) {
    const note = el.imported.querySelector('#run-import-files');
    if (note) note.textContent = 'Its files are not on this server (the export carried its results, features and provenance only).';
    el.spacetime.innerHTML = `<p class="muted absent">No space-time map, plate stresses, snapshot or movie: the files are ${page.absent}. The numbers below are the source's.</p>`;
    return;
  }
  const summary = job.result?.summary || {};
  const frames = await loadFrames(id, names);
  if (!page.alive) return;
  const scale = { lut: colormap('inferno'), vmax: await renderSpacetime(page, names, summary, frames) };
  if (!page.alive) return;
  page.frames = frames;
  renderStress(page, summary);
  await renderSnapshot(el.snapshot, list, summary, scale, id);
  if (!page.alive) return;
  await renderMovie(page, names, summary, scale);
}

// The movie of movie.bin with the colour scale of the space-time map (its own without one).
async function renderMovie(page, names, summary, scale) {
  const { id } = page;
  const box = page.el.movie;
  page.stopMovie();
  if (!names.has('movie.bin')) {
    const every = summary.params?.movie_d_eps;
    box.innerHTML = `<p class="muted">No movie in this result${every === 0 ? ' (movie_d_eps = 0)' : every === undefined ? ' (written before movies existed)' : ''}.</p>`;
    return;
  }
  try {
    const movie = parseMovie(await fetchArtifact(id, 'movie.bin'));
    if (!page.alive) return;
    if (!movie.frames.length) { box.innerHTML = '<p class="muted">The movie has no frames: the run ended before its first.</p>'; return; }
    const vmax = scale.vmax ?? levelScale(movie);
    page.stopMovie = mountPlayer(box, movie, { vmax, lut: scale.lut, spacing: particleSpacing(summary) });
    const cap = document.createElement('p');
    cap.className = 'caption';
    cap.innerHTML = `The particles every Δε = ${movie.header.dEps} of imposed strain, coloured by plastic strain rate over the last frame as the snapshot, on the colour scale of the space-time map${movie.header.flags & 1 ? ' (pseudo-1D: eight periods side by side)' : ''}; the line is the top plate. <a href="/api/v1/jobs/${id}/artifacts/movie.bin">movie.bin</a> (schema/movie-format.md)`;
    box.append(cap);
  } catch (e) {
    console.error('movie.bin', e);
    box.innerHTML = `<p class="muted">The movie could not be read: ${escapeHtml(e.message)}</p>`;
  }
}

// The space-time map from spacetime.npy, else its picture, else a note; returns the top of its
// colour scale (null without the table).
async function renderSpacetime(page, names, summary, frames) {
  const { id } = page;
  const box = page.el.spacetime;
  const npy = await loadSpacetime(id, names);
  if (!page.alive) return null;
  if (npy) {
    try {
      return drawSpacetime(box, npy, summary, frames, id).hi;
    } catch (e) { console.error('spacetime.npy', e); }
  }
  if (names.has('spacetime.png')) {
    box.innerHTML = `<img class="artifact-img" id="st-img" alt="space-time map" src="/api/v1/jobs/${id}/artifacts/spacetime.png">`;
  } else {
    box.innerHTML = '<p class="muted">no space-time map in this result</p>';
  }
  return null;
}

function stop(page) {
  page.alive = false;
  clearTimeout(page.timer);
  page.stopMovie();
}

export function mount(root, params) {
  const page = createPage(root, params.id);
  load(page);
  return () => stop(page);
}

// The job's state, worker, attempts, timings and cost, then its events.
function stateHtml(job) {
  const r = job.result || {};
  const s = r.summary || {};
  // An imported run was created here when it was imported, after the source started it: its
  // start and finish are the source's clock, and its wait in the source's queue is not known.
  const imported = Boolean(r.origin);
  const span = (a, b) => (a && b && b >= a ? (b - a) / 1000 : null);
  const src = imported ? ' <span class="unit">source\'s clock</span>' : '';
  const rows = [
    ['state', `<span class="state-text state-${job.state}">${job.state}</span>${r.status ? ` (result ${escapeHtml(r.status)}${r.reason ? `: ${escapeHtml(r.reason)}` : ''})` : ''}`],
    ['worker', `${escapeHtml(r.worker || job.worker || '—')}${imported ? ' <span class="unit">the source\'s</span>' : ''}`],
    ['attempts', `${job.attempts} of ${job.max_attempts}`],
    ...(imported ? [] : [['created', when(job.created_at)]]),
    ['started', when(job.started_at) + src],
    ['finished', when(job.finished_at) + src],
    ...(imported ? [['imported here', when(r.origin.imported_at ?? job.created_at)]] : [['waited in queue', duration(span(job.created_at, job.started_at))]]),
    ['run time (lease to result)', duration(span(job.started_at, job.finished_at)) + src],
    ['simulation wall time', duration(r.wall_seconds ?? s.wall_seconds)],
    ['steps · particles', s.steps ? `${s.steps.toLocaleString()} · ${s.n_particles?.toLocaleString()}` : '—'],
    ['cost', s.ns_per_particle_step ? `${fixed(s.ns_per_particle_step, 0)} ns per particle-step` : '—'],
    ['strain reached', r.eps_reached ?? s.eps_reached ?? (job.progress_eps !== null ? `${fixed(job.progress_eps, 3)} (running)` : '—')],
    ['engine', `${escapeHtml(job.engine_version)}${r.source_revision ? ` · ${escapeHtml(r.source_revision)}` : ''}`],
    ['sweeps', (job.sweeps || []).map((x) => `#${x}`).join(', ') || '—'],
  ];
  if (job.last_error) rows.push(['last error', `<code class="err">${escapeHtml(job.last_error)}</code>`]);
  let html = table(rows);
  if (job.events?.length) {
    html += `<details class="events"><summary>${job.events.length} events</summary><ol>${job.events.map((e) =>
      `<li><time>${when(e.at)}</time> <b>${escapeHtml(e.kind)}</b> attempt ${e.attempt}${e.worker ? ` · ${escapeHtml(e.worker)}` : ''}${e.message ? `<br><code>${escapeHtml(e.message)}</code>` : ''}</li>`).join('')}</ol></details>`;
  }
  return html;
}

// The scene parameters with their units, then the derived quantities of the result, in two columns.
function paramsHtml(job) {
  const scene = job.scene || {};
  const rows = Object.entries(scene).filter(([k]) => k !== 'threads').map(([k, v]) => {
    const val = typeof v === 'number' ? sci(v, 4) : escapeHtml(Array.isArray(v) ? v.join(', ') : String(v));
    return [`<code>${k}</code>`, `${val}${UNITS[k] ? ` <span class="unit">${escapeHtml(UNITS[k])}</span>` : ''}`];
  });
  const d = job.result?.summary?.derived;
  if (d) {
    rows.push(['<i>E</i>', `${sci(d.E)} <span class="unit">N/m</span>`], ['<i>V</i>', `${sci(d.V)} <span class="unit">m/s</span>`],
      ['bar wave speed', `${sci(d.bar_wave_speed)} <span class="unit">m/s</span>`]);
  }
  if (job.result?.summary?.phi_discrete) rows.push(['φ of the particles', fixed(job.result.summary.phi_discrete, 3)]);
  const half = Math.ceil(rows.length / 2);
  return `<div class="cols2">${table(rows.slice(0, half))}${table(rows.slice(half))}</div>`;
}

// The label with its confidence and runner-up, N_r, c_b/V (only for a run with a band), then
// every feature the result carries in the glossary's groups, each with its one-line explanation.
function classHtml(job, glossary) {
  const r = job.result;
  if (!r) return '<p class="muted">no result yet</p>';
  if (!r.class) {
    return `<p class="muted">${r.status === 'unstable' ? 'Numerically unstable run: not classified.' : 'Done, unclassified: the classifier gave no label for this run (or has not run on it).'}</p>`
      + (r.features ? featuresHtml(r.features, glossary, false, null, job.id) : '');
  }
  const c = CLASSES[r.class];
  const conf = r.confidence ?? null;
  let html = `<div class="class-main"><span class="class-letter" style="background:${c?.color || '#888'};color:${inkOn(c?.color || '#888888')}">${escapeHtml(r.class)}</span>
    <div><div class="class-name">${escapeHtml(c?.name || r.class)}</div>
    <div class="conf"><span class="conf-bar"><span style="width:${conf === null ? 0 : Math.round(conf * 100)}%;background:${c?.color || '#888'}"></span></span> confidence ${conf === null ? '—' : fixed(conf, 2)}</div>
    <div class="muted">runner-up: ${r.runner_up ? escapeHtml(label(r.runner_up)) : '—'}</div></div></div>`;
  const lbl = effectiveLabel(job);
  const band = hasBand(glossary, lbl, r.band_speed_ratio);
  const error = r.features?.band_speed_error;
  const speed = band
    ? `<span id="band-speed">${fixed(r.band_speed_ratio, 3)}${typeof error === 'number' ? ` ± ${fixed(error, 3)}` : ''}</span>`
    : `<span class="muted" id="band-speed">no band ${lbl ? `(${escapeHtml(label(lbl))}${job.human_label ? ', a person\'s label' : ''})` : ''}</span>`;
  html += table([['<i>N</i><sub>r</sub> (reflections)', r.n_reflections ?? '—'], ['<i>c</i><sub>b</sub>/<i>V</i> (band speed)', speed]]);
  return html + (r.features ? featuresHtml(r.features, glossary, band, lbl, job.id) : '');
}

// The features by the glossary's groups: a heading and its line per group, a row per feature
// with its name, value (± its error) and explanation. Without a band the band's speeds are left
// out and the group says why.
function featuresHtml(features, glossary, band, lbl, jobId) {
  const groups = groupFeatures(glossary, features);
  const body = groups.map(({ group, rows }) => {
    const shown = rows.filter((x) => band || !x.entry?.band);
    const hidden = rows.length - shown.length;
    const note = hidden ? `<p class="muted feature-note" id="no-band-note" title="${escapeHtml(glossary.band_classes.text)}">No band in this run${lbl ? ` (${escapeHtml(label(lbl))})` : ''}: its ${hidden} front-speed reading${hidden === 1 ? ' is not a band speed' : 's are not band speeds'}, not shown (they are in the <a href="/api/v1/jobs/${escapeHtml(jobId)}">job JSON</a>).</p>` : '';
    const items = shown.map(({ key, entry, value, error }) => {
      const unit = entry?.unit ? ` <span class="unit">${escapeHtml(entry.unit)}</span>` : '';
      const err = typeof error === 'number' ? ` ± ${sci(error, 3)}` : '';
      return `<li data-feature="${escapeHtml(key)}"><div class="feature-head"><span class="feature-name">${escapeHtml(entry?.name || key)} <code>${escapeHtml(key)}</code></span><span class="feature-value">${featureHtml(value)}${err}${unit}</span></div>${entry ? `<div class="feature-text">${escapeHtml(entry.text)}</div>` : ''}</li>`;
    }).join('');
    return `<section class="feature-group" data-group="${escapeHtml(group.id)}"><h3>${escapeHtml(group.title)} <span class="muted">${escapeHtml(group.text)}</span></h3>${note}${items ? `<ul class="features">${items}</ul>` : ''}</section>`;
  }).join('');
  return `<details class="features-box" open><summary>Features <span class="muted">(what the classifier read of the run; docs/classifier.md)</span></summary>${body}</details>`;
}

// A download link per artifact, the job's JSON and its sweep's export.
function filesHtml(list, job, id, absent) {
  return list.length
    ? `<ul class="files">${list.map((a) => `<li><a href="${a.url}" download="run${id}_${escapeHtml(a.name)}">${escapeHtml(a.name)}</a><span class="muted">${bytes(a.size)}</span></li>`).join('')}</ul>
       <p class="hint">Also: <a href="/api/v1/jobs/${id}">job JSON</a>${job.sweeps?.length ? ` · sweep export <a href="${api.exportUrl(job.sweeps[0], 'csv')}">CSV</a>` : ''}</p>`
    : absent ? `<p class="muted absent">The files are ${absent}. Its <a href="/api/v1/jobs/${id}">job JSON</a> has the results and features.</p>`
      : '<p class="muted">This run has no files' + (job.state === 'failed' ? ' (it failed; see the events).' : '.') + '</p>';
}

// The stress of the top and bottom plates over q_y against imposed strain, from frames.csv
// (js/stressplot.js), on a log axis by default; two buttons switch the axis.
function renderStress(page, summary) {
  const box = page.el.stress;
  const p = plateStresses(page.frames);
  if (!p) {
    box.innerHTML = '<p class="muted">no frames.csv in this result</p>';
    return;
  }
  const log = page.stressScale === 'log' && logShows(p.top.concat(p.bottom));
  box.replaceChildren();
  box.append(toggleTabs('stress axis', [['log', 'log axis'], ['linear', 'linear axis']], log ? 'log' : 'linear',
    (k) => { page.stressScale = k; renderStress(page, summary); }, 'stress-scale'));
  const width = Math.max(300, Math.min(620, box.clientWidth || 520));
  // The bottom plate dashed over the top one: where the two stresses agree both stay visible.
  stressPlot(box, [
    { eps: p.eps, values: p.top, attrs: { class: 'series top', 'data-series': 'top' } },
    { eps: p.eps, values: p.bottom, attrs: { class: 'series bottom', 'data-series': 'bottom' } },
  ], { log, width, svgId: 'stress-svg' });
  // The legend under the axes: inside them it hid a curve on one axis or the other.
  const lg = document.createElement('div');
  lg.className = 'stress-legend';
  lg.innerHTML = [['top', 'top plate (moving)'], ['bottom', 'bottom plate (fixed)']].map(([k, t]) =>
    `<span><svg width="24" height="10" aria-hidden="true"><line x1="0" x2="24" y1="5" y2="5" class="series ${k}"></line></svg>${t}</span>`).join('');
  box.append(lg);
  const cap = document.createElement('p');
  cap.className = 'caption';
  cap.innerHTML = `Compressive stress on the plates, averaged over each frame, ${stressAxisText(summary.params?.q_y ?? 250, log)}. <a href="/api/v1/jobs/${page.id}/artifacts/frames.csv">frames.csv</a>`;
  box.append(cap);
}

// The snapshot nearest eps = 0.2 first, a tab per snapshot; a note when there is none. Drawn
// from snapshot_<eps>.npy with axes and the space-time map's colour bar; its picture when the
// table is missing or unreadable.
async function renderSnapshot(box, list, summary, scale, id) {
  const pngs = list.filter((a) => /^snapshot_.*\.png$/.test(a.name));
  if (!pngs.length) {
    box.innerHTML = `<p class="muted">${noSnapshotWhy(summary)}</p>`;
    return;
  }
  const epsOf = (n) => Number(n.replace(/^snapshot_|\.png$/g, ''));
  pngs.sort((a, b) => Math.abs(epsOf(a.name) - 0.2) - Math.abs(epsOf(b.name) - 0.2));
  const tables = new Map(list.filter((a) => /^snapshot_.*\.npy$/.test(a.name)).map((a) => [a.name, a]));
  const pseudo1d = summary.params?.geometry === 'pseudo1d';
  const caption = (a) => `Particles coloured by plastic strain rate at ε = ${epsOf(a.name)}${pseudo1d ? ' (pseudo-1D: eight periods side by side)' : ''}, on the colour scale of the space-time map. <a href="${a.url}">picture</a>`;
  async function show(a) {
    const one = box.querySelector('#snap-one');
    const npy = tables.get(a.name.replace(/\.png$/, '.npy'));
    if (npy) {
      try {
        const t = parseNpy(await fetchArtifact(id, npy.name));
        const [n, cols] = t.shape;
        if (cols !== 5) throw new Error(`expected 5 columns, got ${cols}`);
        const vmax = scale.vmax ?? tableScale(t.data, n);
        one.replaceChildren();
        const fig = document.createElement('figure');
        one.append(fig);
        const p = summary.params || {};
        const width = (summary.derived?.unit_cell ?? (p.h0 || 1) / (p.n_rows || 34)) * (pseudo1d ? 1 : p.n_cols || 17);
        const { plot, draw } = particleFigure(fig, { width, h0: p.h0 || 1, copies: pseudo1d ? 8 : 1, spacing: particleSpacing(summary), vmax, lut: scale.lut, title: `snapshot at ε = ${epsOf(a.name)}` });
        plot.canvas.id = 'snap-canvas';
        draw(n, (i) => t.data[i * 5], (i) => t.data[i * 5 + 1], (i) => Math.log10(1 + Math.max(0, t.data[i * 5 + 2])) / vmax);
        const cap = document.createElement('figcaption');
        cap.innerHTML = caption(a);
        fig.append(cap);
        return;
      } catch (e) { console.error(npy.name, e); }
    }
    one.innerHTML = `<figure><div class="snap-wrap"><img class="artifact-img" id="snap-img" alt="snapshot at eps ${epsOf(a.name)}" src="${a.url}"></div><figcaption>${caption(a)}</figcaption></figure>`;
  }
  box.innerHTML = (pngs.length > 1 ? `<div class="tabs">${pngs.map((a, i) => `<button data-i="${i}" class="${i ? '' : 'on'}">ε = ${epsOf(a.name)}</button>`).join('')}</div>` : '') + '<div id="snap-one"></div>';
  box.querySelectorAll('.tabs button').forEach((b) => b.addEventListener('click', () => {
    box.querySelectorAll('.tabs button').forEach((x) => x.classList.toggle('on', x === b));
    show(pngs[Number(b.dataset.i)]);
  }));
  await show(pngs[0]);
}

// Why a run has no snapshot, only what is true of it: it ended before the first requested
// strain, or it asked for none; else only that there is none.
function noSnapshotWhy(summary) {
  const want = summary.params?.snapshot_eps;
  const reached = summary.eps_reached;
  if (Array.isArray(want) && !want.length) return 'No snapshot: the run asked for none.';
  if (Array.isArray(want) && typeof reached === 'number' && reached < Math.min(...want)) {
    return `No snapshot: the run ended at ε = ${fixed(reached, 3)}, before the requested ε = ${escapeHtml(want.join(', '))}.`;
  }
  return 'No snapshot in this result.';
}

// The particle spacing of a run [m]: grid spacing / particles per cell and direction.
function particleSpacing(summary) {
  const p = summary.params || {};
  const dx = summary.grid?.dx || (p.h0 || 1) / ((p.n_rows || 34) * (summary.grid?.cells_per_unit || 20));
  return dx / (p.particles_per_cell || 2);
}

// The colour scale without a space-time map: the 99.5th percentile of log10(1 + rate) of the
// particles that flowed (a snapshot's table, a movie's levels), as the map clips its own.
function percentile995(values) {
  if (!values.length) return 1;
  const sorted = Float64Array.from(values).sort();
  return Math.max(sorted[Math.floor(0.995 * (sorted.length - 1))], 1e-6);
}
function tableScale(data, n) {
  const v = [];
  for (let i = 0; i < n; i++) if (data[i * 5 + 2] > 0) v.push(Math.log10(1 + data[i * 5 + 2]));
  return percentile995(v);
}
function levelScale(movie) {
  const v = [], k = movie.header.rateLog10Max / 255;
  for (const f of movie.frames) for (let i = 0; i < f.level.length; i++) if (f.level[i]) v.push(f.level[i] * k);
  return percentile995(v);
}

function table(rows) {
  return `<table class="kv">${rows.map(([k, v]) => `<tr><th>${k}</th><td>${v}</td></tr>`).join('')}</table>`;
}
