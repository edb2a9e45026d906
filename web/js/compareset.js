// The runs a person compares (#/compare?ids=12,15,40, js/pages/compare.js): the rule of how many
// and the list's text in the address, and the runs picked on the Runs page (js/pages/runs.js),
// kept in the tab's sessionStorage so that they stay while the table is filtered, paged or left.

// At most this many runs side by side: six space-time maps still fit two rows of a desktop, six
// curves one plot and six columns one table a person can read across.
export const MAX_COMPARE = 6;

export function compareHash(ids) {
  return `#/compare?ids=${ids.join(',')}`;
}

// The ids of the address's list "12,15,40": whole positive numbers, each once, in its order;
// bad: the entries that are not run ids.
export function parseIds(text) {
  const ids = [], bad = [];
  for (const part of String(text ?? '').split(',').map((s) => s.trim()).filter(Boolean)) {
    const n = /^\d{1,15}$/.test(part) ? Number(part) : NaN;
    if (!(n > 0)) bad.push(part);
    else if (!ids.includes(n)) ids.push(n);
  }
  return { ids, bad };
}

const KEY = 'compaction-sweep.compare';

// The runs picked for comparison in this tab, in the order they were picked.
export function picked() {
  try {
    const v = JSON.parse(sessionStorage.getItem(KEY) || '[]');
    return Array.isArray(v) ? v.filter((x) => Number.isInteger(x) && x > 0).slice(0, MAX_COMPARE) : [];
  } catch {
    return [];
  }
}

export function setPicked(ids) {
  try { sessionStorage.setItem(KEY, JSON.stringify(ids.slice(0, MAX_COMPARE))); } catch { /* private mode: the page's own list */ }
}
