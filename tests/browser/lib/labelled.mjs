// Labelled results for the browser tests, posted through the worker API of a real
// compaction-server: a worker that leases each queued job and completes it at once with a
// summary whose classification a given field decides (no simulation), so a map of known classes
// and boundaries fills in seconds through the same intake as compaction-worker's results.

const FRAMES_CSV = 'eps,stress_top,stress_bottom\n' + Array.from({ length: 10 }, (_, i) => `${(i / 100).toFixed(2)},${(i * 1e-3).toFixed(4)},${(i * 5e-4).toFixed(4)}\n`).join('');

// verdict(scene) -> { class, confidence, runner_up, n_reflections, band_speed_ratio } or null
// (an unclassified run: class null, the other numbers kept). Completes every job queued for
// the server's engine; returns the number completed.
export async function completeAll(url, verdict, { worker = 'labeller' } = {}) {
  const health = await (await fetch(`${url}/api/v1/health`)).json();
  let done = 0;
  for (;;) {
    const lease = await fetch(`${url}/api/v1/leases`, {
      method: 'POST', headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify({ worker, engine_version: health.engine_version }),
    });
    if (lease.status === 204) return done;
    if (lease.status !== 200) throw new Error(`lease -> ${lease.status} ${await lease.text()}`);
    const l = await lease.json();
    const v = verdict(l.scene);
    const classification = {
      class: v.class, confidence: v.confidence ?? null, runner_up: v.runner_up ?? null,
      n_reflections: v.n_reflections ?? null, band_speed_ratio: v.band_speed_ratio ?? null,
      features: { band_speed_ratio: v.band_speed_ratio ?? null, band_speed_error: v.band_speed_ratio ? 0.05 * v.band_speed_ratio : null },
    };
    const summary = {
      status: 'ok', params: l.scene, engine_version: health.engine_version, source_revision: 'browser-test',
      eps_reached: l.scene.eps_end, wall_seconds: 0.01, classification,
    };
    const form = new FormData();
    form.append('lease_token', l.lease_token);
    form.append('summary', new Blob([JSON.stringify(summary)], { type: 'application/json' }), 'summary.json');
    form.append('files', new Blob([FRAMES_CSV], { type: 'text/csv' }), 'frames.csv');
    // Serialised first, so the upload carries a Content-Length as compaction-worker's does:
    // node 18's fetch (Debian 12's node) streams a FormData body chunked, which the server
    // refuses as malformed.
    const encoded = new Response(form);
    const body = await encoded.arrayBuffer();
    const res = await fetch(`${url}/api/v1/jobs/${l.job_id}/complete`, {
      method: 'POST', body, headers: { 'Content-Type': encoded.headers.get('Content-Type') },
    });
    if (res.status !== 200) throw new Error(`complete ${l.job_id} -> ${res.status} ${await res.text()}`);
    done++;
  }
}
