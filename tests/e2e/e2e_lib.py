"""Helpers of the end-to-end tests: real compaction-server and compaction-worker processes on
loopback with a temporary database. Every process started here is killed at exit (by pid)."""
import atexit
import json
import os
import shutil
import signal
import sqlite3
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

_procs = []


def _cleanup():
    for p in _procs:
        if p.poll() is None:
            p.kill()
            p.wait()


atexit.register(_cleanup)
signal.signal(signal.SIGTERM, lambda *_: sys.exit(1))


def fail(message):
    print("FAIL: " + message, file=sys.stderr)
    sys.exit(1)


def check(condition, message):
    if not condition:
        fail(message)


class Env:
    """A temp folder, the binaries' folder, a server and its workers."""

    def __init__(self, bin_dir, name):
        self.bin = bin_dir
        self.dir = tempfile.mkdtemp(prefix="compaction-e2e-%s-" % name)
        atexit.register(self._remove)
        self.db = os.path.join(self.dir, "data", "compaction.db")
        self.server = None
        self.port = None
        self.workers = []

    def _remove(self):
        if os.environ.get("COMPACTION_KEEP_E2E"):
            print("kept " + self.dir)
        else:
            shutil.rmtree(self.dir, ignore_errors=True)

    def start_server(self, *extra):
        port_file = os.path.join(self.dir, "port")
        if os.path.exists(port_file):
            os.remove(port_file)
        log = open(os.path.join(self.dir, "server.log"), "a")
        self.server = subprocess.Popen(
            [os.path.join(self.bin, "compaction-server"), "--db", self.db, "--host", "127.0.0.1",
             "--port", "0", "--port-file", port_file, *extra],
            stdout=log, stderr=subprocess.STDOUT)
        _procs.append(self.server)
        deadline = time.time() + 20
        while not os.path.exists(port_file):
            check(self.server.poll() is None, "the server exited at start: " + self.log("server"))
            check(time.time() < deadline, "the server did not start")
            time.sleep(0.05)
        with open(port_file) as f:
            self.port = int(f.read())
        self.url = "http://127.0.0.1:%d" % self.port
        return self.server

    def start_worker(self, name, *extra):
        log = open(os.path.join(self.dir, "worker-%s.log" % name), "a")
        w = subprocess.Popen(
            [os.path.join(self.bin, "compaction-worker"), "--server", self.url, "--name", name,
             "--poll-interval", "0.2", "--work-dir", os.path.join(self.dir, "work-" + name), *extra],
            stdout=log, stderr=subprocess.STDOUT)
        _procs.append(w)
        self.workers.append(w)
        return w

    def log(self, name):
        path = os.path.join(self.dir, name + ".log")
        if not os.path.exists(path):
            return ""
        with open(path) as f:
            return f.read()[-4000:]

    # --- HTTP ---
    def request(self, method, path, body=None, token=None, raw=None,
                content_type="application/json"):
        data = raw if raw is not None else (json.dumps(body).encode() if body is not None else None)
        req = urllib.request.Request(self.url + path, data=data, method=method)
        req.add_header("Content-Type", content_type)
        if token:
            req.add_header("Authorization", "Bearer " + token)
        try:
            with urllib.request.urlopen(req, timeout=30) as r:
                payload = r.read()
                status = r.status
        except urllib.error.HTTPError as e:
            payload = e.read()
            status = e.code
        try:
            return status, json.loads(payload) if payload else None
        except ValueError:
            return status, payload.decode(errors="replace")

    def request_multipart(self, method, path, form, boundary, token=None):
        return self.request(method, path, token=token, raw=form,
                            content_type="multipart/form-data; boundary=" + boundary)

    def get_bytes(self, path):
        with urllib.request.urlopen(self.url + path, timeout=30) as r:
            return r.status, r.read()

    def get(self, path):
        status, body = self.request("GET", path)
        check(status == 200, "GET %s -> %d %s" % (path, status, body))
        return body

    def submit(self, body, token=None):
        status, out = self.request("POST", "/api/v1/sweeps", body, token)
        check(status == 201, "sweep creation -> %d %s" % (status, out))
        return out

    def wait_for(self, predicate, timeout, what):
        deadline = time.time() + timeout
        while time.time() < deadline:
            value = predicate()
            if value:
                return value
            time.sleep(0.1)
        fail("timed out after %d s waiting for %s\nserver log:\n%s" % (timeout, what, self.log("server")))

    def wait_sweep_done(self, sweep_id, timeout):
        def done():
            s = self.get("/api/v1/sweeps/%d" % sweep_id)
            return s if s["counts"]["queued"] + s["counts"]["running"] == 0 else None
        return self.wait_for(done, timeout, "sweep %d to finish" % sweep_id)

    # --- the database, read only (what the service stored) ---
    def query(self, sql, *args):
        con = sqlite3.connect("file:%s?mode=ro" % self.db, uri=True, timeout=10)
        try:
            return con.execute(sql, args).fetchall()
        finally:
            con.close()


def stop(proc, sig=signal.SIGTERM, timeout=15):
    """Sends sig to one process we started and waits for it; returns its exit code."""
    if proc.poll() is None:
        proc.send_signal(sig)
    try:
        return proc.wait(timeout)
    except subprocess.TimeoutExpired:
        proc.kill()
        fail("process %d did not stop within %d s after signal %d" % (proc.pid, timeout, sig))


def bin_dir_from_args():
    if len(sys.argv) != 2:
        print("usage: %s BIN_DIR" % sys.argv[0], file=sys.stderr)
        sys.exit(2)
    return sys.argv[1]


# A tiny scene: a second or less per job in a release build.
TINY = {"cells_per_unit": 6, "eps_end": 0.03}

# A run long enough to be stopped or killed in the middle: about 5 s on a quiet core of the
# reference machine (2026-12-05), while a worker reports its progress at most once a second.
# The 1 s scene used before (S = 3e-3 at 8 cells per unit cell) once finished before the stop.
STOPPABLE_POINT = {"S": 0.0015, "R": 1e-3, "phi": 0.4}
STOPPABLE = {"cells_per_unit": 12, "eps_end": 0.05}
