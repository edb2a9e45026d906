#!/usr/bin/env python3
"""What a client of compaction-server waits for, measured on real HTTP on loopback, for one or
two server binaries in the same run (e.g. this build against an older one):

  keep-alive   median time of GET /api/v1/health on one keep-alive connection (5 rounds of 200)
  during upload  GET /api/v1/jobs?limit=1 while a worker uploads a 200 MB result: median and
               worst latency of the reads made during the upload, and the upload's own time
  slow clients GET /api/v1/health while 50 sockets send one header line every 3 s: median and
               worst latency over 10 s (a read that takes longer than 5 s counts as 5 s)

usage: bench/server/http_bench.py --bin build/bin [--baseline OLD_BIN_DIR] [--out FILE]
Writes a Markdown table (default bench/results/http_bench.md) with the command that made it.
Standard library only; the runner (compaction-run) of --bin makes the upload's summary.
"""
import argparse
import http.client
import json
import os
import shutil
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
UPLOAD_MB = 200  # below the server's default --max-upload-mb (256)


class Server:
    def __init__(self, bin_dir, workdir, db=None, start_seconds=20):
        """A server on `db` (default: a new database in a folder of its own below workdir),
        listening within start_seconds (a migration of a large database takes longer)."""
        self.dir = tempfile.mkdtemp(dir=workdir)
        port_file = os.path.join(self.dir, "port")
        self.proc = subprocess.Popen(
            [os.path.join(bin_dir, "compaction-server"), "--db", db or os.path.join(self.dir, "b.db"),
             "--port", "0", "--port-file", port_file, "--lease-seconds", "3600",
             "--log-level", "warn"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        deadline = time.time() + start_seconds
        while not os.path.exists(port_file):
            if time.time() > deadline or self.proc.poll() is not None:
                raise RuntimeError("server did not start: " + bin_dir)
            time.sleep(0.05)
        self.port = int(open(port_file).read())

    def call(self, method, path, body=None, timeout=30):
        c = http.client.HTTPConnection("127.0.0.1", self.port, timeout=timeout)
        try:
            data = json.dumps(body).encode() if body is not None else None
            c.request(method, path, body=data, headers={"Content-Type": "application/json"})
            r = c.getresponse()
            return r.status, r.read()
        finally:
            c.close()

    def stop(self):
        self.proc.terminate()
        self.proc.wait(20)


def keep_alive(server):
    rounds = []
    for _ in range(5):
        c = http.client.HTTPConnection("127.0.0.1", server.port, timeout=30)
        times = []
        for _ in range(200):
            t0 = time.perf_counter()
            c.request("GET", "/api/v1/health")
            c.getresponse().read()
            times.append(time.perf_counter() - t0)
        c.close()
        rounds.append(statistics.median(times))
    return statistics.median(rounds)


def multipart(parts, boundary=b"benchboundary"):
    out = []
    for name, filename, content in parts:
        disp = b'form-data; name="' + name + b'"' + (b'; filename="' + filename + b'"' if filename else b"")
        out += [b"--" + boundary + b"\r\nContent-Disposition: " + disp + b"\r\n\r\n", content, b"\r\n"]
    out.append(b"--" + boundary + b"--\r\n")
    return out


def during_upload(server, run_bin, workdir):
    scene = {"S": 0.05, "R": 1e-3, "phi": 0.4, "cells_per_unit": 6, "eps_end": 0.01}
    status, body = server.call("POST", "/api/v1/sweeps", {"name": "bench", "points": [
        {"S": scene["S"], "R": scene["R"], "phi": scene["phi"]}],
        "numerics": {"cells_per_unit": 6, "eps_end": 0.01}})
    assert status == 201, body
    engine = json.loads(server.call("GET", "/api/v1/health")[1])["engine_version"]
    status, body = server.call("POST", "/api/v1/leases", {"worker": "bench", "engine_version": engine})
    lease = json.loads(body)
    out = os.path.join(workdir, "bundle-%d" % server.port)
    scene_file = os.path.join(workdir, "scene-%d.json" % server.port)
    with open(scene_file, "w") as f:
        json.dump(lease["scene"], f)
    subprocess.run([os.path.join(run_bin, "compaction-run"), "--scene", scene_file, "--out", out,
                    "--progress", "none"], check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    summary = open(os.path.join(out, "summary.json"), "rb").read()
    parts = multipart([(b"lease_token", None, lease["lease_token"].encode()),
                       (b"summary", b"summary.json", summary),
                       (b"files", b"snapshot_0.200.npy", b"\0" * (UPLOAD_MB << 20))])
    length = sum(len(p) for p in parts)
    reads, done = [], threading.Event()

    def reader():
        while not done.is_set():
            t0 = time.perf_counter()
            server.call("GET", "/api/v1/jobs?limit=1", timeout=60)
            reads.append(time.perf_counter() - t0)
            time.sleep(0.02)

    t = threading.Thread(target=reader)
    t.start()
    t0 = time.perf_counter()
    c = http.client.HTTPConnection("127.0.0.1", server.port, timeout=300)
    c.putrequest("POST", "/api/v1/jobs/%d/complete" % lease["job_id"])
    c.putheader("Content-Type", "multipart/form-data; boundary=benchboundary")
    c.putheader("Content-Length", str(length))
    c.endheaders()
    for p in parts:
        c.send(p)
    r = c.getresponse()
    answer = r.read()
    upload = time.perf_counter() - t0
    done.set()
    t.join()
    assert r.status == 200, answer
    return upload, statistics.median(reads), max(reads), len(reads)


def slow_clients(server):
    stop = threading.Event()

    def slowloris(i):
        try:
            s = socket.create_connection(("127.0.0.1", server.port), timeout=5)
            s.sendall(b"GET /api/v1/health HTTP/1.1\r\nHost: 127.0.0.1\r\n")
            n = 0
            while not stop.wait(3.0):
                s.sendall(b"X-Slow-%d-%d: 1\r\n" % (i, n))
                n += 1
        except OSError:
            pass

    threads = [threading.Thread(target=slowloris, args=(i,), daemon=True) for i in range(50)]
    for t in threads:
        t.start()
    time.sleep(0.5)
    times = []
    end = time.time() + 10
    while time.time() < end:
        t0 = time.perf_counter()
        try:
            server.call("GET", "/api/v1/health", timeout=5)
            times.append(time.perf_counter() - t0)
        except OSError:
            times.append(5.0)
        time.sleep(0.1)
    stop.set()
    return statistics.median(times), max(times)


def revision_of(bin_dir):
    """The commit a build folder's tree is at (bin/ -> build/ -> the checkout), if it is one."""
    tree = os.path.dirname(os.path.dirname(os.path.abspath(bin_dir)))
    r = subprocess.run(["git", "-C", tree, "rev-parse", "--short", "HEAD"], capture_output=True, text=True)
    return r.stdout.strip() or "?"


def measure(bin_dir, run_bin, workdir):
    out = {}
    s = Server(bin_dir, workdir)
    try:
        out["keep_alive"] = keep_alive(s)
        out["upload"] = during_upload(s, run_bin, workdir)
        out["slow"] = slow_clients(s)
    finally:
        s.stop()
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin", required=True, help="folder of the compaction-server to measure")
    ap.add_argument("--baseline", help="folder of another compaction-server, measured alike")
    ap.add_argument("--out", default=os.path.join(REPO, "bench", "results", "http_bench.md"))
    a = ap.parse_args()
    workdir = tempfile.mkdtemp(prefix="http-bench-")
    try:
        runs = []
        if a.baseline:
            print("measuring the baseline %s ..." % a.baseline, file=sys.stderr)
            runs.append(("baseline (%s, at %s)" % (a.baseline, revision_of(a.baseline)),
                         measure(a.baseline, a.bin, workdir)))
        print("measuring %s ..." % a.bin, file=sys.stderr)
        runs.append(("this build (%s, at %s)" % (a.bin, revision_of(a.bin)),
                     measure(a.bin, a.bin, workdir)))
    finally:
        shutil.rmtree(workdir, ignore_errors=True)
    rev = subprocess.run(["git", "-C", REPO, "rev-parse", "--short", "HEAD"], capture_output=True,
                         text=True).stdout.strip()
    lines = ["# HTTP: what a client waits for", "",
             "Made by `bench/server/http_bench.py %s` (checkout at %s) on this machine (2 cores), %s."
             % (" ".join(sys.argv[1:]), rev, time.strftime("%Y-%m-%d")), "",
             "| server | keep-alive GET /health, median | %d MB upload, its time | GET /jobs?limit=1 during it: median / worst (reads) | GET /health beside 50 slowloris sockets: median / worst |"
             % UPLOAD_MB, "|---|---|---|---|---|"]
    for name, m in runs:
        up, med, worst, n = m["upload"]
        lines.append("| %s | %.2f ms | %.2f s | %.1f ms / %.0f ms (%d) | %.1f ms / %.0f ms |"
                     % (name, m["keep_alive"] * 1e3, up, med * 1e3, worst * 1e3, n,
                        m["slow"][0] * 1e3, m["slow"][1] * 1e3))
    if len(runs) == 2:
        b, t = runs[0][1], runs[1][1]
        lines += ["", "Ratios (baseline / this build): keep-alive %.1fx, worst read during the upload %.1fx, "
                  "worst health beside slow clients %.1fx."
                  % (b["keep_alive"] / t["keep_alive"], b["upload"][2] / t["upload"][2],
                     b["slow"][1] / t["slow"][1])]
    lines += ["", "A slowloris read that took 5 s or more is counted as 5 s (the client's timeout)."]
    with open(a.out, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
