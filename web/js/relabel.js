// The run page's "Human label" card: a person sets a class a-f on a run with a reason (PUT
// /api/v1/jobs/{id}/label, submit token), or removes it (DELETE); the classifier's label stays
// beside it, and the run's changes are listed, newest first (who, what, when, why).
import { api, ApiError, setSubmitToken, submitToken } from './api.js';
import { CLASSES, inkOn, label } from './classes.js';
import { escapeHtml, when } from './format.js';

const BY_KEY = 'compaction.labelBy';
const REASON_MAX = 2000, BY_MAX = 200; // the server's rules (server/store/label_store.hpp)

function rememberedBy() {
  try { return localStorage.getItem(BY_KEY) || ''; } catch { return ''; }
}

function badge(cls) {
  const c = CLASSES[cls];
  return c ? `<span class="badge cls" style="--c:${c.color};color:${inkOn(c.color)}">${escapeHtml(label(cls))}</span>` : '—';
}

// The run's changes, newest first: one compact entry each (what, who, when on a line, why below).
function historyHtml(changes) {
  if (!changes.length) return '<p class="muted">No human label has been set on this run.</p>';
  const items = changes.map((c) => {
    const what = c.action === 'cleared' ? `removed ${c.previous_label ? escapeHtml(c.previous_label) : ''}` : `${escapeHtml(c.action)} <b>${escapeHtml(c.label || '')}</b>`;
    return `<li><div class="lc-head"><span>${what} by <b>${escapeHtml(c.by)}</b></span><time class="muted">${escapeHtml(when(c.at))}</time></div>${c.reason ? `<div class="lc-why">${escapeHtml(c.reason)}</div>` : ''}</li>`;
  });
  return `<ol class="label-history">${items.join('')}</ol>`;
}

// Whether the server wants a submit token (GET /health's tokens.submit), asked once per page
// load; null when it does not say (an older server): the field then shows after a 401.
let tokensAsked = null;
function submitTokenRequired() {
  if (!tokensAsked) tokensAsked = api.health().then((h) => (h.tokens ? h.tokens.submit === 'required' : null), () => { tokensAsked = null; return null; });
  return tokensAsked;
}

// Checks the form as the server will (the server still checks everything): field -> message.
export function validateLabel({ label: cls, reason, by }) {
  const errors = {};
  if (!CLASSES[cls]) errors.label = 'choose a class';
  if (!reason.trim()) errors.reason = 'say why';
  else if (new TextEncoder().encode(reason).length > REASON_MAX) errors.reason = `at most ${REASON_MAX} bytes`;
  if (!by.trim()) errors.by = 'say who you are';
  else if (new TextEncoder().encode(by).length > BY_MAX) errors.by = `at most ${BY_MAX} bytes`;
  return errors;
}

export function showRelabel(box, job, reload) {
  if (!job.result) {
    box.innerHTML = '<p class="muted">A label can be set once the run has a result.</p>';
    delete box.dataset.key;
    return;
  }
  const key = `${job.id}:${JSON.stringify(job.human_label)}`;
  if (box.dataset.key === key) return; // polled again: keep what the person is typing
  box.dataset.key = key;
  const h = job.human_label;
  const options = Object.keys(CLASSES).map((c) => `<option value="${c}" ${h?.label === c ? 'selected' : ''}>${escapeHtml(label(c))}</option>`).join('');
  box.innerHTML = `
    <div class="label-now" id="label-now">${h
      ? `${badge(h.label)} set by <b>${escapeHtml(h.by)}</b> ${escapeHtml(when(h.at))}: ${escapeHtml(h.reason)}<br><span class="muted">classifier: ${job.result.class ? escapeHtml(label(job.result.class)) : 'no label'}; the map and the adaptive planner use the person's label</span>`
      : `<span class="muted">The classifier's label stands (${job.result.class ? escapeHtml(label(job.result.class)) : 'none'}).</span>`}</div>
    <form class="relabel" id="relabel-form" novalidate>
      <div class="rl-row">
        <div class="f"><label for="rl-label">Class</label><select name="label" id="rl-label"><option value="">—</option>${options}</select><span class="field-error" data-for="label"></span></div>
        <div class="f"><label for="rl-by">Who</label><input type="text" name="by" id="rl-by" maxlength="${BY_MAX}" value="${escapeHtml(rememberedBy())}" placeholder="your name"><span class="field-error" data-for="by"></span></div>
      </div>
      <div class="f"><label for="rl-reason">Why</label><textarea name="reason" id="rl-reason" rows="3" maxlength="${REASON_MAX}" placeholder="what in the outputs shows it"></textarea><span class="field-error" data-for="reason"></span></div>
      <div class="f rl-token" id="rl-token-row" hidden><label for="rl-token">Submit token <span class="f-hint">this server wants one; kept in this browser</span></label><input id="rl-token" type="password" autocomplete="off" value="${escapeHtml(submitToken())}"><span class="field-error" data-for="Authorization"></span></div>
      <div class="rl-actions"><button type="submit" class="primary" id="rl-save">Set label</button>${h ? '<button type="button" class="small" id="rl-clear">Remove label</button>' : ''}<span class="muted" id="rl-message"></span></div>
    </form>
    <h2 class="sub-h">Changes</h2><div id="rl-history"><p class="muted">loading…</p></div>`;
  const form = box.querySelector('#relabel-form');
  const $ = (s) => box.querySelector(s);
  submitTokenRequired().then((required) => { if (required) $('#rl-token-row').hidden = false; });
  const showErrors = (errors) => {
    for (const el of box.querySelectorAll('.field-error')) el.textContent = errors[el.dataset.for] || '';
    if (errors.Authorization) $('#rl-token-row').hidden = false;
  };
  const values = () => ({ label: $('#rl-label').value, reason: $('#rl-reason').value, by: $('#rl-by').value.trim() });
  async function send(call) {
    if (!$('#rl-token-row').hidden) setSubmitToken($('#rl-token').value.trim());
    try { localStorage.setItem(BY_KEY, $('#rl-by').value.trim()); } catch { /* private mode */ }
    $('#rl-message').textContent = 'saving…';
    try {
      await call();
      $('#rl-message').textContent = 'saved';
      delete box.dataset.key;
      reload();
    } catch (e) {
      $('#rl-message').textContent = e.message;
      if (e instanceof ApiError) {
        const errors = {};
        for (const d of e.details) errors[d.field] = d.message;
        if (e.status === 401) errors.Authorization = 'this server needs the submit token';
        if (e.status === 403) errors.Authorization = 'the token was refused';
        showErrors(errors);
      }
    }
  }
  form.addEventListener('submit', (ev) => {
    ev.preventDefault();
    const v = values();
    const errors = validateLabel(v);
    showErrors(errors);
    if (Object.keys(errors).length) return;
    send(() => api.setLabel(job.id, v));
  });
  $('#rl-clear')?.addEventListener('click', () => {
    const v = values();
    if (!v.by) { showErrors({ by: 'say who you are' }); return; }
    send(() => api.clearLabel(job.id, v.reason.trim() ? { by: v.by, reason: v.reason } : { by: v.by }));
  });
  api.labels(job.id).then((l) => { $('#rl-history').innerHTML = historyHtml(l.changes); }, (e) => {
    $('#rl-history').innerHTML = `<p class="muted">Could not load the changes: ${escapeHtml(e.message)}</p>`;
  });
}
