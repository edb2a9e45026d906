// The run page of a real run (real compaction-server and compaction-worker, Debian's headless
// chromium): the movie player (the slider changes the frame, the strain shown and the picture;
// play advances it), the snapshot drawn with axes and the colour bar at a readable size, the
// bottom plate's curve visible over the top one's, the space-time map empty (not the colour of
// zero rate) above the top plate, and a page no wider than the window.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { Harness, artifactsDir, waitFor } from './lib/harness.mjs';

// A run of a second or two: 5 cells per unit cell to eps = 0.06, a movie frame every 0.01.
const SWEEP = {
  name: 'run page test', S: 0.05, R: 1e-3, phi: 0.4,
  numerics: { preset: 'fast', cells_per_unit: 5, eps_end: 0.06, snapshot_eps: [0.02], movie_d_eps: 0.01 },
};

async function shot(page, name) {
  const path = join(artifactsDir(), `${name}.png`);
  await page.screenshot({ path, fullPage: true });
  console.log(`screenshot: ${path}`);
}

test('the run page plays the movie and draws its figures readably', { timeout: 180000 }, async () => {
  const h = new Harness('run-page');
  try {
    await h.startServer();
    h.startWorker();
    const created = await h.api('/sweeps', SWEEP);
    assert.equal(created.status, 201, JSON.stringify(created.json));
    const jobId = await waitFor(async () => {
      const { json } = await h.api('/jobs?state=succeeded');
      return json.jobs[0]?.id;
    }, { timeoutMs: 120000, intervalMs: 300, what: 'the run to succeed' });
    const artifacts = (await h.api(`/jobs/${jobId}/artifacts`)).json.artifacts.map((a) => a.name);
    assert.ok(artifacts.includes('movie.bin'), `artifacts ${artifacts}`);

    const page = await h.browser();
    await page.goto(`${h.url}/#/run/${jobId}`);
    await page.waitForSelector('#movie-canvas');
    await page.waitForSelector('#snap-canvas');

    // --- Movie: 6 frames, the first shown; End moves the slider to the last: another strain,
    // another picture, the plate lower.
    const state = () => page.evaluate(() => {
      const c = document.querySelector('#movie-canvas');
      const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
      let hash = 0, drawn = 0;
      for (let i = 0; i < d.length; i += 4) {
        if (d[i + 3]) drawn++;
        hash = (hash * 31 + d[i] * 7 + d[i + 1] * 3 + d[i + 2] + d[i + 3]) >>> 0;
      }
      return {
        frames: Number(c.dataset.frames), frame: Number(c.dataset.frame), hash, drawn,
        label: document.querySelector('#movie-eps').textContent,
        slider: document.querySelector('#movie-slider').value,
        plate: document.querySelector('#card-movie .plate-line').getAttribute('d'),
      };
    });
    const first = await state();
    assert.equal(first.frames, 6, JSON.stringify(first));
    assert.equal(first.frame, 0);
    assert.match(first.label, /ε = 0\.010\b.*frame 1 of 6/);
    assert.ok(first.drawn > 1000, `particles drawn: ${first.drawn}`);
    await page.focus('#movie-slider');
    await page.keyboard.press('End');
    const last = await state();
    assert.equal(last.frame, 5, JSON.stringify(last));
    assert.equal(last.slider, '5');
    assert.match(last.label, /ε = 0\.060\b.*frame 6 of 6/);
    assert.notEqual(last.hash, first.hash, 'the picture changes with the frame');
    assert.notEqual(last.plate, first.plate, 'the plate line moves down');
    await page.keyboard.press('ArrowLeft');
    assert.equal((await state()).frame, 4);
    assert.match((await state()).label, /ε = 0\.050\b/);
    // Play from the last frame starts again at the first and advances.
    await page.click('#movie-play');
    await waitFor(async () => (await state()).frame >= 2, { timeoutMs: 10000, what: 'play to advance the frames' });
    await page.click('#movie-play');  // pause
    const paused = (await state()).frame;
    await new Promise((r) => setTimeout(r, 500));
    assert.equal((await state()).frame, paused, 'pause stops the movie');

    // --- Snapshot: a figure with axes and the colour bar, 420 px of plot height (the picture
    // was shrunk to 80 px wide).
    const snap = await page.evaluate(() => {
      const c = document.querySelector('#snap-canvas');
      const card = document.querySelector('#card-snapshot');
      return {
        h: c.getBoundingClientRect().height, w: c.getBoundingClientRect().width,
        ticks: card.querySelectorAll('text.ticklabel').length,
        colorbar: card.querySelectorAll('.colorbar').length,
        labels: [...card.querySelectorAll('text.axislabel')].map((t) => t.textContent),
      };
    });
    assert.ok(snap.h >= 400 && snap.w >= 80, JSON.stringify(snap));
    assert.ok(snap.ticks >= 6, JSON.stringify(snap));
    assert.equal(snap.colorbar, 1, JSON.stringify(snap));
    assert.ok(snap.labels.some((t) => t.includes('height')), JSON.stringify(snap));

    // --- Stress: the bottom plate drawn over the top one and dashed, so equal stresses show both.
    const stress = await page.evaluate(() => {
      const top = document.querySelector('#stress-fig path[data-series="top"]');
      const bottom = document.querySelector('#stress-fig path[data-series="bottom"]');
      return {
        after: Boolean(top.compareDocumentPosition(bottom) & Node.DOCUMENT_POSITION_FOLLOWING),
        dash: getComputedStyle(bottom).strokeDasharray,
      };
    });
    assert.ok(stress.after, 'the bottom curve is drawn after the top one');
    assert.notEqual(stress.dash, 'none');

    // --- Space-time map: at the last frame the rows above the plate (y/h0 > 0.94) are empty
    // (transparent: the plot's background), the rows below it are drawn.
    const st = await page.evaluate(() => {
      const c = document.querySelector('#st-canvas');
      const alpha = (fx, fy) => c.getContext('2d').getImageData(Math.floor(fx * (c.width - 1)), Math.floor(fy * (c.height - 1)), 1, 1).data[3];
      return { above: alpha(0.99, 0.01), below: alpha(0.99, 0.5), plate: Boolean(document.querySelector('#st-plate')) };
    });
    assert.equal(st.above, 0, 'above the plate: no colour');
    assert.equal(st.below, 255, 'in the specimen: coloured');
    assert.ok(st.plate, 'the plate line is drawn on the map');

    // --- The classification card fits its column and the page its window.
    const fit = await page.evaluate(() => {
      const card = document.querySelector('#card-class');
      return { page: document.documentElement.scrollWidth, window: window.innerWidth, card: card.scrollWidth - card.clientWidth, long: /\d\.\d{7,}/.test(card.innerText) };
    });
    assert.ok(fit.page <= fit.window, JSON.stringify(fit));
    assert.ok(fit.card <= 1, JSON.stringify(fit));
    assert.equal(fit.long, false, 'no number printed to more than 6 decimals');

    await shot(page, 'run-page');
    assert.deepEqual(h.pageErrors, []);
  } finally {
    await h.close();
  }
});
