// An adaptive sweep's plan (#/plan?sweep=ID[&limit=N]): what GET /api/v1/sweeps/{id}/plan says
// (docs/adaptive.md) shown as a page: the state in words, the runs and CPU-hours spent against
// the budgets, per level of numerics its points, robust points, runs and CPU-hours and what the
// planner would queue next there, the resolution the plan reports (the finest step of the map,
// the grid of each level, resolved or not), and the runs the planner ranks now with their weight
// and why, each linked to the map around its point. Polled with If-None-Match (js/api.js: an
// unchanged plan is a 304 and is not drawn again) every POLL_MS while the sweep runs, every
// IDLE_POLL_MS once it has finished (a person's label can make it plan again), never once
// cancelled; unmounting stops it.
//
// Every number drawn from the plan carries data-k, its path in the plan's JSON
// ("runs.done", "levels.0.cpu_hours.pending", "candidates.3.value"): the page's test compares
// each with the API's answer.
import { api } from '../api.js';
import { escapeHtml, sci } from '../format.js';
import { PLAN_STATES, planStateName } from '../mapplan.js';
import { viewParams } from '../mapview.js';
import { setParams } from '../router.js';

const POLL_MS = 2500; // while runs are queued, running or being planned
const IDLE_POLL_MS = 15000; // once finished
const LIMITS = [10, 20, 50, 100, 1000]; // candidates listed (the API's limit, 0 to 1000)
const DEFAULT_LIMIT = 20; // the API's default
const VIEW_STEPS = 4; // a candidate's map link shows this many finest steps on each side of it

// Why the planner ranks a run (docs/adaptive.md, "Levels and replicates"), and how its value
// (its weight) is made.
const WHY = {
  map: 'the coarsest level\'s map: a point of the initial grid, or the split of a cell whose corners disagree (weight 1 for two labels, 0.5 for a label beside a failed or unclassified run, 0.5 × (1 − confidence/0.25) for one label of low confidence; times the cell\'s longer side in decades; initial points first)',
  replicate: 'another seed of a point on a boundary at its level, or of a point whose replicates disagree: a boundary seen by one run may be a perturbation\'s accident (weight 1 × the finest step)',
  level: 'the next finer level at a point still on a boundary after its replicates, or whose replicates disagree (weight 1 × the finest step)',
  follow: 'a corner of a cell whose labels disagree between levels, or the split of a cell whose corners disagree at a finer level: the finer level\'s boundary followed to where it is (weight 1 × the finest step)',
  unsure: 'another seed of a point whose confidence is below 0.25, off any boundary (weight 0.5 × (1 − confidence/0.25) × the finest step)',
};

const int = (v) => (v === null || v === undefined ? '—' : String(v));
// A number of the plan in the page: data-k names its place in the JSON, the text its value (sci:
// three significant digits, a power of ten outside 0.01 to 10^4).
const num = (k, v, f = sci) => `<span class="pn-num" data-k="${k}">${f(v)}</span>`;
const plural = (n, one, many = `${one}s`) => (n === 1 ? one : many);

function pageHtml(id) {
  return `
    <div class="page-head">
      <h1>Plan of sweep #${escapeHtml(id)} <span class="pn-name" id="pn-name"></span></h1>
      <p class="sub">What the adaptive planner makes of the sweep now: how far its budgets are spent, what each level of numerics holds,
        how fine the map is, and the runs it would queue next, best first (<code>GET /api/v1/sweeps/${escapeHtml(id)}/plan</code>; the rule: docs/adaptive.md).</p>
      <p class="pn-links small" id="pn-links"><a href="#/sweeps">all sweeps</a></p>
    </div>
    <div id="pn-problem" class="pn-problem" hidden></div>
    <div id="pn-body" class="pn-body"><p class="muted">loading…</p></div>
    <p class="hint" id="pn-live" aria-live="polite"></p>`;
}

// The page: the sweep (its record: name, phi, request), the plan shown last, the limit of
// candidates asked, its boxes and the next poll.
function createPage(root, params) {
  const id = String(params.sweep ?? '').trim();
  root.innerHTML = pageHtml(id || '?');
  const $ = (x) => root.querySelector(`#${x}`);
  const limit = Number(params.limit);
  return {
    root, id,
    limit: LIMITS.includes(limit) ? limit : DEFAULT_LIMIT,
    sweep: null, plan: null,
    el: { name: $('pn-name'), links: $('pn-links'), problem: $('pn-problem'), body: $('pn-body'), live: $('pn-live') },
    alive: true, timer: null,
  };
}

// A stacked bar of parts [{ n, cls, title }] of a whole.
function barHtml(parts, whole, label) {
  const seg = (p) => (p.n > 0 && whole > 0 ? `<span class="seg ${p.cls}" style="width:${Math.min(100, (100 * p.n) / whole)}%" title="${escapeHtml(p.title)}"></span>` : '');
  const used = parts.reduce((a, p) => a + p.n, 0);
  return `<div class="progress pn-bar" role="progressbar" aria-label="${escapeHtml(label)}" aria-valuemin="0" aria-valuemax="${whole}" aria-valuenow="${used}">${parts.map(seg).join('')}</div>`;
}

// Runs and CPU-hours against the budgets. The CPU bar's parts are the levels' done and pending
// CPU-hours, whose sum is the plan's spent.
function budgetHtml(plan) {
  const r = plan.runs;
  const c = plan.cpu_hours;
  const runs = `<div class="pn-budget" data-budget="runs">
      <div class="pn-budget-head"><b>Runs</b> <span>${num('runs.done', r.done, int)} done + ${num('runs.pending', r.pending, int)} pending of a budget of ${num('runs.budget', r.budget, int)} · ${num('runs.budget_left', r.budget_left, int)} left</span></div>
      ${barHtml([{ n: r.done, cls: 'succeeded', title: `${r.done} done` }, { n: r.pending, cls: 'running', title: `${r.pending} pending` }], r.budget, 'runs against the budget')}</div>`;
  const sum = (k) => plan.levels.reduce((a, l) => a + l.cpu_hours[k], 0);
  const cpu = c.budget === null
    ? `<div class="pn-budget" data-budget="cpu"><div class="pn-budget-head"><b>CPU-hours</b> <span>${num('cpu_hours.spent', c.spent)} done and pending; no CPU-hour budget (the runs' budget alone bounds the sweep)</span></div></div>`
    : `<div class="pn-budget" data-budget="cpu">
      <div class="pn-budget-head"><b>CPU-hours</b> <span>${num('cpu_hours.spent', c.spent)} done and pending of a budget of ${num('cpu_hours.budget', c.budget)} · ${num('cpu_hours.budget_left', c.budget_left)} left</span></div>
      ${barHtml([{ n: sum('done'), cls: 'succeeded', title: 'done' }, { n: sum('pending'), cls: 'running', title: 'pending' }], c.budget, 'CPU-hours against the budget')}</div>`;
  return `<section class="card pn-card"><h2>Budget</h2>${runs}${cpu}
    <p class="hint">CPU-hours are the cost model's (server/plan/cost_model.hpp), not measured: a run's particles × time steps × the time of a particle-step. The planner never queues a run that would take the sweep past either budget.</p></section>`;
}

function stateHtml(plan) {
  const s = PLAN_STATES[plan.state];
  return `<section class="card pn-card pn-state-card"><h2>State</h2>
    <p class="pn-state"><b class="plan-state" data-k="state" data-state="${escapeHtml(plan.state)}">${escapeHtml(planStateName(plan.state))}</b>
      <span class="muted">· boundaries <span data-k="resolved">${plan.resolved ? 'resolved' : 'not resolved'}</span></span></p>
    <p class="pn-state-text">${escapeHtml(s ? s.text : 'a state this page does not know')}</p></section>`;
}

// A level's numerics as the sweep's request gives them (its levels, else the sweep's numerics),
// but the grid, which the plan gives (cells_per_unit).
function levelNumerics(sweep, i) {
  const rq = sweep?.request;
  const n = rq?.adaptive?.levels?.[i] ?? (i === 0 ? rq?.numerics : null);
  if (!n) return '';
  return Object.entries(n).filter(([k]) => k !== 'cells_per_unit').map(([k, v]) => `${k} ${typeof v === 'object' ? JSON.stringify(v) : v}`).join(', ');
}

function levelsHtml(plan, sweep) {
  const rows = plan.levels.map((l, i) => `<tr data-level="${i}">
      <th scope="row">${i}<div class="muted small">${escapeHtml(levelNumerics(sweep, i))}</div></th>
      <td>${num(`levels.${i}.cells_per_unit`, l.cells_per_unit, int)}</td>
      <td>${num(`levels.${i}.points`, l.points, int)}</td><td>${num(`levels.${i}.robust`, l.robust, int)}</td>
      <td>${num(`levels.${i}.runs.done`, l.runs.done, int)}</td><td>${num(`levels.${i}.runs.pending`, l.runs.pending, int)}</td>
      <td>${num(`levels.${i}.cpu_hours.done`, l.cpu_hours.done)}</td><td>${num(`levels.${i}.cpu_hours.pending`, l.cpu_hours.pending)}</td>
      <td>${num(`levels.${i}.next.runs`, l.next.runs, int)}</td><td>${num(`levels.${i}.next.cpu_hours`, l.next.cpu_hours)}</td></tr>`).join('');
  return `<section class="card pn-card"><h2>Levels of numerics</h2>
    <div class="pn-scroll"><table class="pn-table pn-levels">
      <thead><tr><th rowspan="2">level</th><th rowspan="2">grid <span class="muted">cells per unit cell</span></th><th rowspan="2">points</th><th rowspan="2">robust</th>
        <th colspan="2">runs</th><th colspan="2">CPU-hours</th><th colspan="2">next</th></tr>
        <tr><th>done</th><th>pending</th><th>done</th><th>pending</th><th>runs</th><th>CPU-hours</th></tr></thead>
      <tbody>${rows}</tbody></table></div>
    <p class="hint">Level 0 is the coarsest. <b>points</b>: the points with a finished run at the level; <b>robust</b>: those of at least two replicates
      that all finished with the same label (docs/replicates.md); <b>next</b>: what the planner would queue at the level now, within the room the sweep's
      in-flight limit leaves (up to ${num('replicates', plan.replicates, int)} ${plural(plan.replicates, 'run')} of a point at one level).</p></section>`;
}

// The resolution the plan reports: the finest step for the whole map (the lattice), the grid of
// each level, whether every boundary is resolved, and per S column how finely its boundaries
// along R are bracketed (columns).
function resolutionHtml(plan) {
  const L = plan.lattice;
  const used = plan.runs.done + plan.runs.pending;
  const share = L.runs > 0 ? `${Math.round((100 * used) / L.runs)} %` : '—';
  const grids = plan.levels.map((l, i) => `level ${i}: ${num(`levels.${i}.cells_per_unit`, l.cells_per_unit, int)} cells per unit cell`).join(', ');
  return `<section class="card pn-card"><h2>Resolution</h2>
    <dl class="pn-dl">
      <dt>finest step</dt><dd>${num('lattice.step_S_decades', L.step_S_decades)} decade of <i>S</i> × ${num('lattice.step_R_decades', L.step_R_decades)} decade of <i>R</i></dd>
      <dt>boundaries</dt><dd>${plan.resolved ? '<b>resolved</b>: each lies between two runs at most one finest step apart' : '<b>not resolved</b> yet: some boundary lies in a cell larger than the finest step, or a replicate or finer level is still asked for'}</dd>
      <dt>full lattice</dt><dd>${num('lattice.S', L.S, int)} <i>S</i> × ${num('lattice.R', L.R, int)} <i>R</i> = ${num('lattice.points', L.points, int)} points, ${num('lattice.runs', L.runs, int)} runs with every replicate:
        what the same map would cost without planning, at one level. This sweep holds <span data-derived="share">${share}</span> of it.</dd>
      <dt>numerics</dt><dd>${grids}</dd>
    </dl>
    ${columnsHtml(plan)}</section>`;
}

// Per S of the lattice: its points, its boundaries along R and the widest gap that brackets one
// (against the finest R step), and the finest level run there.
function columnsHtml(plan) {
  const cols = plan.columns || [];
  if (!cols.length) return '<p class="muted" id="pn-columns-none">No <i>S</i> column has a finished point yet.</p>';
  const unresolved = cols.filter((c) => !c.resolved).length;
  const rows = cols.map((c, i) => `<tr data-column="${i}" class="${c.resolved ? '' : 'pn-open'}">
      <td>${num(`columns.${i}.S`, c.S)}</td><td>${num(`columns.${i}.points`, c.points, int)}</td><td>${num(`columns.${i}.boundaries`, c.boundaries, int)}</td>
      <td>${c.bracket_decades === null ? '<span class="muted">—</span>' : num(`columns.${i}.bracket_decades`, c.bracket_decades)}</td>
      <td data-k="columns.${i}.resolved">${c.resolved ? 'resolved' : '<b>not resolved</b>'}</td><td>${num(`columns.${i}.finest_level`, c.finest_level, int)}</td></tr>`).join('');
  return `<h3 class="pn-sub">Per <i>S</i> column <span class="muted small" id="pn-columns-count">${cols.length} ${plural(cols.length, 'column')}, ${unresolved ? `${unresolved} not resolved` : 'all resolved'}</span></h3>
    <div class="pn-scroll"><table class="pn-table pn-columns">
      <thead><tr><th><i>S</i></th><th>points</th><th title="neighbours along R whose labels differ, or a label beside a failed or unclassified point">boundaries</th>
        <th title="the widest gap along R between two points that bracket a boundary">bracket <span class="muted">decades of R</span></th><th title="every bracket within the finest R step">resolved</th><th>finest level</th></tr></thead>
      <tbody>${rows}</tbody></table></div>
    <p class="hint">A point's label is that of its finest finished level (its replicates' majority). Two neighbours along <i>R</i> with different labels bracket
      a boundary; a column is resolved when every bracket is within the finest <i>R</i> step (${num('lattice.step_R_decades', plan.lattice.step_R_decades)} decade).
      A boundary that two points of one label step over is not seen here, as the planner does not see it.</p>`;
}

// The map around a point: the sweep at its phi, the view VIEW_STEPS finest steps to each side.
function mapHashAt(page, c) {
  const phi = page.sweep?.phis?.[0];
  if (phi === undefined) return null;
  const L = page.plan.lattice;
  const s = Math.log10(c.S), r = Math.log10(c.R);
  const dS = VIEW_STEPS * L.step_S_decades, dR = VIEW_STEPS * L.step_R_decades;
  const q = new URLSearchParams({ phi, sweep: page.id, ...viewParams({ S: [(s - dS).toFixed(4), (s + dS).toFixed(4)], R: [(r - dR).toFixed(4), (r + dR).toFixed(4)] }) });
  return `#/map?${q}`;
}

function candidatesHtml(page) {
  const plan = page.plan;
  const limitSelect = `<label class="small pn-limit">listed <select id="pn-limit" aria-label="candidates listed">${LIMITS.map((n) => `<option value="${n}"${n === page.limit ? ' selected' : ''}>${n}</option>`).join('')}</select></label>`;
  const head = `<p class="small pn-count"><span>${num('candidates_total', plan.candidates_total, int)} ${plural(plan.candidates_total, 'run')} ranked now${plan.candidates.length < plan.candidates_total ? `, the first ${plan.candidates.length} listed` : ''}</span> ${limitSelect}</p>`;
  if (!plan.candidates.length) {
    const why = plan.state === 'running' ? 'the neighbourhoods of the runs still pending wait for them' : 'nothing is left worth running';
    return `<section class="card pn-card"><h2>Next runs</h2>${head}<p class="muted" id="pn-none">None: ${why}.</p></section>`;
  }
  const rows = plan.candidates.map((c, i) => {
    const map = mapHashAt(page, c);
    return `<tr data-rank="${i}">
      <td>${i + 1}</td><td>${num(`candidates.${i}.S`, c.S)}</td><td>${num(`candidates.${i}.R`, c.R)}</td>
      <td>${num(`candidates.${i}.level`, c.level, int)}</td><td>${num(`candidates.${i}.replicate`, c.replicate, int)}</td>
      <td>${num(`candidates.${i}.value`, c.value)}</td>
      <td class="pn-why"><b data-k="candidates.${i}.why" title="${escapeHtml(WHY[c.why] || '')}">${escapeHtml(c.why)}</b></td>
      <td>${num(`candidates.${i}.cpu_seconds`, c.cpu_seconds)}</td>
      <td>${map ? `<a href="${map}" class="pn-map" title="the map around this point (${VIEW_STEPS} finest steps to each side)">map</a>` : ''}</td></tr>`;
  }).join('');
  return `<section class="card pn-card"><h2>Next runs</h2>${head}
    <div class="pn-scroll"><table class="pn-table pn-candidates">
      <thead><tr><th>#</th><th><i>S</i></th><th><i>R</i></th><th>level</th><th title="the point's runs at that level before it: its seed is the sweep's seeds[replicate]">replicate</th>
        <th title="the planner's value of the run: its weight times the cell's side in decades (or the finest step)">weight</th><th>why</th><th>CPU-s</th><th></th></tr></thead>
      <tbody>${rows}</tbody></table></div>
    <dl class="pn-dl pn-whys">${[...new Set(plan.candidates.map((c) => c.why))].map((w) => `<dt>${escapeHtml(w)}</dt><dd>${escapeHtml(WHY[w] || 'a reason this page does not know')}</dd>`).join('')}</dl>
    <p class="hint">Ranked best first, budgets aside: the coarsest level's map first, then by level, weight, cost and larger <i>S</i>.
      The planner queues from the top what fits the budgets and the in-flight limit; CPU-s: the cost model's CPU seconds of the run.</p></section>`;
}

function render(page) {
  const { el, plan, sweep } = page;
  el.problem.hidden = true;
  el.body.innerHTML = `<div class="pn-grid">${stateHtml(plan)}${budgetHtml(plan)}</div>${levelsHtml(plan, sweep)}${resolutionHtml(plan)}${candidatesHtml(page)}`;
  el.body.querySelector('#pn-limit')?.addEventListener('change', (ev) => {
    page.limit = Number(ev.target.value);
    setParams({ sweep: page.id, limit: page.limit === DEFAULT_LIMIT ? '' : page.limit });
    poll(page);
  });
}

function showSweep(page) {
  const s = page.sweep;
  page.el.name.textContent = s.name;
  const phi = s.phis?.[0];
  page.el.links.innerHTML = `${phi !== undefined ? `<a href="#/map?phi=${phi}&sweep=${s.id}" id="pn-map">on the map</a> · ` : ''}<a href="#/runs?sweep=${s.id}">its runs</a> · <a href="#/sweeps">all sweeps</a>`;
}

// A plan the server does not give: no such sweep (404), a sweep that does not plan (409: a
// grid sweep, or a request the server's limits no longer plan), a refused request (422).
function problemHtml(page, e) {
  const id = escapeHtml(page.id);
  const back = '<a href="#/sweeps">the sweeps list</a>';
  if (e.status === 404) return `<p><b>No sweep #${id} on this server.</b> The sweeps it holds are in ${back}.</p>`;
  const grid = page.sweep && !page.sweep.request?.adaptive;
  if ((e.status === 409 || e.status === 422) && grid) {
    return `<p><b>Sweep #${id} (${escapeHtml(page.sweep.name)}) is not adaptive</b>: it is a grid of points fixed when it was made, so no planner chooses its runs and it has no plan.
      Its progress is in ${back}; its runs are <a href="#/map?phi=${page.sweep.phis?.[0] ?? ''}&sweep=${id}">on the map</a>.</p>`;
  }
  return `<p><b>The server gives no plan for sweep #${id}</b> (HTTP ${e.status}${e.field ? `, ${escapeHtml(e.field)}` : ''}): ${escapeHtml(e.message)}</p><p>Back to ${back}.</p>`;
}

function showProblem(page, html) {
  page.el.problem.innerHTML = html;
  page.el.problem.hidden = false;
  page.el.body.innerHTML = '';
}

// Asks for the plan (a 304 gives the same object back: nothing to draw) and plans the next ask.
async function poll(page) {
  clearTimeout(page.timer);
  if (!page.alive) return;
  const limit = page.limit;
  let next = POLL_MS;
  try {
    const plan = await api.sweepPlan(page.id, limit);
    if (!page.alive || limit !== page.limit) return;
    if (plan !== page.plan) {
      page.plan = plan;
      render(page);
    }
    const done = PLAN_STATES[plan.state]?.done;
    next = plan.state === 'cancelled' ? null : done ? IDLE_POLL_MS : POLL_MS;
    const at = new Date().toLocaleTimeString();
    page.el.live.textContent = next === null ? `read at ${at}; a cancelled sweep is not asked again`
      : `read at ${at}; asked again every ${next / 1000} s${done ? ' (finished: a new label can make it plan again)' : ' while it runs'}`;
  } catch (e) {
    if (!page.alive) return;
    if (e.status === 404 || e.status === 409 || e.status === 422) {
      showProblem(page, problemHtml(page, e));
      page.el.live.textContent = '';
      return;
    }
    // The server is unreachable or failed: the plan shown stays, marked old, and is asked again.
    page.el.live.innerHTML = `<span class="error">Could not read the plan (${escapeHtml(e.message)}); the one shown may be old. Asking again.</span>`;
  }
  if (next !== null && page.alive) page.timer = setTimeout(() => poll(page), next);
}

export function mount(root, params) {
  const page = createPage(root, params);
  if (!/^[1-9]\d*$/.test(page.id)) {
    showProblem(page, `<p><b>${page.id ? `"${escapeHtml(page.id)}" is not a sweep id` : 'No sweep given'}.</b> A plan's address is <code>#/plan?sweep=ID</code>; the adaptive sweeps in <a href="#/sweeps">the sweeps list</a> link to theirs.</p>`);
    return () => {};
  }
  (async () => {
    try {
      page.sweep = await api.sweep(page.id);
      if (page.alive) showSweep(page);
    } catch { /* the plan's answer says what is wrong */ }
    if (page.alive) poll(page);
  })();
  return () => { page.alive = false; clearTimeout(page.timer); };
}
