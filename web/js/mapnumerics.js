// The phase map's numerics: which resolution each place shows, and the caption that says it.
// A place is an (S, R) at the page's phi. By default ("finest") it shows only its finest points
// (the most grid cells per unit cell, the same order as cells across a strut at one phi), so a
// fast-preset run never sits beside a default-preset one at a place and coarse and fine runs do
// not pile up; "all" shows every point (those at one place set around it), a number one grid.
import { fixed } from './format.js';

export const FINEST = 'finest';

// A place's key: its (S, R) to 10 digits (a run imported from another map may differ from the
// same grid value in the 12th digit).
export const placeKey = (p) => `${p.S.toPrecision(10)}|${p.R.toPrecision(10)}`;

// Cells across a strut of a point, as its preset names them (4.5, 9, 1.8).
const strutOf = (p) => Number((p.s?.cells_per_strut ?? p.runs?.[0]?.cells_per_strut ?? 0).toFixed(1));

// The points of the finest grid at each place; `hidden`: how many coarser points it leaves out.
export function finestPerPlace(points) {
  const best = new Map(); // place -> finest cells_per_unit there
  for (const p of points) {
    const k = placeKey(p);
    if (!(best.get(k) >= p.cells_per_unit)) best.set(k, p.cells_per_unit);
  }
  const kept = points.filter((p) => p.cells_per_unit === best.get(placeKey(p)));
  return { kept, hidden: points.length - kept.length };
}

// The points of a numerics choice: "finest", "all", or one grid's cells per unit cell.
export function ofNumerics(choice, points) {
  if (choice === 'all') return points;
  if (choice === FINEST) return finestPerPlace(points).kept;
  return points.filter((p) => String(p.cells_per_unit) === String(choice));
}

// "4.5 cells across a strut at 180 points, 9 at 20": the resolutions shown, most points first.
function resolutionsText(points) {
  const n = new Map();
  for (const p of points) n.set(strutOf(p), (n.get(strutOf(p)) || 0) + 1);
  const parts = [...n].sort((a, b) => b[1] - a[1] || b[0] - a[0]);
  return parts.map(([c, k], i) => `${fixed(c, c % 1 ? 1 : 0)}${i ? '' : ' cells across a strut'} at ${k.toLocaleString()} point${k === 1 ? '' : 's'}`).join(', ');
}

// The caption under the map: what the choice shows of `points` (every point of the filters).
export function numericsCaption(choice, points) {
  if (!points.length) return '';
  if (choice === FINEST) {
    const { kept, hidden } = finestPerPlace(points);
    return `finest run per point: ${resolutionsText(kept)}${hidden ? ` · ${hidden.toLocaleString()} coarser point${hidden === 1 ? '' : 's'} not shown (numerics: all resolutions)` : ''}`;
  }
  if (choice === 'all') return `all resolutions: ${resolutionsText(points)}`;
  return `one resolution: ${resolutionsText(ofNumerics(choice, points))}`;
}
