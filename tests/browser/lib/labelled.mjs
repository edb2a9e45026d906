// Labelled results for the browser tests, posted through the worker API of a real
// compaction-server: a worker that leases each queued job and completes it at once with a
// summary whose classification a given field decides (no simulation), so a map of known classes
// and boundaries fills in seconds through the same intake as compaction-worker's results.

const FRAMES_CSV = 'eps,stress_top,stress_bottom\n' + Array.from({ length: 10 }, (_, i) => `${(i / 100).toFixed(2)},${(i * 1e-3).toFixed(4)},${(i * 5e-4).toFixed(4)}\n`).join('');

// A multipart/form-data body as curl and compaction-worker write it: a Content-Length (a
// Buffer body, not a stream) and a CRLF after the close delimiter. Node's FormData is not used:
// node 18 (Debian 12's) streams it chunked, and ends it at the close delimiter without that CRLF,
// which the server's multipart parser (cpp-httplib 0.11) refuses (docs/service.md, "Uploads").
// A part's value is text (UTF-8) or a Buffer (binary, e.g. a .npy).
function multipart(parts) {
  const boundary = `----compaction-browser-test-${Date.now()}`;
  const chunks = [];
  for (const p of parts) {
    let head = `--${boundary}\r\nContent-Disposition: form-data; name="${p.name}"`;
    head += p.filename ? `; filename="${p.filename}"\r\nContent-Type: ${p.type}\r\n\r\n` : '\r\n\r\n';
    chunks.push(Buffer.from(head), Buffer.isBuffer(p.value) ? p.value : Buffer.from(String(p.value)), Buffer.from('\r\n'));
  }
  chunks.push(Buffer.from(`--${boundary}--\r\n`));
  return { body: Buffer.concat(chunks), contentType: `multipart/form-data; boundary=${boundary}` };
}

// A float32 .npy file (format 1.0, C order) of the given shape and values, as the engine writes
// spacetime.npy (frames x rows).
export function npyFloat32(shape, values) {
  let header = `{'descr': '<f4', 'fortran_order': False, 'shape': (${shape.join(', ')}${shape.length === 1 ? ',' : ''}), }`;
  header += ' '.repeat((64 - ((10 + header.length + 1) % 64)) % 64) + '\n'; // data 64-byte aligned
  const head = Buffer.alloc(10);
  Buffer.from([0x93, 0x4e, 0x55, 0x4d, 0x50, 0x59, 1, 0]).copy(head);
  head.writeUInt16LE(header.length, 8);
  return Buffer.concat([head, Buffer.from(header, 'latin1'), Buffer.from(Float32Array.from(values).buffer)]);
}

// verdict(scene) -> { class, confidence, runner_up, n_reflections, band_speed_ratio, and
// optionally features (more of them, over the two made here), frames (frames.csv's text) and
// files (more artifacts: [{name, value: text or Buffer}], e.g. spacetime.npy from npyFloat32) } or null
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
      ...(v.files || []).map((f) => ({ name: 'files', filename: f.name, type: 'application/octet-stream', value: f.value })),
    ]);
    const res = await fetch(`${url}/api/v1/jobs/${l.job_id}/complete`, {
      method: 'POST', body, headers: { 'Content-Type': contentType },
    });
    if (res.status !== 200) throw new Error(`complete ${l.job_id} -> ${res.status} ${await res.text()}`);
    done++;
  }
  return done;
}
