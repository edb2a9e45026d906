// The classifier's features grouped, each with its one-line explanation, from the one glossary
// the docs share (web/data/feature-glossary.json; docs/classifier.md's table is generated from
// it, tests/docs/feature_glossary_test.py checks both against the classifier), and the rule of
// whether a run has a band, whose speeds are shown only then.
import { escapeHtml, fixed, sci } from './format.js';

let loading = null;

// The glossary, fetched once per page load ({groups: [], features: {}, band_classes} on failure:
// the features are then shown ungrouped under their keys).
export function loadGlossary() {
  if (!loading) {
    loading = fetch(new URL('../data/feature-glossary.json', import.meta.url), { cache: 'no-cache' })
      .then((r) => (r.ok ? r.json() : Promise.reject(new Error(`HTTP ${r.status}`))))
      .catch((e) => {
        console.warn('feature glossary:', e.message);
        loading = null;
        return { groups: [], features: {}, band_classes: { classes: ['a', 'b', 'c', 'e'], text: '' } };
      });
  }
  return loading;
}

// The label that counts: a person's, else the classifier's (null: none).
export function effectiveLabel(job) {
  return job.human_label?.label ?? job.result?.class ?? null;
}

// Whether a run (or a point, given its label and c_b/V) has a band: its label is one of the
// glossary's band classes and its front ran down from the top (c_b/V > 0).
export function hasBand(glossary, label, speed) {
  return Boolean(label) && glossary.band_classes.classes.includes(label) && typeof speed === 'number' && Number.isFinite(speed) && speed > 0;
}

// The features in the glossary's groups, in its order: [{group, rows: [{key, entry, value,
// error}]}]; an error shown beside its value is not a row of its own; keys the glossary does not
// know (another engine version) go to a last group, "other".
export function groupFeatures(glossary, features) {
  const known = glossary.features;
  const byGroup = new Map(glossary.groups.map((g) => [g.id, { group: g, rows: [] }]));
  const other = { group: { id: 'other', title: 'Other', text: 'features this dashboard has no explanation of (another engine version)' }, rows: [] };
  for (const [key, entry] of Object.entries(known)) {
    if (!(key in features) || entry.error_of) continue;
    const row = { key, entry, value: features[key], error: entry.error ? features[entry.error] : undefined };
    (byGroup.get(entry.group) || other).rows.push(row);
  }
  for (const [key, value] of Object.entries(features)) {
    if (!known[key]) other.rows.push({ key, entry: null, value, error: undefined });
  }
  return [...byGroup.values(), other].filter((g) => g.rows.length);
}

// A feature's value as HTML: a number to 3 digits, yes or no, a list of names, an object of
// numbers (the scores) one key each.
export function featureHtml(v) {
  if (v === null || v === undefined) return '—';
  if (typeof v === 'boolean') return v ? 'yes' : 'no';
  if (typeof v === 'string') return escapeHtml(v || '—');
  if (Array.isArray(v) && v.every((x) => typeof x === 'string')) return v.length ? escapeHtml(v.join(', ')) : 'none';
  if (typeof v === 'number') return sci(v, 3);
  if (v && typeof v === 'object' && !Array.isArray(v) && Object.values(v).every((x) => typeof x === 'number')) {
    return `<span class="scores">${Object.entries(v).map(([k, x]) => `<span><b>${escapeHtml(k)}</b> ${fixed(x, 2)}</span>`).join(' ')}</span>`;
  }
  return escapeHtml(JSON.stringify(v));
}
