// Helpers of the browser tests and the render benchmark: a real compaction-server and
// compaction-worker on loopback with a temporary database, and Debian's headless chromium driven
// by playwright-core (never a downloaded browser). Every process started here is killed by pid
// when the test ends, also on failure (see Harness.close and the exit hooks).
import { spawn } from 'node:child_process';
import { mkdtempSync, mkdirSync, readFileSync, rmSync, existsSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { setTimeout as sleep } from 'node:timers/promises';

const here = dirname(fileURLToPath(import.meta.url));
export const REPO = resolve(here, '../../..');
export const WEB_DIR = process.env.COMPACTION_WEB_DIR || join(REPO, 'web');
export const CHROMIUM = process.env.CHROMIUM || '/usr/bin/chromium';

// Binaries: from CMake ($<TARGET_FILE:...>) through the environment, else build/bin.
export function binaries() {
  const dir = process.env.COMPACTION_BIN_DIR || join(REPO, 'build', 'bin');
  return {
    server: process.env.COMPACTION_SERVER || join(dir, 'compaction-server'),
    worker: process.env.COMPACTION_WORKER || join(dir, 'compaction-worker'),
    runner: process.env.COMPACTION_RUN || join(dir, 'compaction-run'),
  };
}

// Where screenshots go: $BROWSER_ARTIFACTS_DIR, else a fixed folder under the system temp dir.
export function artifactsDir() {
  const d = process.env.BROWSER_ARTIFACTS_DIR || join(tmpdir(), 'compaction-browser-artifacts');
  mkdirSync(d, { recursive: true });
  return d;
}

const live = new Set(); // child processes not yet reaped
function killAll() {
  for (const p of live) { try { p.kill('SIGKILL'); } catch { /* gone */ } }
}
process.on('exit', killAll);
for (const sig of ['SIGINT', 'SIGTERM']) process.on(sig, () => { killAll(); process.exit(130); });

// Polls fn() until it returns a truthy value or the deadline passes (then throws `what`).
export async function waitFor(fn, { timeoutMs = 10000, intervalMs = 100, what = 'condition' } = {}) {
  const deadline = Date.now() + timeoutMs;
  let last;
  for (;;) {
    try { const v = await fn(); if (v) return v; } catch (e) { last = e; }
    if (Date.now() > deadline) throw new Error(`timed out after ${timeoutMs} ms waiting for ${what}${last ? ` (last error: ${last.message})` : ''}`);
    await sleep(intervalMs);
  }
}

// The page box of a canvas the page may be redrawing. A redraw replaces the canvas, and a box
// asked for while the old one is gone is null, so ask until one is laid out.
export const canvasBox = (page, selector) =>
  waitFor(() => page.locator(selector).first().boundingBox(), { what: `the box of ${selector}` });

export class Harness {
  constructor(name) {
    this.dir = mkdtempSync(join(tmpdir(), `compaction-browser-${name}-`));
    this.procs = [];
    this.logs = {};
    this.context = null;
  }

  spawn(tag, cmd, args) {
    if (!existsSync(cmd)) throw new Error(`${cmd} not found: build it or set COMPACTION_BIN_DIR`);
    const p = spawn(cmd, args, { stdio: ['ignore', 'pipe', 'pipe'] });
    this.logs[tag] = '';
    const keep = (b) => { this.logs[tag] = (this.logs[tag] + b.toString()).slice(-20000); };
    p.stdout.on('data', keep);
    p.stderr.on('data', keep);
    live.add(p);
    p.on('exit', () => live.delete(p));
    this.procs.push(p);
    return p;
  }

  async startServer(extra = []) {
    const bins = binaries();
    const portFile = join(this.dir, 'port');
    this.server = this.spawn('server', bins.server, ['--db', join(this.dir, 'compaction.db'), '--port', '0', '--port-file', portFile, '--web-dir', WEB_DIR, '--log-level', 'warn', ...extra]);
    const port = await waitFor(() => {
      if (this.server.exitCode !== null) throw new Error(`server exited ${this.server.exitCode}: ${this.logs.server}`);
      const t = existsSync(portFile) ? readFileSync(portFile, 'utf8').trim() : '';
      return /^\d+$/.test(t) && Number(t) > 0 ? Number(t) : null;
    }, { timeoutMs: 15000, what: 'the server port file' });
    this.url = `http://127.0.0.1:${port}`;
    await waitFor(async () => (await fetch(`${this.url}/api/v1/health`)).ok, { timeoutMs: 10000, what: 'server health' });
    return this.url;
  }

  // extra: more flags of compaction-worker (e.g. --max-jobs 2: it exits after two runs).
  startWorker(name = 'w1', extra = []) {
    const bins = binaries();
    return this.spawn(`worker-${name}`, bins.worker, ['--server', this.url, '--runner', bins.runner, '--work-dir', join(this.dir, `work-${name}`), '--name', name, '--poll-interval', '0.2', '--log-level', 'warn', ...extra]);
  }

  async api(path, body) {
    const res = await fetch(`${this.url}/api/v1${path}`, body === undefined ? {} : { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) });
    const text = await res.text();
    return { status: res.status, json: text ? JSON.parse(text) : null };
  }

  // A fresh chromium profile in the temp folder; returns a page with console errors collected.
  async browser({ width = 1440, height = 1000 } = {}) {
    const { chromium } = await import('playwright-core');
    this.context = await chromium.launchPersistentContext(join(this.dir, 'profile'), {
      executablePath: CHROMIUM,
      headless: true,
      viewport: { width, height },
      deviceScaleFactor: 1,
      args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
        '--disable-component-update', '--disable-sync', '--disable-dev-shm-usage'],
      timeout: 30000,
    });
    this.context.setDefaultTimeout(15000);
    const page = this.context.pages()[0] || (await this.context.newPage());
    this.pageErrors = [];
    page.on('pageerror', (e) => this.pageErrors.push(`pageerror: ${e.message}`));
    page.on('console', (m) => { if (m.type() === 'error') this.pageErrors.push(`console: ${m.text()}`); });
    return page;
  }

  async close() {
    if (this.context) { try { await Promise.race([this.context.close(), sleep(10000)]); } catch { /* already gone */ } }
    for (const p of this.procs) if (p.exitCode === null && p.signalCode === null) p.kill('SIGTERM');
    const deadline = Date.now() + 5000;
    while (this.procs.some((p) => p.exitCode === null && p.signalCode === null) && Date.now() < deadline) await sleep(50);
    for (const p of this.procs) if (p.exitCode === null && p.signalCode === null) p.kill('SIGKILL');
    if (!process.env.COMPACTION_KEEP_BROWSER) rmSync(this.dir, { recursive: true, force: true });
  }
}
