// The phase map's points. A point is one computation up to its seed (docs/replicates.md); its
// runs are its replicates. GET /phase-map serves the runs (`points`, one per run) and one
// summary per point (`summaries`: the replicates' class probabilities, majority label and share,
// robustness, band speeds as mean, sd and n); mapPoints joins the two, and drawPointMarks draws
// them: a point of one run exactly as that run is drawn, a point of several in its majority's
// colour and shape with a pie of its classes inside when they disagree, ringed by a dashed line
// while its label is not robust. The map, its export and its keys all draw through here.
import { CLASSES, INCIRCLE, category, confidenceFade, drawMarker, fadeColor, look } from './classes.js';
import { drawHumanMark } from './humanlabels.js';
import { escapeHtml, fixed } from './format.js';

// The pie of a split point fills the incircle of its marker's shape, inside the marker's 1 px
// outline (PIE_INSET px in): a circle becomes a pie chart, the other shapes keep their corners
// in the majority's colour, so the shape still reads at a glance.
export const PIE_INSET = 0.6;
// A point of several runs whose label is not robust (its replicates split, or one failed, is
// unclassified or still pending) is ringed by UNSETTLED_DASHES dashes of ink, the first centred
// at 12 o'clock, dash and gap alike, UNSETTLED_WIDTH px wide, on a circle UNSETTLED_GAP px
// outside the circle of 1.2 r that holds every class shape (the diamond's and the triangles'
// tips). A robust point and a point of one run (no evidence either way) have none, so a map
// without replicates looks as it did before them.
export const UNSETTLED_DASHES = 6;
export const UNSETTLED_GAP = 1.5;
export const UNSETTLED_WIDTH = 1.4;
export const UNSETTLED_INK = '#1d2433';
export const unsettledRadius = (r) => 1.2 * r + UNSETTLED_GAP;

const ENDED = ['unclassified', 'unstable', 'failed', 'cancelled']; // the looks of an ended run without a label

// An answer without summaries (a server before replicates, the render benchmark's fabricated
// answer) reads as one point per run.
function summaryOfRun(p) {
  return { point_id: p.point_id ?? -p.job_id, S: p.S, R: p.R, phi: p.phi, cells_per_unit: p.cells_per_unit, cells_per_strut: p.cells_per_strut, eps_end: p.eps_end, structure: p.structure, jobs: [p.job_id], runs: 1 };
}

// The majority's mean confidence (a person's label counts as 1, as the planner counts it,
// counted_label.hpp); null when none of its runs has one.
function majorityConfidence(runs, cls) {
  let sum = 0, n = 0;
  for (const p of runs) {
    if (category(p) !== cls) continue;
    const c = p.human_label ? 1 : p.confidence;
    if (Number.isFinite(c)) { sum += c; n++; }
  }
  return n ? sum / n : null;
}

// The runs of a point that carry its majority's label (category: the counted label).
export const majorityRuns = (pt) => pt.runs.filter((p) => category(p) === pt.s.label);

// How many of a point's labelled replicates carry its majority's label.
export const majorityCount = (s) => (s.label ? Math.round(s.share * s.labelled) : 0);

// How a point of one run looks: as the run, exactly as the map drew runs before it had
// replicates (a person's label unfaded).
function oneRunLook(p) {
  const cat = category(p);
  return {
    cat,
    progress: p.progress_eps !== null && p.eps_end > 0 ? p.progress_eps / p.eps_end : 0,
    fade: CLASSES[cat] && !p.human_label ? confidenceFade(p.confidence) : 0,
    ring: cat === 'unclassified' ? p.runner_up : null,
    split: null,
  };
}

// How a point of several runs looks: its majority's class; without one, running (the arc: the
// share of its replicates' strain done) or queued while a replicate waits, else the look most of
// its ended runs have (unclassified: ringed by the runner-up most of them name).
function severalRunsLook(s, runs) {
  if (CLASSES[s.label]) {
    const split = s.share !== null && s.share < 1
      ? Object.entries(s.probabilities || {}).filter(([k, v]) => CLASSES[k] && v > 0).sort((a, b) => b[1] - a[1] || (a[0] < b[0] ? -1 : 1))
      : null;
    // The majority first: the pie starts at 12 o'clock with it.
    if (split) split.sort((a, b) => (a[0] === s.label ? -1 : b[0] === s.label ? 1 : 0));
    return { cat: s.label, progress: 0, fade: confidenceFade(majorityConfidence(runs, s.label)), ring: null, split };
  }
  const cats = runs.map(category);
  if (cats.includes('running') || cats.includes('queued')) {
    const done = (p) => (['succeeded', 'failed', 'cancelled'].includes(p.state) ? 1 : p.state === 'running' && p.progress_eps !== null && p.eps_end > 0 ? Math.min(1, p.progress_eps / p.eps_end) : 0);
    const progress = runs.reduce((a, p) => a + done(p), 0) / runs.length;
    return { cat: cats.includes('running') ? 'running' : 'queued', progress, fade: 0, ring: null, split: null };
  }
  let cat = 'unclassified', most = 0;
  for (const k of ENDED) {
    const n = cats.filter((c) => c === k).length;
    if (n > most) { most = n; cat = k; }
  }
  return { cat, progress: 0, fade: 0, split: null, ring: cat === 'unclassified' ? commonest(runs.map((p) => p.runner_up).filter(Boolean)) : null };
}

// The value most often in a list (the first of the tied ones); null for none.
function commonest(values) {
  const n = new Map();
  for (const v of values) n.set(v, (n.get(v) || 0) + 1);
  let best = null, most = 0;
  for (const [v, k] of n) if (k > most) { best = v; most = k; }
  return best;
}

// The points of a /phase-map answer, each { id, s (its summary), runs (its run objects), S, R,
// cells_per_unit, cat, progress, fade, ring, human, split ([[class, share], ...] with the
// majority first, or null), robust, unsettled (several runs, a label, not robust) }.
export function mapPoints(answer) {
  const runs = answer?.points || [];
  const byJob = new Map(runs.map((p) => [p.job_id, p]));
  const summaries = answer?.summaries || runs.map(summaryOfRun);
  const out = [];
  for (const s of summaries) {
    const rs = s.jobs.map((id) => byJob.get(id)).filter(Boolean);
    if (!rs.length) continue;
    const several = rs.length > 1;
    const pt = { id: s.point_id, s, runs: rs, S: s.S, R: s.R, cells_per_unit: s.cells_per_unit, ...(several ? severalRunsLook(s, rs) : oneRunLook(rs[0])) };
    pt.robust = several && s.robust === true;
    pt.unsettled = several && !pt.robust && !!CLASSES[pt.cat];
    pt.human = rs.some((p) => p.human_label);
    out.push(pt);
  }
  return out;
}

// The colour a class's part of a pie is filled with: faded as the marker is.
const pieColor = (cls, fade) => (fade > 0 ? fadeColor(CLASSES[cls].color, fade) : CLASSES[cls].color);

// The radius and centre of a split point's pie in its marker (m: cat, x, y, r).
export function pieOf(m) {
  const [dy, inr] = INCIRCLE[look(m.cat).shape] || [0, 1];
  return { cx: m.x, cy: m.y + dy * m.r, pr: Math.max(0, inr * m.r - PIE_INSET) };
}

// The pie of a split point inside its marker: one sector per class from 12 o'clock, clockwise,
// the majority first (its sector is the marker's own colour, not drawn again), the other
// classes' sectors parted from it and from each other by thin white radii (left out below
// PIE_RADII_FROM px, where they would hide the sectors). Fills the sectors and adds the radii to
// `radii` (one stroke draws them all).
const PIE_RADII_FROM = 3;
function drawSplit(ctx, m, radii) {
  const { cx, cy, pr } = pieOf(m);
  let a = -Math.PI / 2 + 2 * Math.PI * m.split[0][1];
  const edges = [-Math.PI / 2, a];
  for (const [cls, share] of m.split.slice(1)) {
    const b = a + 2 * Math.PI * share;
    ctx.beginPath();
    ctx.moveTo(cx, cy);
    ctx.arc(cx, cy, pr, a, b);
    ctx.closePath();
    ctx.fillStyle = pieColor(cls, m.fade);
    ctx.fill();
    edges.push(b);
    a = b;
  }
  if (pr >= PIE_RADII_FROM) for (const e of edges) radii.push(cx, cy, cx + pr * Math.cos(e), cy + pr * Math.sin(e));
}

// The pies of the split points, their white radii in one path (one stroke draws them).
function drawSplits(ctx, marks) {
  const radii = []; // x0, y0, x1, y1 of each
  for (const m of marks) if (m.split && CLASSES[m.cat]) drawSplit(ctx, m, radii);
  if (!radii.length) return;
  ctx.beginPath();
  for (let i = 0; i < radii.length; i += 4) { ctx.moveTo(radii[i], radii[i + 1]); ctx.lineTo(radii[i + 2], radii[i + 3]); }
  ctx.lineWidth = 0.9;
  ctx.strokeStyle = '#ffffff';
  ctx.stroke();
}

// The dashed rings of the unsettled points, all in one path (one stroke draws them).
function drawUnsettled(ctx, marks) {
  const half = Math.PI / (2 * UNSETTLED_DASHES); // a dash's half-angle: dash and gap alike
  ctx.beginPath();
  let any = false;
  for (const m of marks) {
    if (!m.unsettled) continue;
    const R = unsettledRadius(m.r);
    for (let k = 0; k < UNSETTLED_DASHES; k++) {
      const c = -Math.PI / 2 + (2 * Math.PI * k) / UNSETTLED_DASHES;
      ctx.moveTo(m.x + R * Math.cos(c - half), m.y + R * Math.sin(c - half));
      ctx.arc(m.x, m.y, R, c - half, c + half);
    }
    any = true;
  }
  if (!any) return;
  ctx.lineWidth = UNSETTLED_WIDTH;
  ctx.strokeStyle = UNSETTLED_INK;
  ctx.stroke();
}

// Draws the markers of points on a canvas context (or an SvgPathContext), each m = { cat, x, y,
// r, progress, fade, ring, split, unsettled, human, added }: every marker in the order given, then
// the pies of the split ones, the rings of the unsettled ones, the marks of the ones a person
// labelled and of the ones an adaptive planner added. A filled shape is a path of its own and the pies' radii share one: chromium fills
// one path of many polygons ten times slower than many paths of one, and strokes lines the
// other way round.
export function drawPointMarks(ctx, marks) {
  for (const m of marks) drawMarker(ctx, m.cat, m.x, m.y, m.r, m.progress || 0, m.fade || 0, m.ring || null);
  drawSplits(ctx, marks);
  drawUnsettled(ctx, marks);
  for (const m of marks) if (m.human) drawHumanMark(ctx, m.x, m.y, m.r);
  for (const m of marks) if (m.added) drawAddedMark(ctx, m.x, m.y, m.r);
}

// A point an adaptive sweep's planner added after its initial grid (mapplan.js): a white-rimmed
// ink dot on the upper right of its marker (the middle is a person's label's), ADDED_AT x r out
// along the diagonal, where the class shapes' corners stay visible beside it.
export const ADDED_AT = 0.85;
export const addedDot = (r) => Math.max(1.4, 0.3 * r);
export function drawAddedMark(ctx, x, y, r) {
  ctx.beginPath();
  ctx.arc(x + ADDED_AT * r, y - ADDED_AT * r, addedDot(r), 0, 2 * Math.PI);
  ctx.fillStyle = UNSETTLED_INK;
  ctx.fill();
  ctx.lineWidth = 1;
  ctx.strokeStyle = '#fff';
  ctx.stroke();
}

// One point's marker (the export's, a key's).
export const drawPointMark = (ctx, m) => drawPointMarks(ctx, [m]);

// Why a point's label is not robust: "1 of 4 pending", "1 failed or unclassified", "they
// split", "one run" (a point of one run has no evidence either way); '' when it is.
export function notRobustWhy(s) {
  if (s.robust) return '';
  if (s.runs < 2) return 'one run';
  const why = [];
  if (s.finished < s.runs) why.push(`${s.runs - s.finished} of ${s.runs} pending`);
  if (s.labelled < s.finished) why.push(`${s.finished - s.labelled} failed or unclassified`);
  if (s.label && s.share < 1) why.push('they split');
  return why.join(', ');
}

// A reading over the replicates ({mean, sd, n} or null) as "2.31 ± 0.12 (n = 3)".
export function spreadText(r, digits = 3) {
  if (!r || !Number.isFinite(r.mean)) return '—';
  return `${fixed(r.mean, digits)}${r.sd === null || r.sd === undefined ? '' : ` ± ${fixed(r.sd, digits)}`} (<i>n</i> = ${r.n})`;
}

const dot = (cls) => (CLASSES[cls] ? `<span class="dot" style="background:${CLASSES[cls].color}"></span>` : '');

// The classes of the labelled replicates, most frequent first: "● a 0.75  ● b 0.25".
export function probabilitiesHtml(probabilities) {
  const e = Object.entries(probabilities || {}).filter(([k]) => CLASSES[k]).sort((a, b) => b[1] - a[1] || (a[0] < b[0] ? -1 : 1));
  return e.length ? e.map(([k, v]) => `<span class="prob">${dot(k)}${k} ${fixed(v, 2)}</span>`).join(' ') : '—';
}

// What a run of a point shows beside its link: its counted label, else its state.
export function runStateText(p) {
  const cat = category(p);
  if (CLASSES[cat]) return `${dot(cat)}${cat}${p.human_label ? ' ●' : ''}`;
  return escapeHtml(look(cat).name);
}

// A link to each run of a point, with its label or state.
export function runLinksHtml(runs) {
  return runs.map((p) => `<div class="tt-run"><a href="#/run/${p.job_id}" data-job="${p.job_id}">run ${p.job_id}</a> <span class="run-state">${runStateText(p)}</span></div>`).join('');
}
