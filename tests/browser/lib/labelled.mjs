// Labelled results for the browser tests, posted through the worker API of a real
// compaction-server: a worker that leases each queued job and completes it at once with a
// summary whose classification a given field decides (no simulation), so a map of known classes
// and boundaries fills in seconds through the same intake as compaction-worker's results.

const FRAMES_CSV = 'eps,stress_top,stress_bottom\n' + Array.from({ length: 10 }, (_, i) => `${(i / 100).toFixed(2)},${(i * 1e-3).toFixed(4)},${(i * 5e-4).toFixed(4)}\n`).join('');

// A multipart/form-data body as curl and compaction-worker write it: a Content-Length (a
// string body, not a stream) and a CRLF after the close delimiter. Node's FormData is not used:
// node 18 (Debian 12's) streams it chunked, and ends it at the close delimiter without that CRLF,
// which the server's multipart parser (cpp-httplib 0.11) refuses (docs/service.md, "Uploads").
function multipart(parts) {
  const boundary = `----compaction-browser-test-${Date.now()}`;
  let body = '';
  for (const p of parts) {
    body += `--${boundary}\r\nContent-Disposition: form-data; name="${p.name}"`;
    body += p.filename ? `; filename="${p.filename}"\r\nContent-Type: ${p.type}\r\n\r\n` : '\r\n\r\n';
    body += `${p.value}\r\n`;
  }
  body += `--${boundary}--\r\n`;
  return { body, contentType: `multipart/form-data; boundary=${boundary}` };
}

// verdict(scene) -> { class, confidence, runner_up, n_reflections, band_speed_ratio, and
// optionally features (more of them, over the two made here) and frames (frames.csv's text) } or null
// (an unclassified run: class null, the other numbers kept). Completes every job queued for
// the server's engine (most: at most that many, in the queue's order); returns the number completed.
export async function completeAll(url, verdict, { worker = 'labeller', most = Infinity } = {}) {
  const health = await (await fetch(`${url}/api/v1/health`)).json();
  let done = 0;
  while (done < most) {
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
      features: { band_speed_ratio: v.band_speed_ratio ?? null, band_speed_error: v.band_speed_ratio ? 0.05 * v.band_speed_ratio : null, ...(v.features || {}) },
    };
    const summary = {
      status: 'ok', params: l.scene, engine_version: health.engine_version, source_revision: 'browser-test',
      eps_reached: l.scene.eps_end, wall_seconds: 0.01, classification,
    };
    const { body, contentType } = multipart([
      { name: 'lease_token', value: l.lease_token },
      { name: 'summary', filename: 'summary.json', type: 'application/json', value: JSON.stringify(summary) },
      { name: 'files', filename: 'frames.csv', type: 'text/csv', value: v.frames ?? FRAMES_CSV },
    ]);
    const res = await fetch(`${url}/api/v1/jobs/${l.job_id}/complete`, {
      method: 'POST', body, headers: { 'Content-Type': contentType },
    });
    if (res.status !== 200) throw new Error(`complete ${l.job_id} -> ${res.status} ${await res.text()}`);
    done++;
  }
  return done;
}
