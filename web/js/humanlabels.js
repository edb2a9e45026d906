// Human labels on the phase map: a run a person labelled is drawn in the colour and shape of the
// person's class (classes.js: category), with this mark in its middle, and its tooltip shows the
// classifier's label beside the person's (docs/dashboard.md, "Human labels").
import { CLASSES, label } from './classes.js';
import { escapeHtml } from './format.js';

// A white-rimmed black dot at the marker's centre: visible on every class colour.
export function drawHumanMark(ctx, x, y, r) {
  const m = Math.max(1.5, r * 0.38);
  ctx.beginPath();
  ctx.arc(x, y, m, 0, 2 * Math.PI);
  ctx.fillStyle = '#000';
  ctx.fill();
  ctx.lineWidth = 1;
  ctx.strokeStyle = '#fff';
  ctx.stroke();
}

// Tooltip rows of a point with a human label: the person's class and the classifier's.
export function humanTipRows(p) {
  if (!p.human_label) return [];
  const dot = (c) => (CLASSES[c] ? `<span class="dot" style="background:${CLASSES[c].color}"></span>` : '');
  return [
    ['set by a person', `${dot(p.human_label)}${escapeHtml(label(p.human_label))} ●`],
    ['classifier', p.class ? `${dot(p.class)}${escapeHtml(label(p.class))}` : '—'],
  ];
}
