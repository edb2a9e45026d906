// The run table's filter form (every filter of GET /limits' jobs.parameters, grouped), shared by
// the Runs page (js/pages/runs.js) and the Plots page (js/pages/plots.js): the same controls
// make the same query (js/runquery.js), so a plot is filtered as the table is. The form's
// controls carry the API's parameter names (data-name); ids start with rt-.
import { CLASSES } from './classes.js';
import { escapeHtml } from './format.js';
import { GEOMETRIES } from './geometries.js';
import { JOB_STATES, LETTERS, filterNames, rangeNames } from './runquery.js';

// The ranges' labels (a range not listed is labelled by its name).
const RANGE_LABELS = {
  S: '<i>S</i>', R: '<i>R</i>', phi: 'φ', confidence: 'confidence', n_reflections: '<i>N</i><sub>r</sub> (reflections)',
  band_speed_ratio: '<i>c</i><sub>b</sub>/<i>V</i> (band speed)',
};
function chipsHtml(name, options) {
  return `<div class="rt-chips" role="group" data-name="${name}">${options.map(([v, text, color]) => `<label class="rt-chip"${color ? ` style="--c:${color}"` : ''}><input type="checkbox" value="${escapeHtml(v)}"><span>${text}</span></label>`).join('')}</div>`;
}

function errHtml(name) {
  return `<div class="field-error" data-for="${name}"></div>`;
}

// The filter form: every filter of limits.jobs.parameters, grouped.
export function filterFormHtml(limits, presets) {
  const names = filterNames(limits);
  const has = (n) => names.includes(n);
  const letters = (extra) => [...LETTERS.map((c) => [c, c, CLASSES[c].color]), ...extra];
  const parts = [];
  const field = (name, label, control, hint = '') =>
    `<div class="f rt-f" data-field="${name}"><label for="rt-${name}">${label}</label>${control}${hint ? `<span class="f-hint">${hint}</span>` : ''}${errHtml(name)}</div>`;
  if (has('q')) parts.push(field('q', 'Search', `<input type="text" id="rt-q" data-name="q" placeholder="sweep name, source id, label reason or who" maxlength="${limits.jobs.q_max_bytes}">`));
  if (has('class')) parts.push(`<div class="f rt-f" data-field="class"><label>Class <span class="f-hint">(classifier)</span></label>${chipsHtml('class', letters([['none', 'none']]))}${errHtml('class')}</div>`);
  if (has('label')) parts.push(`<div class="f rt-f" data-field="label"><label>Label that counts</label>${chipsHtml('label', letters([['none', 'none']]))}${errHtml('label')}</div>`);
  if (has('human_label')) parts.push(`<div class="f rt-f" data-field="human_label"><label>Human label</label>${chipsHtml('human_label', letters([['any', 'any'], ['none', 'none']]))}${errHtml('human_label')}</div>`);
  if (has('state')) parts.push(`<div class="f rt-f" data-field="state"><label>State</label>${chipsHtml('state', JOB_STATES.map((s) => [s, s]))}${errHtml('state')}</div>`);
  if (has('sweep')) {
    parts.push(field('sweep', 'Sweep', '<select id="rt-sweep" data-name="sweep"><option value="">all sweeps</option></select>'));
  }
  if (has('preset')) parts.push(`<div class="f rt-f" data-field="preset"><label>Preset <span class="f-hint">(numerics)</span></label>${chipsHtml('preset', [...presets.map((p) => [p, escapeHtml(p)]), ['none', 'own numerics']])}${errHtml('preset')}</div>`);
  if (has('geometry')) parts.push(`<div class="f rt-f" data-field="geometry"><label>Column <span class="f-hint">(geometry)</span></label>${chipsHtml('geometry', GEOMETRIES)}${errHtml('geometry')}</div>`);
  if (has('cells_per_unit')) {
    const { lo, hi } = limits.scene.cells_per_unit;
    parts.push(field('cells_per_unit', 'Cells per unit cell', `<input type="text" id="rt-cells_per_unit" data-name="cells_per_unit" inputmode="numeric" placeholder="e.g. 8,20">`, `resolution, ${lo} to ${hi}; several comma-separated`));
  }
  if (has('imported')) parts.push(field('imported', 'Imported', `<select id="rt-imported" data-name="imported"><option value="">imported or not</option><option value="true">imported</option><option value="false">computed here</option></select>`));
  if (has('phi')) parts.push(field('phi', 'φ exactly', `<input type="text" id="rt-phi" data-name="phi" inputmode="decimal" placeholder="e.g. 0.4">`));
  const range = (r) => `<div class="f rt-f rt-range" data-field="${r}"><label for="rt-${r}_min">${RANGE_LABELS[r] || r}</label>
      <div class="rt-pair"><input type="text" id="rt-${r}_min" data-name="${r}_min" inputmode="decimal" placeholder="min" aria-label="${r} min"><span>to</span><input type="text" id="rt-${r}_max" data-name="${r}_max" inputmode="decimal" placeholder="max" aria-label="${r} max"></div>
      ${errHtml(`${r}_min`)}${errHtml(`${r}_max`)}</div>`;
  const ranges = rangeNames(limits).map(escapeHtml);
  for (const r of ranges.filter((n) => RANGE_LABELS[n])) parts.push(range(r));
  if (has('point')) parts.push(field('point', 'Point', `<input type="text" id="rt-point" data-name="point" inputmode="numeric" placeholder="point id (its replicates)">`));
  if (has('source')) parts.push(field('source', 'Source database', `<input type="text" id="rt-source" data-name="source" placeholder="start of its id (hex)">`));
  // The other ranges (the run's strain reached and wall time, the classifier's features) in a
  // fold of their own, last, opened by fillFilterForm when one of them is set.
  const more = ranges.filter((n) => !RANGE_LABELS[n]);
  if (more.length) {
    parts.push(`<details class="rt-more" id="rt-more"><summary>Features and run numbers <span class="f-hint">(${more.length} ranges: the classifier's features, the strain reached, the wall time)</span></summary>
      <div class="rt-grid">${more.map(range).join('')}</div></details>`);
  }
  return parts.join('');
}

// The form's controls set from filters ({name: text}); returns how many are set.
export function fillFilterForm(form, f) {
  for (const input of form.querySelectorAll('input[data-name], select[data-name]')) {
    const v = f[input.dataset.name] ?? '';
    if (input.tagName === 'SELECT' && v && ![...input.options].some((o) => o.value === v)) input.append(new Option(v, v));
    input.value = v;
  }
  for (const group of form.querySelectorAll('.rt-chips')) {
    const on = (f[group.dataset.name] || '').split(',');
    for (const box of group.querySelectorAll('input')) box.checked = on.includes(box.value);
  }
  const more = form.querySelector('.rt-more');
  if (more && [...more.querySelectorAll('input[data-name]')].some((i) => i.value !== '')) more.open = true;
  return Object.keys(f).length;
}

// The filters the form holds.
export function readFilterForm(form) {
  const f = {};
  for (const input of form.querySelectorAll('input[data-name], select[data-name]')) {
    const v = input.value.trim();
    if (v !== '') f[input.dataset.name] = v;
  }
  for (const group of form.querySelectorAll('.rt-chips')) {
    const on = [...group.querySelectorAll('input:checked')].map((b) => b.value);
    if (on.length) f[group.dataset.name] = on.join(',');
  }
  return f;
}

// Each problem ({field, message}: checkQuery's or the server's 422) at its field in root, one
// without a field of the form in `other`.
export function showFilterErrors(root, problems, other) {
  for (const e of root.querySelectorAll('.field-error')) e.textContent = '';
  for (const f of root.querySelectorAll('.rt-f.invalid')) f.classList.remove('invalid');
  for (const p of problems) {
    const at = root.querySelector(`.rt-f .field-error[data-for="${CSS.escape(p.field)}"]`);
    if (at) {
      at.textContent = p.message;
      at.closest('.rt-f').classList.add('invalid');
    } else {
      other.textContent = `${p.field ? `${p.field}: ` : ''}${p.message}`;
    }
  }
}

// The sweeps of the sweep list, when they come (the rows do not wait for them).
export function fillSweepSelect(form, sweeps) {
  const select = form.querySelector('#rt-sweep');
  if (!select) return;
  const keep = select.value;
  select.replaceChildren(new Option('all sweeps', ''), ...sweeps.map((s) => new Option(`${s.id} · ${s.name || ''}`, String(s.id))));
  if (keep && ![...select.options].some((o) => o.value === keep)) select.append(new Option(keep, keep));
  select.value = keep;
}
