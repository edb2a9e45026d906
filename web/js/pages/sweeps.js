// Sweeps: a form for a grid sweep over (S, R, phi) or an adaptive sweep over a box in S and R at
// one phi, with the job count shown before submitting and validation next to each field, and the
// list of sweeps with progress (against the budget of an adaptive one), cancel and export.
import { api, submitToken, setSubmitToken } from '../api.js';
import { validateSweep, validateAdaptive, formFieldOf } from '../sweepform.js';
import { when, escapeHtml, duration, bytes } from '../format.js';
import { planHash } from '../mapplan.js';

const POLL_MS = 2500;
const FIELDS = ['name', 's-min', 's-max', 's-n', 's-scale', 'r-min', 'r-max', 'r-n', 'r-scale', 'phi', 'res', 'budget', 'in-flight', 'preset', 'structure', 'seeds', 'rep-n', 'rep-pert', 'cps', 'cpu', 'eps-end', 'snapshots', 'movie', 'priority', 'attempts'];

// A field of the form: its label, its input, its hint and the line for its error.
function field(id, labelHtml, input, hint = '') {
  return `
    <div class="f" data-field="${id}">
      <label for="f-${id}">${labelHtml}</label>${input}
      ${hint ? `<div class="f-hint">${hint}</div>` : ''}
      <div class="field-error" id="err-${id}" data-for="${id}" role="alert"></div>
    </div>`;
}
const numIn = (id, value, extra = '') => `<input id="f-${id}" name="${id}" type="text" inputmode="decimal" value="${value}" autocomplete="off" ${extra}>`;
const scaleIn = (id) => `<select id="f-${id}" name="${id}"><option value="log" selected>log</option><option value="linear">linear</option></select>`;
// Text shown in one mode only (the form's data-mode picks it).
const byMode = (grid, adaptive) => `<span class="grid-only">${grid}</span><span class="adaptive-only">${adaptive}</span>`;
const modeOption = (value, label, hint, checked) => `<label class="mode-option"><input type="radio" name="mode" value="${value}" id="f-mode-${value}" ${checked ? 'checked' : ''}><span><b>${label}</b> <span class="muted">${hint}</span></span></label>`;

// The form's card: the kind of sweep, S and R, phi, numerics, refinement (adaptive), the
// advanced numerics, the token, the job count and the submit button. The form's data-mode
// ("grid" or "adaptive") shows the .grid-only or the .adaptive-only parts (css/dashboard.css);
// S and R keep their fields in both modes, their points being the initial grid's in adaptive mode.
function formHtml() {
  const points = byMode('points', 'initial points');
  return `<section class="card form-card">
        <h2>New sweep</h2>
        <form id="sweep-form" data-mode="grid" novalidate>
          <div class="mode-choice" role="radiogroup" aria-label="kind of sweep">
            ${modeOption('grid', 'grid', 'every point of S × R × φ', true)}${modeOption('adaptive', 'adaptive', 'refines a box where the classes change', false)}
          </div>
          ${field('name', 'Name', '<input id="f-name" name="name" type="text" placeholder="e.g. phi 0.4 coarse map" autocomplete="off">')}
          <fieldset><legend>Mach number <i>S</i> = <i>V</i>/√(<i>E</i>/ρ) <span class="unit">in (0, 1)</span></legend>
            <div class="row4">${field('s-min', 'min', numIn('s-min', '1e-3'))}${field('s-max', 'max', numIn('s-max', '1e-1'))}${field('s-n', points, numIn('s-n', '5'))}<div class="grid-only">${field('s-scale', 'spacing', scaleIn('s-scale'))}</div></div>
          </fieldset>
          <fieldset><legend>Relative strength <i>R</i> = <i>q</i><sub>y</sub>/<i>E</i> <span class="unit">in (0, 1)</span></legend>
            <div class="row4">${field('r-min', 'min', numIn('r-min', '1e-5'))}${field('r-max', 'max', numIn('r-max', '1e-1'))}${field('r-n', points, numIn('r-n', '5'))}<div class="grid-only">${field('r-scale', 'spacing', scaleIn('r-scale'))}</div></div>
          </fieldset>
          <div class="row2">
            ${field('phi', 'Solid fraction φ', numIn('phi', '0.4'), byMode('one value or a list: 0.3, 0.4, 0.5', 'one value'))}
            ${field('preset', 'Numerics preset', '<select id="f-preset" name="preset"><option value="fast">fast</option><option value="default" selected>default</option><option value="reference">reference</option></select>', '<span id="preset-note"></span>')}
          </div>
          <div class="row2">
            ${field('structure', 'Structure', '<select id="f-structure" name="structure"><option value="regular" selected>regular</option><option value="random">random</option></select>', 'random: void sizes and centres drawn from the seed')}
            ${field('seeds', 'Seeds', numIn('seeds', '', 'placeholder="1"'), byMode('random only; a list runs each point once per seed: 1, 2, 3', 'random only; one seed'))}
          </div>
          <fieldset class="replicates-set"><legend>Replicates <span class="unit">optional: each point run n times, seeds 1..n, the particles perturbed</span></legend>
            <div class="row2">
              ${field('rep-n', 'runs per point <i>n</i>', numIn('rep-n', '', 'placeholder="1 (none)"'), 'the map then shows how often each class came out')}
              ${field('rep-pert', 'perturbation <span class="unit">of the particle spacing</span>', numIn('rep-pert', '', 'placeholder="e.g. 0.01"'), 'needed by a regular structure')}
            </div>
          </fieldset>
          <fieldset class="adaptive-only"><legend>Refinement <span class="unit">on log S and log R</span></legend>
            <div class="row3">
              ${field('res', 'resolution <span class="unit">decades</span>', numIn('res', '', 'placeholder="server default"'), 'the finest step wanted')}
              ${field('budget', 'budget <span class="unit">runs</span>', numIn('budget', '', 'placeholder="server default"'), 'at most, the initial grid included')}
              ${field('in-flight', 'in flight', numIn('in-flight', '', 'placeholder="server default"'), 'points open at once past the initial grid')}
            </div>
          </fieldset>
          <details class="advanced"><summary>Numerics over the preset, priority</summary>
            <div class="row2">
              ${field('cps', 'cells across a strut', numIn('cps', '', 'placeholder="preset"'), 'the same resolution at every φ')}
              ${field('cpu', 'cells per unit cell', numIn('cpu', '', 'placeholder="from the strut"'), 'an explicit grid instead')}
            </div>
            <div class="row2">
              ${field('eps-end', 'final strain ε<sub>end</sub>', numIn('eps-end', '', 'placeholder="fully dense"'))}
              ${field('snapshots', 'snapshots at ε', numIn('snapshots', '', 'placeholder="0.2"'))}
            </div>
            <div class="row3">
              ${field('priority', 'priority', numIn('priority', '0'), 'higher runs first')}
              ${field('attempts', 'max attempts', numIn('attempts', '3'))}
              ${field('movie', 'movie every Δε', numIn('movie', '', 'placeholder="server default"'), '0: no movie')}
            </div>
          </details>
          <details class="advanced" id="token-box"><summary>Access</summary>
            ${field('token', 'Submit token <span class="unit">only if the server was started with one; kept in this browser</span>', `<input id="f-token" name="token" type="password" autocomplete="off" value="${escapeHtml(submitToken())}">`)}
          </details>
          <div class="submit-row">
            <div class="count-box"><div class="count" id="job-count" aria-live="polite"></div>
              <div class="cost muted small" id="job-cost" aria-live="polite"></div></div>
            <button type="submit" id="submit-sweep" class="primary">Create sweep</button>
          </div>
          <div class="form-message" id="form-message" role="status"></div>
        </form>
      </section>`;
}

// The form's card and the card of the list.
function pageHtml() {
  return `
    <div class="page-head">
      <h1>Sweeps</h1>
      <p class="sub">A sweep is a grid over the Mach number <i>S</i>, the relative strength <i>R</i> and the solid fraction φ.
        Each point becomes one job (<i>n</i> jobs with <i>n</i> replicates); a point already computed with the same numerics is reused, not run again.
        An adaptive sweep starts with a coarse grid over a box in <i>S</i> and <i>R</i> at one φ, and the server adds points where neighbouring results disagree, up to its budget.</p>
    </div>
    <div class="layout-sweeps">
      ${formHtml()}
      <section class="card list-card">
        <h2>All sweeps</h2>
        <div id="sweep-list"><p class="muted">loading…</p></div>
      </section>
    </div>`;
}

// The page: its form, the fields a person has edited (their errors show before a submit), the
// server's limits (GET /api/v1/limits, loaded once with the page), the estimate asked last, the
// next refresh of the list. Every part below takes it explicitly.
function createPage(root) {
  root.innerHTML = pageHtml();
  const $ = (x) => root.querySelector(`#${x}`);
  return {
    root, $,
    form: $('sweep-form'),
    touched: new Set(),
    submitted: false, // a submit was tried: every error shows
    limits: null,
    estimateTimer: null, estimateSeq: 0, // the estimate waiting for the edits to stop, and the last asked
    alive: true,
    timer: null, // the next refresh of the list
    archiveOpen: new Set(), // the sweeps whose "Archive" is open (the list is redrawn at each poll)
    archiveSizes: new Map(), // sweep id -> { run_page, none: bytes (null: unknown), runs: its runs then }
  };
}

function formValues($) {
  return {
    name: $('f-name').value, sMin: $('f-s-min').value, sMax: $('f-s-max').value, sN: $('f-s-n').value, sScale: $('f-s-scale').value,
    rMin: $('f-r-min').value, rMax: $('f-r-max').value, rN: $('f-r-n').value, rScale: $('f-r-scale').value,
    phi: $('f-phi').value, resolution: $('f-res').value, budget: $('f-budget').value, inFlight: $('f-in-flight').value, preset: $('f-preset').value, structure: $('f-structure').value, seeds: $('f-seeds').value, repN: $('f-rep-n').value, repPert: $('f-rep-pert').value, cps: $('f-cps').value, cpu: $('f-cpu').value, epsEnd: $('f-eps-end').value,
    snapshots: $('f-snapshots').value, movie: $('f-movie').value, priority: $('f-priority').value, attempts: $('f-attempts').value,
  };
}

// Each field's error (all of them, or only those of the fields a person edited), opening the
// advanced numerics when one of theirs has one.
function showErrors(page, errors, all) {
  const { $ } = page;
  for (const id of FIELDS.concat('token')) {
    const msg = errors[id] && (all || page.touched.has(id)) ? errors[id] : '';
    const el = $(`err-${id}`);
    if (!el) continue;
    el.textContent = msg;
    el.closest('.f').classList.toggle('invalid', !!msg);
    $(`f-${id}`)?.setAttribute('aria-invalid', msg ? 'true' : 'false');
    if (msg && ['cps', 'cpu', 'eps-end', 'snapshots', 'priority', 'attempts', 'movie'].includes(id)) el.closest('details').open = true;
  }
}

const formMode = (form) => (form.elements.mode.value === 'adaptive' ? 'adaptive' : 'grid');

// The server's estimate of a valid form's cost (POST /sweeps/estimate: the cost model and the
// workers connected), asked a moment after the last edit; a late answer to an older form is
// dropped.
function estimate(page, r) {
  clearTimeout(page.estimateTimer);
  const box = page.$('job-cost');
  const seq = ++page.estimateSeq;
  if (!r.ok) { box.textContent = ''; delete box.dataset.cpuSeconds; return; }
  page.estimateTimer = setTimeout(() => askEstimate(page, r.body, seq), 250);
}

async function askEstimate(page, body, seq) {
  const box = page.$('job-cost');
  try {
    const e = await api.estimateSweep(body);
    if (!page.alive || seq !== page.estimateSeq) return;
    box.dataset.cpuSeconds = String(e.cpu_seconds);
    box.dataset.workers = String(e.workers);
    box.innerHTML = costHtml(e);
  } catch (err) {
    if (seq !== page.estimateSeq) return;
    // A rule that spans fields (a grid too coarse for a phi) is the server's: shown at the
    // field it names.
    const { errs, rest } = fieldErrors(err.details || []);
    if (err.status === 422 && Object.keys(errs).length) {
      showErrors(page, errs, true);
      box.textContent = rest.length ? `no estimate: ${rest.join('; ')}` : '';
    } else {
      box.textContent = `no estimate: ${err.message}`;
    }
  }
}

// Checks the form against the server's limits, shows its errors, the number of jobs and the
// estimate; returns the check (its body is the request).
function update(page) {
  const { $, form } = page;
  if (!page.limits) {
    $('job-count').innerHTML = '<span class="muted">loading the server\'s limits…</span>';
    return { ok: false, errors: {}, dims: [0, 0, 0], count: 0 };
  }
  const adaptive = formMode(form) === 'adaptive';
  form.dataset.mode = formMode(form);
  const r = (adaptive ? validateAdaptive : validateSweep)(formValues($), page.limits);
  showErrors(page, r.errors, page.submitted);
  showCount($('job-count'), r, adaptive);
  estimate(page, r);
  return r;
}

// The number of jobs the form makes: its factors (seeds and replicates each run a point again)
// for a grid; the initial grid (one run a point) and the budget for an adaptive sweep, whose
// replicates come out of the budget where the map asks for them.
function showCount(cnt, r, adaptive) {
  const [a, b, c] = r.dims;
  cnt.dataset.count = String(r.count);
  cnt.dataset.replicates = String(r.replicates || 1);
  const jobs = `<b>${r.count.toLocaleString()}</b> job${r.count === 1 ? '' : 's'}`;
  const countError = r.errors.count ? `<div class="field-error">${escapeHtml(r.errors.count)}</div>` : '';
  if (r.count <= 0) cnt.innerHTML = '<span class="muted">fix the ranges to see the number of jobs</span>';
  else if (!adaptive) {
    const reps = r.replicates > 1 ? ` × ${r.replicates} replicates` : '';
    cnt.innerHTML = `${jobs} <span class="muted">= ${a} S × ${b} R × ${c} φ${r.seeds > 1 ? ` × ${r.seeds} seeds` : ''}${reps}</span>${countError}`;
  }
  else {
    const most = r.errors.budget ? '' : `, at most ${r.budget.toLocaleString()}`;
    const reps = r.replicates > 1 ? `; up to ${r.replicates} replicates a point where the map asks` : '';
    cnt.innerHTML = `${jobs} to start${most}<div class="muted small">initial grid ${a} S × ${b} R${reps}</div>${countError}`;
  }
}

// Sends a valid form as a new sweep and says what the server made of it.
async function submit(page, ev) {
  const { $ } = page;
  ev.preventDefault();
  page.submitted = true;
  setSubmitToken($('f-token').value.trim());
  const r = update(page);
  const msg = $('form-message');
  if (!page.limits) {
    msg.className = 'form-message error';
    msg.textContent = 'The server\'s limits are not loaded yet: is the server reachable?';
    return;
  }
  if (!r.ok) {
    msg.className = 'form-message error';
    msg.textContent = 'Please fix the fields marked in red.';
    page.root.querySelector('.f.invalid input, .f.invalid select')?.focus();
    return;
  }
  $('submit-sweep').disabled = true;
  msg.className = 'form-message';
  msg.textContent = 'submitting…';
  try {
    const sweep = await api.createSweep(r.body);
    const phi = sweep.phis?.[0] ?? 0.4;
    msg.className = 'form-message ok';
    const budget = sweep.request.adaptive?.budget;
    const n = sweep.request.replicates?.n;
    const reps = n > 1 ? (budget ? ` (up to ${n} replicates a point where the map asks)` : ` (${n} replicates of each point)`) : '';
    msg.innerHTML = `Sweep <b>#${sweep.id}</b> created with ${sweep.counts.total} jobs${reps} (${sweep.counts.succeeded} already computed)${budget ? `; the server adds points up to ${budget} runs as results arrive` : ''}. <a href="#/map?phi=${phi}&sweep=${sweep.id}">Watch it on the phase map →</a>`;
    page.submitted = false;
    page.touched.clear();
    refresh(page);
  } catch (e) {
    showRefusal(page, msg, e);
  } finally {
    $('submit-sweep').disabled = false;
  }
}

// Why the server did not create the sweep: the token (401, 403), its field errors at the fields,
// or its message.
function showRefusal(page, msg, e) {
  msg.className = 'form-message error';
  if (e.status === 401 || e.status === 403) {
    page.$('token-box').open = true;
    showErrors(page, { token: e.status === 401 ? 'this server needs a submit token' : 'the token was refused' }, true);
    msg.textContent = `Not allowed (${e.status}): ${e.message}`;
  } else if (e.details?.length) {
    const { errs, rest } = fieldErrors(e.details);
    showErrors(page, errs, true);
    msg.textContent = `The server refused the sweep (${e.status})${rest.length ? `: ${rest.join('; ')}` : '; see the marked fields.'}`;
  } else {
    msg.textContent = `Could not create the sweep: ${e.message}`;
  }
}

// Every edit checks the form again; a field edited shows its errors from then on.
function wireForm(page) {
  const { form } = page;
  form.addEventListener('input', (ev) => { if (ev.target.name) page.touched.add(ev.target.name); update(page); page.$('form-message').textContent = ''; });
  form.addEventListener('change', (ev) => { if (ev.target.name) page.touched.add(ev.target.name); update(page); });
  form.addEventListener('submit', (ev) => submit(page, ev));
}

// The server's limits, and its defaults as the placeholders of the fields that take them.
function loadLimits(page) {
  const { $ } = page;
  api.limits().then((l) => {
    if (!page.alive) return;
    page.limits = l;
    const movie = l.scene?.movie_d_eps;
    if (movie) $('f-movie').placeholder = String(movie.default);  // the scene's default
    // The adaptive defaults are the server's: an empty field takes them.
    $('f-res').placeholder = String(l.adaptive.resolution_decades);
    $('f-budget').placeholder = String(l.adaptive.budget);
    update(page);
  }).catch(() => {});
}

// The server's presets as the preset's options, the default chosen, with the chosen one's note.
function loadPresets(page) {
  const { $ } = page;
  api.presets().then((p) => {
    if (!page.alive) return;
    const sel = $('f-preset');
    sel.replaceChildren(...p.presets.map((x) => new Option(`${x.name} (${x.cells_per_strut} cells across a strut)`, x.name, false, x.name === p.default)));
    sel.value = p.default;
    const note = () => { $('preset-note').textContent = p.presets.find((x) => x.name === sel.value)?.description || ''; };
    sel.addEventListener('change', note);
    note();
  }).catch(() => {});
}

// Reads the list of sweeps, and again every POLL_MS.
async function refresh(page) {
  const { $ } = page;
  clearTimeout(page.timer);
  if (!page.alive) return;
  try {
    const { sweeps, total } = await api.sweeps(200);
    if (!page.alive) return;
    const list = $('sweep-list');
    if (!sweeps.length) {
      list.innerHTML = '<p class="muted">No sweeps yet. The form creates one.</p>';
    } else {
      list.innerHTML = sweepsTableHtml(page, sweeps, total);
      list.querySelectorAll('button.cancel').forEach((b) => b.addEventListener('click', () => cancel(page, Number(b.dataset.id))));
      list.querySelectorAll('details.archive').forEach((d) => d.addEventListener('toggle', () => sizeArchive(page, d)));
    }
  } catch (e) {
    $('sweep-list').innerHTML = `<p class="error">Could not load the sweeps: ${escapeHtml(e.message)}</p>`;
  }
  if (page.alive) page.timer = setTimeout(() => refresh(page), POLL_MS);
}

async function cancel(page, id) {
  const { $ } = page;
  if (!confirm(`Cancel sweep #${id}? Its queued and running jobs that no other sweep needs are cancelled.`)) return;
  try {
    const r = await api.cancelSweep(id);
    $('form-message').className = 'form-message ok';
    $('form-message').textContent = `Sweep #${id} cancelled (${r.cancelled_jobs} jobs).`;
  } catch (e) {
    $('form-message').className = 'form-message error';
    $('form-message').textContent = `Could not cancel sweep #${id}: ${e.message}${e.status === 401 || e.status === 403 ? ' (set the submit token under Access)' : ''}`;
    if (e.status === 401 || e.status === 403) $('token-box').open = true;
  }
  refresh(page);
}

function stop(page) {
  page.alive = false;
  clearTimeout(page.timer);
}

export function mount(root) {
  const page = createPage(root);
  wireForm(page);
  loadLimits(page);
  loadPresets(page);
  update(page);
  refresh(page);
  return () => stop(page);
}

// The estimate's cost and when it would be done:
// "about 3.2 CPU-hours; 2 workers connected: done in about 1.6 h (around 14:05)".
function costHtml(e) {
  const hours = (s) => `${Number((s / 3600).toPrecision(2)).toLocaleString()} CPU-hour${s === 3600 ? '' : 's'}`;
  const upTo = e.max_jobs > e.jobs ? `, at most ${hours(e.max_cpu_seconds)} for the budget` : '';
  const cost = `about <b>${hours(e.cpu_seconds)}</b>${upTo} <span title="cost model: particles × time steps × ${e.ns_per_particle_step} ns per particle-step">(cost model)</span>`;
  if (!e.workers) return `${cost}; no worker connected (none seen in the last ${e.workers_seen_within_seconds} s)`;
  const at = new Date(Date.now() + e.finish_seconds * 1000).toLocaleTimeString(undefined, { hour: '2-digit', minute: '2-digit' });
  return `${cost}; ${e.workers} worker${e.workers === 1 ? '' : 's'} connected: done in about <b>${duration(e.finish_seconds)}</b> (around ${at}), if nothing else is queued`;
}

// The server's field errors (its details) at the form's fields, the first one per field; the
// rest (fields the form does not have, or a second error) as text.
function fieldErrors(details) {
  const errs = {};
  const rest = [];
  for (const d of details) {
    const id = formFieldOf(d.field);
    if (id && !errs[id]) errs[id] = d.message; else rest.push(`${d.field}: ${d.message}`);
  }
  return { errs, rest };
}

// A stacked bar of the sweep's jobs: succeeded, failed, cancelled, running.
function bar(c) {
  const t = c.total || 1;
  const seg = (k) => (c[k] ? `<span class="seg ${k}" style="width:${(100 * c[k]) / t}%" title="${c[k]} ${k}"></span>` : '');
  return `<div class="progress" role="progressbar" aria-valuemin="0" aria-valuemax="${c.total}" aria-valuenow="${c.succeeded + c.failed + c.cancelled}">${seg('succeeded')}${seg('failed')}${seg('cancelled')}${seg('running')}</div>`;
}

// The list of sweeps: name, grid, progress with counts, exports and Cancel for active sweeps.
function sweepsTableHtml(page, sweeps, total) {
  return `<table class="sweeps"><thead><tr><th>sweep</th><th>grid</th><th class="wide">progress</th><th></th></tr></thead><tbody>${sweeps.map((s) => sweepRowHtml(page, s)).join('')}</tbody></table>${total > sweeps.length ? `<p class="muted">showing the newest ${sweeps.length} of ${total}</p>` : ''}`;
}

function sweepRowHtml(page, s) {
  const c = s.counts;
  const phi = s.phis?.[0] ?? 0.4;
  const rq = s.request;
  const ad = rq.adaptive;
  const grid = ad ? `adaptive from ${ad.initial.S} S × ${ad.initial.R} R<div class="muted">step ${ad.resolution_decades} decades</div>`
    : rq.points ? `${rq.points.length} points` : `${axisText(rq.S)} S × ${axisText(rq.R)} R × ${(s.phis || []).length} φ`;
  // An adaptive sweep's total grows as the server adds points, up to its budget.
  const of = ad ? `<span class="budget" data-budget="${ad.budget}">${c.total} of at most ${ad.budget} runs</span>` : `of ${c.total}`;
  const reps = rq.replicates ? `<div class="muted">× ${rq.replicates.n} replicates${rq.replicates.perturbation !== undefined ? `, perturbation ${rq.replicates.perturbation}` : ''}</div>` : '';
  return `<tr data-sweep="${s.id}" class="sw-${s.state}">
    <td><a href="#/map?phi=${phi}&sweep=${s.id}" class="sw-name">#${s.id} ${escapeHtml(s.name)}</a>${importedHtml(s.imported)}<div class="muted small">${s.imported ? 'imported ' : ''}${when(s.created_at)} · priority ${s.priority} · ${escapeHtml(rq.numerics?.preset || 'default')}${rq.numerics?.structure === 'random' ? ` · random structure, ${rq.numerics.seeds ? `${rq.numerics.seeds.length} seeds` : `seed ${rq.numerics.seed ?? 1}`}` : ''}</div></td>
    <td class="small">${grid}<div class="muted">φ = ${(s.phis || []).join(', ')}</div>${reps}</td>
    <td>${bar(c)}<div class="small"><span class="state-text state-${s.state}">${s.state}</span> · ${c.succeeded} done${c.running ? ` · ${c.running} running` : ''}${c.queued ? ` · ${c.queued} queued` : ''}${c.failed ? ` · <b class="bad">${c.failed} failed</b>` : ''}${c.cancelled ? ` · ${c.cancelled} cancelled` : ''}${ad ? ' · ' : ' '}${of}</div></td>
    <td class="actions">${ad ? `<a href="${planHash(s.id)}" class="plan-link" title="the adaptive planner's state, budgets and next runs">plan</a> ` : ''}<a href="${api.exportUrl(s.id, 'csv')}" download>CSV</a> <a href="${api.exportUrl(s.id, 'json')}" download>JSON</a>
      ${archiveHtml(page, s)}
      ${s.state === 'active' ? `<button class="cancel" data-id="${s.id}">Cancel</button>` : ''}</td></tr>`;
}

// The sweep's archive, the file another server imports (docs/service.md, "Merging maps"), in its
// two forms with their sizes stated before download: asked by HEAD (the server builds the file
// for it) when "Archive" is opened, kept while it stays open (the list is redrawn at each poll),
// asked again when it is opened again.
function archiveHtml(page, s) {
  const sizes = page.archiveSizes.get(s.id) || {};
  const form = (artifacts, what, title) => `<li><a href="${api.archiveUrl(s.id, artifacts)}" download title="${title}">${what}</a>
    <span class="muted" data-size="${artifacts}">${sizeText(sizes[artifacts])}</span></li>`;
  const older = sizes.runs !== undefined && sizes.runs !== s.counts.succeeded
    ? `<li class="muted small" data-sized-at="${sizes.runs}">sized at ${sizes.runs} runs; open again to size it now</li>` : '';
  return `<details class="archive" data-id="${s.id}" data-runs="${s.counts.succeeded}"${page.archiveOpen.has(s.id) ? ' open' : ''}>
    <summary>Archive</summary><ul class="archive-forms">
    ${form('run_page', 'with the runs\' files', 'each run with its files but the particle snapshots: an imported run shows the same plots')}
    ${form('none', 'results only', 'the results and their provenance, without files: a map to commit or mail')}${older}</ul></details>`;
}

function sizeText(n) {
  if (n === undefined) return 'sizing…';
  return n === null ? 'size unknown' : bytes(n);
}

async function sizeArchive(page, details) {
  const id = Number(details.dataset.id);
  if (!details.open) {
    page.archiveOpen.delete(id);
    page.archiveSizes.delete(id);
    return;
  }
  page.archiveOpen.add(id);
  if (page.archiveSizes.has(id)) return; // sized, or being sized, since it was opened
  const sizes = { runs: Number(details.dataset.runs) };
  page.archiveSizes.set(id, sizes);
  for (const artifacts of ['none', 'run_page']) {
    if (!page.alive || page.archiveSizes.get(id) !== sizes) return; // left, or closed meanwhile
    try {
      sizes[artifacts] = await api.downloadSize(api.archiveUrl(id, artifacts));
    } catch {
      sizes[artifacts] = null;
    }
    // The list may have been redrawn meanwhile: write into the row shown now.
    const el = page.$('sweep-list')?.querySelector(`details.archive[data-id="${id}"] [data-size="${artifacts}"]`);
    if (el) el.textContent = sizeText(sizes[artifacts]);
  }
}

// An imported sweep's mark: the server it came from and its sweep there (the sweep's
// `imported`: docs/service.md, "Merging maps"); its runs' pages say more.
function importedHtml(imp) {
  if (!imp) return '';
  const from = imp.source?.server ? ` from ${escapeHtml(imp.source.server)}` : '';
  const there = imp.source_sweep ?? imp.sweep;
  return ` <span class="badge imported" title="imported ${escapeHtml(when(imp.imported_at))}; computed by database ${escapeHtml(imp.database)}">imported${from}${there !== undefined && there !== null ? `, its sweep ${escapeHtml(there)}` : ''}</span>`;
}

function axisText(a) {
  if (typeof a === 'number') return '1';
  if (Array.isArray(a)) return String(a.length);
  return a ? String(a.n) : '?';
}
