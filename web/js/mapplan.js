// An adaptive sweep on the phase map: its plan's state in a caption (GET /sweeps/{id}/plan:
// state, runs against the budget, CPU-hours against the budget) and which of its points the
// planner added after the initial grid. The server serves no per-run origin; the initial grid is
// derived from the sweep's stored request as the planner makes it (docs/adaptive.md, "Lattice":
// log-spaced, both ends included, at the first level's grid): a point elsewhere, or at a finer
// level, was added by the planner (refinement, a finer level, or a point it followed).
import { escapeHtml, fixed } from './format.js';

const ON_NODE = 1e-6; // decades: grid values are rounded to 12 significant digits

// Whether an axis value (decades) is one of n log-spaced nodes from min to max, ends included.
function onAxis(v, { min, max }, n) {
  const a = Math.log10(min), b = Math.log10(max);
  const k = ((v - a) / (b - a)) * (n - 1);
  return Math.abs(k - Math.round(k)) * ((b - a) / (n - 1)) < ON_NODE && Math.round(k) >= 0 && Math.round(k) <= n - 1;
}

// A test of "the planner added this point" for a sweep record (GET /sweeps) and its plan, or null
// when the sweep is not adaptive. A point of the initial grid stays initial with its replicates.
export function addedByPlanner(sweep, plan) {
  const spec = sweep?.request?.adaptive;
  if (!spec) return null;
  const init = spec.initial || { S: 5, R: 5 };
  const level0 = plan?.levels?.[0]?.cells_per_unit ?? null;
  return (p) => !(onAxis(Math.log10(p.S), spec.S, init.S) && onAxis(Math.log10(p.R), spec.R, init.R) && (level0 === null || p.cells_per_unit === level0));
}

const hours = (h) => (h === null || h === undefined ? '—' : h < 10 ? fixed(h, 2) : fixed(h, 1));

// The states of a plan (GET /sweeps/{id}/plan, `state`) in words, after docs/adaptive.md; done:
// whether the sweep has stopped growing in that state.
export const PLAN_STATES = {
  running: { done: false, text: 'Runs of the sweep are queued or running; the planner adds more as their results arrive, up to the sweep\'s in-flight limit.' },
  planning: { done: false, text: 'A result has just arrived and the planner is adding the runs it asks for: nothing is pending, runs are worth queueing and budget is left.' },
  resolved: { done: true, text: 'Finished: every boundary between classes lies between two runs at most one finest step apart, and no boundary, disagreement between replicates or label moved by a finer level asks for another run.' },
  budget_spent: { done: true, text: 'Finished: runs are left worth queueing, but neither budget (runs, CPU-hours) allows one more. The boundaries may be coarser than the finest step.' },
  unresolved: { done: true, text: 'Finished: nothing is left worth running while a boundary is still coarser than the finest step, e.g. beside failed runs (a failed region is not searched).' },
  cancelled: { done: true, text: 'The sweep was cancelled: nothing more is queued or planned.' },
};
export const planStateName = (state) => state.replace('_', ' ');

// The hash of an adaptive sweep's plan page (js/pages/plan.js).
export const planHash = (sweepId) => `#/plan?sweep=${encodeURIComponent(sweepId)}`;

// "adaptive plan: running · 180 of 200 runs (8 pending) · 3.10 of 40.0 CPU-hours · 155 points
// added by the planner (dot at upper right), 25 of the initial grid · the plan", the last a link
// to the plan page.
export function planCaption(plan, added, initial) {
  if (!plan) return '';
  const runs = plan.runs || {};
  const cpu = plan.cpu_hours || {};
  const parts = [
    `adaptive plan: <b class="plan-state" data-state="${escapeHtml(plan.state)}" title="${escapeHtml(PLAN_STATES[plan.state]?.text ?? '')}">${escapeHtml(planStateName(plan.state))}</b>`,
    `${(runs.done + runs.pending).toLocaleString()} of ${runs.budget.toLocaleString()} runs${runs.pending ? ` (${runs.pending} pending)` : ''}`,
    cpu.budget === null || cpu.budget === undefined ? `${hours(cpu.spent)} CPU-hours (no CPU budget)` : `${hours(cpu.spent)} of ${hours(cpu.budget)} CPU-hours`,
  ];
  if (added !== null) parts.push(`${added.toLocaleString()} point${added === 1 ? '' : 's'} added by the planner (dot at upper right), ${initial.toLocaleString()} of the initial grid`);
  parts.push(`<a href="${planHash(plan.id)}" class="plan-link">the plan</a>`);
  return parts.join(' · ');
}
