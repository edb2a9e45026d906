// The audit of human labels (#/labels): every change, newest first, with who made it, when,
// the label before and the classifier's, and why; each run linked.
import { api } from '../api.js';
import { escapeHtml, when } from '../format.js';

export function mount(root) {
  let alive = true;
  root.innerHTML = `
    <div class="page-head"><h1>Human labels</h1>
      <p class="sub">Labels people set on runs beside the classifier's, and every change (GET /api/v1/labels/audit).</p></div>
    <section class="card"><div id="audit-box"><p class="muted">loading…</p></div></section>`;
  const box = root.querySelector('#audit-box');
  api.labelAudit(500).then((a) => {
    if (!alive) return;
    if (!a.changes.length) { box.innerHTML = '<p class="muted">Nobody has set a label yet.</p>'; return; }
    const rows = a.changes.map((c) => `<tr data-job="${c.job_id}"><td>${escapeHtml(when(c.at))}</td><td>${escapeHtml(c.by)}</td>
      <td><a href="#/run/${c.job_id}">run ${c.job_id}</a></td><td>${escapeHtml(c.action)}</td>
      <td>${escapeHtml(c.label ?? '—')}</td><td>${escapeHtml(c.previous_label ?? '—')}</td><td>${escapeHtml(c.classifier_label ?? '—')}</td>
      <td>${escapeHtml(c.reason)}</td></tr>`);
    box.innerHTML = `<p class="muted">${a.total} change${a.total === 1 ? '' : 's'}${a.total > a.changes.length ? `, the newest ${a.changes.length} shown` : ''}.</p>
      <table class="kv audit"><tr><th>when</th><th>who</th><th>run</th><th>action</th><th>label</th><th>before</th><th>classifier</th><th>why</th></tr>${rows.join('')}</table>`;
  }, (e) => { if (alive) box.innerHTML = `<p class="muted">Could not load the audit: ${escapeHtml(e.message)}</p>`; });
  return () => { alive = false; };
}
