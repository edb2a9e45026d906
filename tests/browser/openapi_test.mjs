// The API description, server/openapi.yaml (read from the source tree, not from a server: the
// binary serves the copy it was built with): Redocly's linter with its recommended rules finds
// no error and no warning in it, and the answers of a real compaction-server match it. The
// server runs on loopback with a temporary database and named tokens; its content is real: a
// sweep that compaction-worker runs, a sweep whose jobs this test leases, checkpoints, resumes,
// completes and fails through the worker API with bundles of the real compaction-run, an
// adaptive sweep, the committed export studies/phase_map/results/example-c-reference.export.json
// imported, and human labels. Every answer taken is checked against the response the document
// declares for its operation and status (lib/openapi.mjs), every operation of the document is
// taken at least once, and the request bodies sent for a success are checked against the
// operation's request schema.
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { readFileSync, readdirSync, writeFileSync, mkdirSync, statSync } from 'node:fs';
import { connect } from 'node:net';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { Harness, REPO, binaries, waitFor } from './lib/harness.mjs';
import { OpenApi } from './lib/openapi.mjs';

const here = dirname(fileURLToPath(import.meta.url));
const DOC = join(REPO, 'server', 'openapi.yaml');
const EXAMPLE_EXPORT = join(REPO, 'studies', 'phase_map', 'results', 'example-c-reference.export.json');
const SUBMIT = 'openapi-submit-0123';  // the token named "ana" (role submit)
const WORKER = 'openapi-worker-4567';  // the token named "farm" (role worker)
const TINY = { cells_per_unit: 6, eps_end: 0.03 }; // well under a second a run

const api = new OpenApi(DOC);
const h = new Harness('openapi');
let base = '';
let port = 0;
const bins = binaries();
let engineVersion = '';
const taken = []; // "METHOD /path -> status (response key)" of every answer checked

before(async () => {
  const tokens = join(h.dir, 'tokens');
  writeFileSync(tokens, `submit ana ${SUBMIT}\nworker farm ${WORKER}\n`, { mode: 0o600 });
  base = await h.startServer(['--tokens', tokens]);
  port = Number(new URL(base).port);
});
after(() => h.close());

// One request; the answer with its bytes and text.
async function call(method, path, { json, body, token, headers = {} } = {}) {
  const hd = { ...headers };
  if (token) hd.Authorization = `Bearer ${token}`;
  let payload = body;
  if (json !== undefined) {
    payload = JSON.stringify(json);
    if (!Object.keys(hd).some((k) => k.toLowerCase() === 'content-type')) hd['Content-Type'] = 'application/json';
  }
  const res = await fetch(`${base}/api/v1${path}`, { method, headers: hd, body: payload });
  const bytes = Buffer.from(await res.arrayBuffer());
  return {
    method, path: new URL(`${base}/api/v1${path}`).pathname, asked: `/api/v1${path}`, status: res.status,
    contentType: res.headers.get('content-type'), headers: res.headers, bytes, text: bytes.toString('utf8'),
  };
}

// Checks an answer against the document and records it. `key`: the response that must
// describe it (its own status unless said otherwise, 'default' for the front's refusals);
// `field`: the field an error must name.
function check(a, { status, key = String(status), field } = {}) {
  assert.equal(a.status, status, `${a.method} ${a.path}: expected ${status}, got ${a.status}: ${a.text.slice(0, 400)}`);
  const got = api.checkAnswer(a);
  assert.equal(got, key, `${a.method} ${a.path} -> ${a.status} is described by ${got}, expected ${key}`);
  if (field !== undefined) assert.equal(JSON.parse(a.text).error.field, field, `${a.method} ${a.path}: ${a.text}`);
  taken.push(`${a.method} ${a.asked ?? a.path} -> ${a.status} (${got})`);
  return a;
}

// A request whose answer is checked; a JSON body sent for a success is checked first.
async function sample(method, path, opts = {}) {
  const { status, key, field, ...req } = opts;
  if (req.json !== undefined && status < 300) api.checkRequest(method, `/api/v1${path.split('?')[0]}`, req.json);
  return check(await call(method, path, req), { status, key, field });
}
const json = (a) => JSON.parse(a.text);

// A request written on a socket as it is given (for what fetch never sends: a write without
// Content-Length, a body beyond a limit the server refuses from the head); the whole answer,
// read until the server closes the connection.
function raw(text) {
  return new Promise((resolve, reject) => {
    const s = connect(port, '127.0.0.1');
    const chunks = [];
    s.setTimeout(10000, () => { s.destroy(); reject(new Error('raw request: no answer within 10 s')); });
    s.on('data', (d) => chunks.push(d));
    s.on('error', reject);
    s.on('close', () => {
      const all = Buffer.concat(chunks).toString('utf8');
      const end = all.indexOf('\r\n\r\n');
      if (end < 0) return reject(new Error(`raw request: no head in ${JSON.stringify(all.slice(0, 200))}`));
      const [statusLine, ...fields] = all.slice(0, end).split('\r\n');
      const headers = Object.fromEntries(fields.map((f) => [f.slice(0, f.indexOf(':')).toLowerCase(), f.slice(f.indexOf(':') + 1).trim()]));
      resolve({ status: Number(statusLine.split(' ')[1]), contentType: headers['content-type'], text: all.slice(end + 4) });
    });
    s.end(text);
  });
}

// A multipart/form-data body as curl and compaction-worker write it: a Content-Length and a
// CRLF after the close delimiter (lib/labelled.mjs says why node's FormData is not used).
function multipart(parts) {
  const boundary = `----openapi-test-${process.pid}-${Date.now()}`;
  const chunks = [];
  for (const p of parts) {
    let head = `--${boundary}\r\nContent-Disposition: form-data; name="${p.name}"`;
    head += p.filename ? `; filename="${p.filename}"\r\nContent-Type: ${p.type || 'application/octet-stream'}\r\n\r\n` : '\r\n\r\n';
    chunks.push(Buffer.from(head), Buffer.isBuffer(p.value) ? p.value : Buffer.from(p.value), Buffer.from('\r\n'));
  }
  chunks.push(Buffer.from(`--${boundary}--\r\n`));
  return { body: Buffer.concat(chunks), headers: { 'Content-Type': `multipart/form-data; boundary=${boundary}` } };
}

// Runs compaction-run on a leased scene as compaction-worker does (its own folder); returns the
// bundle's folder and the runner's log.
function runScene(scene, name, extra = []) {
  const dir = join(h.dir, name);
  mkdirSync(dir, { recursive: true });
  const sceneFile = join(dir, 'scene.json');
  writeFileSync(sceneFile, JSON.stringify(scene));
  const out = join(dir, 'out');
  const r = spawnSync(bins.runner, ['--scene', sceneFile, '--out', out, '--progress', 'none', ...extra], { encoding: 'utf8', timeout: 120000 });
  assert.equal(r.status, 0, `compaction-run ${name}: ${r.stderr}`);
  return { dir, out, log: r.stdout + r.stderr };
}

// The upload of a bundle as compaction-worker sends it: lease_token, summary, every file.
function bundleForm(out, token, nextLease) {
  const parts = [{ name: 'lease_token', value: token },
    { name: 'summary', filename: 'summary.json', type: 'application/json', value: readFileSync(join(out, 'summary.json')) }];
  if (nextLease) parts.push({ name: 'next_lease', value: JSON.stringify(nextLease) });
  for (const f of readdirSync(out).sort()) {
    if (statSync(join(out, f)).isFile()) parts.push({ name: 'files', filename: f, value: readFileSync(join(out, f)) });
  }
  return multipart(parts);
}

const state = {}; // ids made by one test and read by later ones

test('server/openapi.yaml lints clean with Redocly\'s recommended rules (no error, no warning)', () => {
  const cli = join(here, 'node_modules', '@redocly', 'cli');
  const pinned = JSON.parse(readFileSync(join(here, 'package.json'), 'utf8')).dependencies['@redocly/cli'];
  const installed = JSON.parse(readFileSync(join(cli, 'package.json'), 'utf8')).version;
  assert.equal(installed, pinned, 'tests/browser/node_modules is not what package.json pins: run scripts/install-browser-deps.sh');
  // redocly.yaml beside this file names the recommended ruleset, so that no other configuration
  // (a redocly.yaml in the working folder) applies.
  const r = spawnSync(process.execPath, [join(cli, 'bin', 'cli.js'), 'lint', '--config', join(here, 'redocly.yaml'), '--format', 'json', DOC], {
    encoding: 'utf8', timeout: 120000,
    env: { ...process.env, REDOCLY_TELEMETRY: 'off', REDOCLY_SUPPRESS_UPDATE_NOTICE: 'true' },
  });
  const start = r.stdout.indexOf('{');
  assert.ok(start >= 0, `redocly lint printed no report (exit ${r.status}): ${r.stdout}${r.stderr}`);
  const report = JSON.parse(r.stdout.slice(start));
  const problems = report.problems.map((p) => `${p.severity} ${p.ruleId}: ${p.message} at ${p.location?.[0]?.pointer}`).join('\n');
  assert.deepEqual(report.totals, { errors: 0, warnings: 0, ignored: 0 }, problems);
  assert.equal(r.status, 0, r.stderr);
});

test('every schema of the document compiles as JSON Schema, and the checker refuses what does not match', async () => {
  assert.ok(api.compileAll() > 100);
  // The checker has teeth: a real answer passes, the same answer altered does not.
  const health = await call('GET', '/health');
  api.checkAnswer(health);
  const altered = (f) => ({ ...health, text: JSON.stringify(f(json(health))) });
  assert.throws(() => api.checkAnswer(altered((v) => { delete v.engine_version; return v; })), /engine_version/);
  assert.throws(() => api.checkAnswer(altered((v) => ({ ...v, extra: 1 }))), /additional properties/);
  assert.throws(() => api.checkAnswer({ ...health, contentType: 'text/html' }), /text\/html is not among/);
  assert.throws(() => api.checkAnswer({ ...health, status: 201 }), /no response|own status/);
});

test('service answers: health, metrics, this document, presets, limits', async () => {
  const health = json(await sample('GET', '/health', { status: 200 }));
  engineVersion = health.engine_version;
  // Both roles have a token here (--tokens): the dashboard asks for one where it says so.
  assert.deepEqual(health.tokens, { submit: 'required', worker: 'required' });
  await sample('GET', '/metrics', { status: 200 });
  const served = await sample('GET', '/openapi.yaml', { status: 200 });
  assert.match(served.text, /^openapi: 3\.0\.3/);
  const presets = json(await sample('GET', '/presets', { status: 200 }));
  assert.deepEqual(presets.presets.map((p) => p.name), ['fast', 'default', 'reference']);
  assert.equal(presets.default, 'default');
  await sample('GET', '/limits', { status: 200 });
});

test('a sweep run by compaction-worker, its reads, and refused sweeps', async () => {
  const tiny = { name: 'tiny', S: 0.02, R: 1e-3, phi: 0.4, numerics: TINY };
  await sample('POST', '/sweeps', { json: tiny, status: 401, field: 'Authorization' });
  await sample('POST', '/sweeps', { json: tiny, token: 'wrong-token-0000', status: 403, field: 'Authorization' });
  await sample('POST', '/sweeps', { body: '{"name": ', token: SUBMIT, headers: { 'Content-Type': 'application/json' }, status: 400, field: 'body' });
  await sample('POST', '/sweeps', { body: JSON.stringify(tiny), token: SUBMIT, headers: { 'Content-Type': 'text/plain' }, status: 415, field: 'Content-Type' });
  const invalid = json(await sample('POST', '/sweeps', { json: { ...tiny, R: 2, phi: 0.9 }, token: SUBMIT, status: 422, field: 'R' }));
  assert.equal(invalid.error.details.length, 2);
  await sample('POST', '/sweeps/estimate', { json: tiny, status: 200 });
  await sample('POST', '/sweeps/estimate', { json: tiny, headers: { Origin: 'http://elsewhere.example' }, status: 403, field: 'Origin' });
  const created = json(await sample('POST', '/sweeps', { json: tiny, token: SUBMIT, status: 201 }));
  state.tinySweep = created.id;

  const worker = h.spawn('worker', bins.worker, ['--server', base, '--token', WORKER, '--runner', bins.runner, '--work-dir', join(h.dir, 'work'), '--name', 'w1', '--max-jobs', '1', '--poll-interval', '0.2', '--log-level', 'warn']);
  await waitFor(() => worker.exitCode !== null, { timeoutMs: 60000, what: 'compaction-worker to run its one job and exit' });
  assert.equal(worker.exitCode, 0, h.logs.worker);
  const jobs = json(await sample('GET', `/jobs?sweep=${state.tinySweep}`, { status: 200 }));
  assert.equal(jobs.jobs.length, 1);
  assert.equal(jobs.jobs[0].state, 'succeeded');
  state.tinyJob = jobs.jobs[0].id;

  await sample('GET', `/sweeps/${state.tinySweep}`, { status: 200 });
  await sample('GET', '/sweeps/999999', { status: 404, field: 'id' });
  await sample('GET', `/sweeps/${state.tinySweep}/plan`, { status: 409, field: 'id' });
  await sample('GET', `/sweeps/${state.tinySweep}/export`, { status: 200 });
  const csv = await sample('GET', `/sweeps/${state.tinySweep}/export?format=csv`, { status: 200 });
  assert.equal(csv.text.trim().split('\n').length, 2);
  state.archive = (await sample('GET', `/sweeps/${state.tinySweep}/export?format=archive`, { status: 200 })).text;
  await sample('GET', `/sweeps/${state.tinySweep}/export?format=xml`, { status: 422, field: 'format' });
  await sample('GET', `/sweeps/${state.tinySweep}/export?artifacts=none`, { status: 422, field: 'artifacts' });

  const detail = json(await sample('GET', `/jobs/${state.tinyJob}`, { status: 200 }));
  assert.equal(detail.result.status, 'ok');
  await sample('GET', '/jobs/999999', { status: 404, field: 'id' });
  const artifacts = json(await sample('GET', `/jobs/${state.tinyJob}/artifacts`, { status: 200 }));
  assert.ok(artifacts.artifacts.length >= 5, JSON.stringify(artifacts));
  for (const a of artifacts.artifacts) {
    const file = await sample('GET', `/jobs/${state.tinyJob}/artifacts/${a.name}`, { status: 200 });
    assert.equal(file.bytes.length, a.size, a.name);
  }
  await sample('GET', `/jobs/${state.tinyJob}/artifacts/nothing.csv`, { status: 404, field: 'name' });
});

test('the worker API: lease, heartbeat, checkpoint, release, resume, complete with the next lease, fail', async () => {
  const created = json(await sample('POST', '/sweeps', { json: { name: 'worker api', S: [0.03, 0.04], R: 1e-3, phi: 0.4, numerics: TINY }, token: SUBMIT, status: 201 }));
  state.workerSweep = created.id;
  const ask = { worker: 'openapi-test', engine_version: engineVersion };
  await sample('POST', '/leases', { json: ask, status: 401, field: 'Authorization' });
  await sample('POST', '/leases', { json: { worker: 'openapi-test' }, token: WORKER, status: 422, field: 'engine_version' });
  const first = json(await sample('POST', '/leases', { json: ask, token: WORKER, status: 200 }));
  assert.equal(first.checkpoint, null);
  await sample('POST', `/jobs/${first.job_id}/heartbeat`, { json: { lease_token: first.lease_token, eps: 0 }, token: WORKER, status: 200 });

  // A run that writes a checkpoint every millisecond of wall time: its last one (a state before
  // the run's end) is uploaded as a worker that is being stopped uploads it, then the lease is
  // given back.
  const stopped = runScene(first.scene, 'stopped', ['--checkpoint', join(h.dir, 'checkpoint.bin'), '--checkpoint-every', '0.001']);
  const marks = [...stopped.log.matchAll(/checkpoint step=(\d+) eps=([0-9.e+-]+)/g)];
  assert.ok(marks.length > 0, `the runner wrote no checkpoint: ${stopped.log}`);
  const [, step, eps] = marks[marks.length - 1];
  const bytes = readFileSync(join(h.dir, 'checkpoint.bin'));
  const upload = multipart([{ name: 'lease_token', value: first.lease_token }, { name: 'step', value: step }, { name: 'eps', value: eps },
    { name: 'checkpoint', filename: 'checkpoint.bin', value: bytes }]);
  await sample('POST', `/jobs/${first.job_id}/checkpoint`, { ...upload, token: WORKER, status: 200 });
  await sample('POST', `/jobs/${first.job_id}/checkpoint`, { body: 'x', headers: { 'Content-Type': 'application/json' }, token: WORKER, status: 415, field: 'Content-Type' });
  await sample('POST', `/jobs/${first.job_id}/release`, { json: { lease_token: first.lease_token }, token: WORKER, status: 200 });
  await sample('POST', `/jobs/${first.job_id}/heartbeat`, { json: { lease_token: first.lease_token, eps: 0.01 }, token: WORKER, status: 409, field: 'lease_token' });
  await sample('POST', '/jobs/999999/release', { json: { lease_token: first.lease_token }, token: WORKER, status: 404, field: 'id' });

  // The next lease of the job carries the checkpoint; the run goes on from it.
  const again = json(await sample('POST', '/leases', { json: ask, token: WORKER, status: 200 }));
  assert.equal(again.job_id, first.job_id);
  assert.equal(again.checkpoint.step, Number(step));
  const download = await sample('GET', `/jobs/${again.job_id}/checkpoint`, { token: WORKER, status: 200 });
  assert.ok(download.bytes.equals(bytes));
  await sample('GET', `/jobs/${again.job_id}/checkpoint`, { status: 401, field: 'Authorization' });
  writeFileSync(join(h.dir, 'downloaded.bin'), download.bytes);
  const resumed = runScene(again.scene, 'resumed', ['--resume', join(h.dir, 'downloaded.bin')]);
  await sample('POST', `/jobs/${again.job_id}/heartbeat`, { json: { lease_token: again.lease_token, eps: Number(eps), resumed: { step: Number(step), eps: Number(eps) } }, token: WORKER, status: 200 });
  const running = json(await sample('GET', `/jobs/${again.job_id}`, { status: 200 }));
  assert.equal(running.state, 'running');
  assert.equal(running.resumes.length, 1);
  assert.notEqual(running.checkpoint, null);

  const done = json(await sample('POST', `/jobs/${again.job_id}/complete`, { ...bundleForm(resumed.out, again.lease_token, ask), token: WORKER, status: 200 }));
  assert.equal(done.state, 'succeeded');
  assert.notEqual(done.next, null, 'the upload leased the sweep\'s other job');
  await sample('POST', `/jobs/${again.job_id}/complete`, { ...bundleForm(resumed.out, again.lease_token), token: WORKER, status: 409, field: 'lease_token' });
  const failed = json(await sample('POST', `/jobs/${done.next.job_id}/fail`, { json: { lease_token: done.next.lease_token, reason: 'given up by the test', retryable: false }, token: WORKER, status: 200 }));
  assert.equal(failed.state, 'failed');
  state.failedJob = done.next.job_id;
  await sample('POST', `/jobs/${done.next.job_id}/fail`, { json: { lease_token: done.next.lease_token, reason: 'again' }, token: WORKER, status: 409, field: 'lease_token' });
  await sample('GET', `/jobs/${state.failedJob}/checkpoint`, { token: WORKER, status: 404, field: 'checkpoint' });
  await sample('POST', '/leases', { json: ask, token: WORKER, status: 204 });
});

test('an adaptive sweep\'s plan, and its cancel', async () => {
  const body = { name: 'adaptive', phi: 0.4, numerics: TINY, adaptive: { S: { min: 1e-2, max: 1e-1 }, R: { min: 1e-4, max: 1e-2 }, initial: { S: 2, R: 2 }, resolution_decades: 0.5, budget: 6 } };
  const created = json(await sample('POST', '/sweeps', { json: body, token: SUBMIT, status: 201 }));
  state.adaptiveSweep = created.id;
  const plan = json(await sample('GET', `/sweeps/${created.id}/plan?limit=5`, { status: 200 }));
  assert.equal(plan.state, 'running');
  await sample('GET', `/sweeps/${created.id}/plan?limit=-1`, { status: 422, field: 'limit' });
  const queued = json(await sample('GET', `/jobs?sweep=${created.id}&state=queued`, { status: 200 }));
  state.queuedJob = queued.jobs[0].id;
  await sample('POST', `/sweeps/${created.id}/cancel`, { json: { force: true }, token: SUBMIT, status: 422, field: 'force' });
  await sample('POST', `/sweeps/${created.id}/cancel`, { body: '', headers: { 'Content-Type': 'application/json' }, token: SUBMIT, status: 200 });
  await sample('POST', '/sweeps/999999/cancel', { json: {}, token: SUBMIT, status: 404, field: 'id' });
  assert.equal(json(await sample('GET', `/sweeps/${created.id}/plan`, { status: 200 })).state, 'cancelled');
});

test('imports: the committed example export, this server\'s own export again, a truncated file', async () => {
  const example = readFileSync(EXAMPLE_EXPORT, 'utf8');
  await sample('POST', '/imports', { body: example, headers: { 'Content-Type': 'application/json' }, status: 401, field: 'Authorization' });
  api.checkRequest('POST', '/api/v1/imports', JSON.parse(example));
  const outcome = json(await sample('POST', '/imports', { body: example, headers: { 'Content-Type': 'application/json' }, token: SUBMIT, status: 200 }));
  assert.equal(outcome.changed, true);
  assert.ok(outcome.added > 0);
  state.importedSweep = outcome.sweep_id;
  api.checkRequest('POST', '/api/v1/imports', JSON.parse(state.archive));
  const own = json(await sample('POST', '/imports', { body: state.archive, headers: { 'Content-Type': 'application/json' }, token: SUBMIT, status: 200 }));
  assert.equal(own.changed, false);
  await sample('POST', '/imports', { body: example.slice(0, 1000), headers: { 'Content-Type': 'application/json' }, token: SUBMIT, status: 422, field: 'file' });
});

test('human labels: set, read, clear, the audit, and refused changes', async () => {
  const imported = json(await sample('GET', `/jobs?sweep=${state.importedSweep}&limit=2`, { status: 200 }));
  const [kept, cleared] = imported.jobs.map((j) => j.id);
  state.importedJob = kept;
  const label = { label: 'c', reason: 'a reflection the classifier missed\n(checked by eye)', by: 'ana' };
  await sample('PUT', `/jobs/${kept}/label`, { json: label, status: 401, field: 'Authorization' });
  await sample('PUT', `/jobs/${kept}/label`, { json: label, token: SUBMIT, status: 200 });
  await sample('PUT', `/jobs/${cleared}/label`, { json: { ...label, label: 'f' }, token: SUBMIT, status: 200 });
  await sample('DELETE', `/jobs/${cleared}/label`, { json: { by: 'ana', reason: 'a second look' }, token: SUBMIT, status: 200 });
  await sample('DELETE', `/jobs/${cleared}/label`, { json: { by: 'ana' }, token: SUBMIT, status: 404, field: 'label' });
  await sample('PUT', `/jobs/${kept}/label`, { json: { ...label, label: 'z' }, token: SUBMIT, status: 422, field: 'label' });
  await sample('PUT', `/jobs/${state.queuedJob}/label`, { json: label, token: SUBMIT, status: 409, field: 'id' });
  await sample('PUT', '/jobs/999999/label', { json: label, token: SUBMIT, status: 404, field: 'id' });
  const labels = json(await sample('GET', `/jobs/${kept}/label`, { status: 200 }));
  assert.equal(labels.human_label.token, 'submit:ana');
  await sample('GET', `/jobs/${state.queuedJob}/label`, { status: 200 });
  await sample('GET', '/jobs/999999/label', { status: 404, field: 'id' });
  const audit = json(await sample('GET', '/labels/audit', { status: 200 }));
  assert.deepEqual(audit.changes.map((c) => c.action).slice(0, 3), ['cleared', 'set', 'set']);
  await sample('GET', `/labels/audit?job=${cleared}&limit=1&offset=1`, { status: 200 });
  await sample('GET', '/labels/audit?limit=0', { status: 422, field: 'limit' });
});

test('the polled reads over all of it, with their ETags', async () => {
  for (const path of ['/sweeps', '/jobs', '/phase-map?phi=0.4', '/phase-map/regions?phi=0.4&grid=16']) {
    const first = await sample('GET', path, { status: 200 });
    const tag = first.headers.get('etag');
    assert.ok(tag, `${path} has no ETag`);
    await sample('GET', path, { headers: { 'If-None-Match': tag }, status: 304 });
  }
  const sweeps = json(await sample('GET', '/sweeps?limit=10&offset=0', { status: 200 }));
  assert.ok(sweeps.sweeps.some((s) => s.imported !== null) && sweeps.sweeps.some((s) => s.state === 'cancelled'));
  await sample('GET', `/sweeps/${state.importedSweep}`, { status: 200 });
  await sample('GET', `/sweeps/${state.importedSweep}/export`, { status: 200 });
  const importedJob = json(await sample('GET', `/jobs/${state.importedJob}`, { status: 200 }));
  assert.notEqual(importedJob.result.origin, null);
  assert.notEqual(importedJob.human_label, null);
  await sample('GET', `/jobs/${state.failedJob}`, { status: 200 });
  await sample('GET', `/jobs/${state.queuedJob}/artifacts`, { status: 200 });
  await sample('GET', '/jobs?state=failed&phi=0.4', { status: 200 });
  await sample('GET', '/jobs?state=lost', { status: 422, field: 'state' });
  await sample('GET', '/sweeps?limit=5000', { status: 422, field: 'limit' });
  const map = json(await sample('GET', '/phase-map?phi=0.4', { status: 200 }));
  assert.ok(map.points.some((p) => p.human_label === 'c') && map.points.some((p) => p.state === 'cancelled'));
  await sample('GET', `/phase-map?phi=0.4&sweep=${state.tinySweep}&cells_per_unit=6`, { status: 200 });
  await sample('GET', '/phase-map', { status: 422, field: 'phi' });
  const regions = json(await sample('GET', '/phase-map/regions?phi=0.4&grid=8', { status: 200 }));
  assert.ok(regions.runs > 0);
  await sample('GET', '/phase-map/regions?phi=0.3', { status: 200 }); // no run at 0.3: the empty answer
  await sample('GET', '/phase-map/regions?phi=0.9', { status: 422, field: 'phi' });
});

test('refusals the connection front answers from the head are the document\'s default answer', async () => {
  const host = `Host: 127.0.0.1:${port}\r\n`;
  const noLength = await raw(`POST /api/v1/sweeps HTTP/1.1\r\n${host}Authorization: Bearer ${SUBMIT}\r\nContent-Type: application/json\r\n\r\n`);
  check({ method: 'POST', path: '/api/v1/sweeps', ...noLength }, { status: 411, key: 'default', field: 'Content-Length' });
  const big = '{' + ' '.repeat(8000) + '}';
  const tooLarge = await raw(`POST /api/v1/sweeps/${state.tinySweep}/cancel HTTP/1.1\r\n${host}Authorization: Bearer ${SUBMIT}\r\nContent-Type: application/json\r\nContent-Length: ${big.length}\r\n\r\n${big}`);
  check({ method: 'POST', path: `/api/v1/sweeps/${state.tinySweep}/cancel`, ...tooLarge }, { status: 413, key: 'default', field: 'body' });
  const badHead = await raw(`GET /api/v1/health HTTP/1.1\r\n${host}${host}\r\n`);
  check({ method: 'GET', path: '/api/v1/health', ...badHead }, { status: 400, key: 'default', field: 'Host' });
});

test('every operation of the document was taken', () => {
  const missing = api.operations().filter((o) => !api.seen.has(o.id)).map((o) => `${o.method} ${o.path} (${o.id})`);
  assert.deepEqual(missing, [], `operations no answer was checked for:\n${missing.join('\n')}`);
  console.log(`${taken.length} answers checked against server/openapi.yaml:\n  ${taken.join('\n  ')}`);
});
