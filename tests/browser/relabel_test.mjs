// A person disagrees with the classifier, in real headless Chromium against a real
// compaction-server (with a submit token) and compaction-worker: the run page's "Human label"
// card refuses an empty reason next to its field, asks for the token the server wants, then sets
// the label; the classifier's label stays on the page; the phase map draws the run in the
// person's class with the mark at its centre and shows both labels in the tooltip; the audit page
// lists the change; the label is removed again from the run page. Screenshots go to
// $BROWSER_ARTIFACTS_DIR.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { Harness, artifactsDir, canvasBox, waitFor } from './lib/harness.mjs';

async function shot(page, name) {
  const path = join(artifactsDir(), `${name}.png`);
  await page.screenshot({ path, fullPage: true });
  console.log(`# screenshot ${path}`);
}

const TOKEN = 'relabel-secret';

test('a relabel through the run page shows on the map and in the audit', { timeout: 200000 }, async () => {
  const h = new Harness('relabel');
  try {
    await h.startServer(['--submit-token', TOKEN]);
    h.startWorker('w1');
    const res = await fetch(`${h.url}/api/v1/sweeps`, {
      method: 'POST', headers: { 'Content-Type': 'application/json', Authorization: `Bearer ${TOKEN}` },
      body: JSON.stringify({ name: 'relabel', points: [{ S: 0.05, R: 1e-3, phi: 0.4 }], numerics: { cells_per_unit: 6, eps_end: 0.03 } }),
    });
    assert.equal(res.status, 201);
    const sweep = await res.json();
    const job = await waitFor(async () => {
      const { json } = await h.api(`/jobs?sweep=${sweep.id}`);
      return json.jobs[0]?.state === 'succeeded' ? json.jobs[0] : null;
    }, { timeoutMs: 120000, what: 'the run' });
    const classifier = job.result.class;
    const mine = ['a', 'b', 'c', 'd', 'e', 'f'].find((c) => c !== classifier);

    const page = await h.browser();
    await page.goto(`${h.url}/#/run/${job.id}`);
    await page.locator('#relabel-form').waitFor();
    // The form's own check: no reason.
    await page.locator('#rl-label').selectOption(mine);
    await page.locator('#rl-by').fill('ana');
    await page.locator('#rl-save').click();
    await waitFor(async () => /say why/.test(await page.locator('.field-error[data-for="reason"]').innerText()), { what: 'the reason error' });
    // The server wants its token: asked for at the token field.
    await page.locator('#rl-reason').fill('the band reflects twice in the space-time map');
    await page.locator('#rl-save').click();
    await waitFor(async () => /submit token/.test(await page.locator('.field-error[data-for="Authorization"]').innerText()), { what: 'the token error' });
    assert.equal(await page.locator('#rl-token-row').isVisible(), true);
    await page.locator('#rl-token').fill(TOKEN);
    await page.locator('#rl-save').click();
    await waitFor(async () => /set by ana/.test(await page.locator('#label-now').innerText()), { what: 'the label shown' });
    assert.match(await page.locator('#label-now').innerText(), new RegExp(`classifier: ${classifier ? `${classifier} ·` : "no label"}`));
    await waitFor(async () => /ana/.test(await page.locator('#rl-history').innerText()), { what: 'the change listed' });
    const stored = (await h.api(`/jobs/${job.id}`)).json;
    assert.equal(stored.human_label.label, mine);
    assert.equal(stored.result.class, classifier, 'the classifier label stays');
    await shot(page, '40-run-human-label');

    // The map: the person's class, the mark at the centre, both labels in the tooltip.
    await page.goto(`${h.url}/#/map?phi=0.4`);
    const state = await waitFor(() => page.evaluate(() => window.__dashboard?.phaseMap?.count === 1 && window.__dashboard.phaseMap), { what: 'the map' });
    const p = state.points[0];
    assert.equal(p.cat, mine, 'drawn in the person\'s class');
    const centre = await page.evaluate(({ x, y }) => {
      const c = document.querySelector('#map-plot canvas');
      const dpr = c.width / c.clientWidth;
      return Array.from(c.getContext('2d').getImageData(Math.round(x * dpr), Math.round(y * dpr), 1, 1).data.slice(0, 3));
    }, p);
    assert.ok(centre.every((v) => v < 40), `the mark is black at the centre: ${centre}`);
    const box = await canvasBox(page, '#map-plot canvas');
    await page.mouse.move(box.x + p.x, box.y + p.y);
    await waitFor(async () => /set by a person/.test(await page.locator('#tooltip').innerText()), { what: 'the tooltip' });
    assert.match(await page.locator('#tooltip').innerText(), /classifier/);
    await shot(page, '41-map-human-label');

    // The audit page.
    await page.goto(`${h.url}/#/labels`);
    await waitFor(async () => /1 change/.test(await page.locator('#audit-box').innerText()), { what: 'the audit' });
    assert.match(await page.locator('#audit-box').innerText(), /ana[\s\S]*run \d+[\s\S]*set/);
    await shot(page, '42-label-audit');

    // Removed from the run page: the classifier's label stands again.
    await page.goto(`${h.url}/#/run/${job.id}`);
    await page.locator('#rl-clear').click();
    await waitFor(async () => /classifier's label stands/.test(await page.locator('#label-now').innerText()), { what: 'the label removed' });
    const audit = (await h.api('/labels/audit')).json;
    assert.equal(audit.total, 2);
    assert.equal(audit.changes[0].action, 'cleared');
    assert.deepEqual(h.pageErrors.filter((e) => !/401/.test(e)), [], 'no errors in the page besides the refused request');
  } finally {
    await h.close();
  }
});
