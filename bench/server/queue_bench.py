#!/usr/bin/env python3
"""How many workers and dashboard readers compaction-server holds, measured on real HTTP on
loopback with fake workers, for one or two server binaries in the same run:

  cycles     lease + complete cycles per second with 1, 4, 16 and 32 fake workers. A fake worker
             leases a job, then uploads a minimal valid bundle at once (POST /jobs/{id}/complete:
             the summary of the leased scene with a classification, and one 200-byte
             frames.csv): the same endpoints, checks, artifact files and transactions as a real
             worker's, without the simulation. Two fake workers: Python threads (this script),
             and queue_fake_workers (bench/server/fake_workers.cpp), which is compaction-worker's
             own HTTP client. The protocol of a cycle:
               next      the complete asks for the next job (form field next_lease), as
                         compaction-worker does: one request per cycle
               kept      POST /leases on the complete's kept-alive connection (compaction-worker
                         from de4c718 until next_lease; Python client only)
               separate  POST /leases on a connection of its own
             Median of 3 rounds of 3 s each.
  readers    200 dashboard readers at once, each one GET /phase-map of a 2 000-job sweep (every
             job succeeded): median and 90th percentile of their waits and the answer's size;
             then the same 200 polling again with the ETag of their first answer
             (If-None-Match) while nothing changed
  map        GET /phase-map of 10 000 succeeded jobs at one phi (30 000 jobs in the database),
             one client, each GET after a change of the database (a heartbeat): median of 20

usage: bench/server/queue_bench.py --bin build/bin [--baseline OLD_BIN_DIR] [--out FILE]
                                   [--bin-rev REV] [--baseline-rev REV]
                                   [--baseline-protocol kept] [--fake-workers PROGRAM]
Writes a Markdown table (default bench/results/queue_bench.md) with the command that made it and
the machine's load average (the cores may be shared). Standard library only.
"""
import argparse
import http.client
import json
import multiprocessing
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time

from http_bench import REPO, Server, revision_of

CLIENTS = [1, 4, 16, 32]
ROUNDS, ROUND_SECONDS = 3, 3.0
READERS = 200
MAP_SWEEPS = 5         # 5 sweeps of 2 000 jobs at phi 0.4: the 10 000-job map
OTHER_SWEEPS = 10      # 20 000 jobs at other phis beside it in the database
PROCESSES = 4          # the clients run as threads of this many processes (fewer GIL waits)
FRAMES_CSV = b"eps,stress\n" + b"".join(b"%.3f,%.6f\n" % (i / 100, i * 1e-4) for i in range(15))


def sweep_body(name, k, phi, priority=0):
    """2 000 distinct scenes: a 50 x 40 grid of S and R, shifted by k."""
    return {"name": name, "priority": priority, "phi": [phi],
            "S": {"min": 0.001 + 1e-4 * k, "max": 0.09 + 1e-4 * k, "n": 50, "scale": "linear"},
            "R": {"min": 1e-5, "max": 1e-1, "n": 40, "scale": "log"},
            "numerics": {"preset": "fast"}}


def create(server, body):
    status, answer = server.call("POST", "/api/v1/sweeps", body, timeout=120)
    if status != 201:
        raise RuntimeError("sweep creation -> %d %s" % (status, answer[:300]))
    return json.loads(answer)["id"]


def multipart(lease, engine, next_lease=None, classification=None, status="ok"):
    """The upload of a fake worker: the leased scene's summary with `classification` (class
    (a) by default) and one 200-byte frames.csv."""
    scene = lease["scene"]
    summary = {"status": status, "params": scene, "engine_version": engine,
               "source_revision": "queue-bench", "eps_reached": scene["eps_end"],
               "wall_seconds": 0.01,
               "classification": classification or {
                   "class": "a", "confidence": 0.9, "runner_up": "b", "n_reflections": 2,
                   "band_speed_ratio": 1.7,
                   "features": {"band_speed_ratio": 1.7, "band_speed_error": 0.01}}}
    if status != "ok":
        summary["reason"] = "energy blew up"
    parts = [(b"lease_token", None, lease["lease_token"].encode()),
             (b"summary", b"summary.json", json.dumps(summary).encode()),
             (b"files", b"frames.csv", FRAMES_CSV)]
    if next_lease:
        parts.append((b"next_lease", None, next_lease.encode()))
    out = []
    for name, filename, content in parts:
        disp = b'form-data; name="' + name + b'"' + (b'; filename="' + filename + b'"' if filename else b"")
        out += [b"--benchboundary\r\nContent-Disposition: " + disp + b"\r\n\r\n", content, b"\r\n"]
    out.append(b"--benchboundary--\r\n")
    return b"".join(out)


def post(port, path, body, content_type, resets, kept=None, keep=False):
    """One request as compaction-worker sends it: on `kept` (the connection the last complete
    left open) or on a new connection; the connection is closed after the answer, unless `keep`
    (a complete's, which the next lease uses). Returns (status, body, the kept connection or
    None). A connection the server reset or closed is counted and the request sent again on a
    new one (the worker retries an unreachable server too)."""
    while True:
        c, kept = kept or http.client.HTTPConnection("127.0.0.1", port, timeout=60), None
        try:
            c.request("POST", path, body=body, headers={"Content-Type": content_type})
            r = c.getresponse()
            answer = r.status, r.read()
            if keep:
                return answer + (c,)
            c.close()
            return answer + (None,)
        except (ConnectionError, http.client.RemoteDisconnected):
            c.close()
            resets[0] += 1
            time.sleep(0.01)


def worker_thread(port, engine, name, start, end, protocol, out):
    """Lease + complete until `end` by `protocol` (the module's docstring); counts the cycles
    that finished within [start, end]."""
    lease_body = json.dumps({"worker": name, "engine_version": engine})
    done, times, idle, resets = 0, [], 0, [0]
    kept, lease = None, None
    while time.time() < end:
        t0 = time.time()
        if lease is None:
            status, body, _ = post(port, "/api/v1/leases", lease_body, "application/json", resets, kept)
            kept = None
            if status == 204:
                idle += 1
                time.sleep(0.01)
                continue
            if status != 200:
                raise RuntimeError("lease -> %d %s" % (status, body[:200]))
            lease = json.loads(body)
        before = resets[0]
        status, body, kept = post(port, "/api/v1/jobs/%d/complete" % lease["job_id"],
                                  multipart(lease, engine, lease_body if protocol == "next" else None),
                                  "multipart/form-data; boundary=benchboundary", resets,
                                  keep=protocol == "kept")
        if status != 200 and not (status == 409 and resets[0] > before):  # 409: the first try went in
            raise RuntimeError("complete -> %d %s" % (status, body[:200]))
        lease = json.loads(body).get("next") if protocol == "next" and status == 200 else None
        t1 = time.time()
        if start <= t0 and t1 <= end:
            done += 1
            times.append(t1 - t0)
    if kept:
        kept.close()
    if lease:  # the job the last complete leased goes back to the queue
        post(port, "/api/v1/jobs/%d/release" % lease["job_id"],
             json.dumps({"lease_token": lease["lease_token"]}), "application/json", resets)
    out.append((done, times, idle, resets[0]))


def reader_thread(port, path, etag, barrier, out):
    """One GET; a reset or a timeout (60 s) is kept as a failure with the time it took."""
    barrier.wait()
    t0 = time.perf_counter()
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
    try:
        c.request("GET", path, headers={"If-None-Match": etag} if etag else {})
        r = c.getresponse()
        body = r.read()
        out.append((time.perf_counter() - t0, r.status, len(body), r.getheader("ETag")))
    except (OSError, http.client.HTTPException) as e:
        out.append((time.perf_counter() - t0, type(e).__name__, 0, None))
    finally:
        c.close()


def process_main(kind, args, n_threads, index, queue):
    out, threads = [], []
    if kind == "worker":
        port, engine, start, end, protocol = args
        for i in range(n_threads):
            threads.append(threading.Thread(target=worker_thread, args=(
                port, engine, "bench-%d-%d" % (index, i), start, end, protocol, out)))
    else:
        port, path, etag, at = args
        barrier = threading.Barrier(n_threads, timeout=60)
        for _ in range(n_threads):
            threads.append(threading.Thread(target=reader_thread,
                                            args=(port, path, etag, barrier, out)))
        time.sleep(max(0.0, at - time.time()))
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    queue.put(out)


def run_clients(kind, n, args):
    """n client threads spread over up to PROCESSES processes; the results of all threads."""
    queue = multiprocessing.Queue()
    procs = []
    n_procs = min(n, PROCESSES)
    for p in range(n_procs):
        share = n // n_procs + (1 if p < n % n_procs else 0)
        procs.append(multiprocessing.Process(target=process_main, args=(kind, args, share, p, queue)))
    for p in procs:
        p.start()
    results = []
    for _ in procs:
        results += queue.get(timeout=600)
    for p in procs:
        p.join()
        if p.exitcode != 0:
            raise RuntimeError("a client process failed (exit %d)" % p.exitcode)
    if len(results) != n:
        raise RuntimeError("a client thread failed")
    return results


def cpu_seconds(pid):
    """User + system CPU time of a process so far (/proc/PID/stat)."""
    fields = open("/proc/%d/stat" % pid).read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def cycles(server, engine, n, seconds, client):
    """(cycles per second, median cycle time, resets, the server's CPU seconds per cycle) of n
    fake workers; client: (kind, protocol) with kind "python" or the path of
    queue_fake_workers."""
    kind, protocol = client
    cpu0 = cpu_seconds(server.proc.pid)
    start = time.time() + 0.5  # the clients connect and run half a second before counting
    if kind == "python":
        results = run_clients("worker", n, (server.port, engine, start, start + seconds, protocol))
        done = sum(r[0] for r in results)
        times = [t for r in results for t in r[1]]
        idle = sum(r[2] for r in results)
        resets = sum(r[3] for r in results)
        median = statistics.median(times) if times else float("nan")
    else:
        p = subprocess.run([kind, "--url", "http://127.0.0.1:%d" % server.port, "--clients", str(n),
                            "--start", repr(start), "--seconds", repr(seconds), "--engine", engine]
                           + (["--separate-lease"] if protocol == "separate" else []),
                           capture_output=True, text=True, timeout=600)
        answer = json.loads(p.stdout) if p.stdout.strip() else {}
        if p.returncode != 0:
            raise RuntimeError("queue_fake_workers exit %d: %s %s" % (p.returncode, answer.get("errors"),
                                                                     p.stderr[-500:]))
        done, idle, resets = answer["cycles"], answer["idle"], 0
        median = answer["median_seconds"] if answer["median_seconds"] is not None else float("nan")
    if idle:
        raise RuntimeError("the queue ran dry: %d leases found nothing" % idle)
    return done / seconds, median, resets, (cpu_seconds(server.proc.pid) - cpu0) / max(done, 1)


def queued(server):
    return json.loads(server.call("GET", "/api/v1/health")[1])["jobs"].get("queued", 0)


def readers(server, path):
    def round_of(etag):
        res = run_clients("reader", READERS, (server.port, path, etag, time.time() + 0.5))
        waits = sorted(r[0] for r in res)
        ok = [r for r in res if isinstance(r[1], int)]
        return {"p50": statistics.median(waits), "p90": waits[int(0.9 * len(waits)) - 1],
                "statuses": sorted(set(str(r[1]) for r in res)),
                "failed": len(res) - len(ok),
                "bytes": statistics.median(r[2] for r in ok) if ok else 0,
                "etag": next((r[3] for r in ok if r[3]), None)}
    first = round_of(None)
    again = round_of(first["etag"]) if first["etag"] else None
    return first, again


def one_reader(server, path, engine, n=20):
    """Median time of GET path after a change: before each GET, a heartbeat of a job at another
    phi changes the database (so no answer of an earlier version can serve it)."""
    status, body = server.call("POST", "/api/v1/leases", {"worker": "bench-poller", "engine_version": engine})
    assert status == 200, status
    lease = json.loads(body)
    times, size = [], 0
    for i in range(n):
        status, _ = server.call("POST", "/api/v1/jobs/%d/heartbeat" % lease["job_id"],
                                {"lease_token": lease["lease_token"], "eps": 0.001 * (i + 1)})
        assert status == 200, status
        t0 = time.perf_counter()
        status, body = server.call("GET", path, timeout=120)
        times.append(time.perf_counter() - t0)
        assert status == 200, status
        size = len(body)
    return statistics.median(times), size


def measure(bin_dir, workdir, clients):
    """The readers, the map and the cycles of one server; the cycles once per client of
    `clients` ([(kind, protocol)], the first also fills the map)."""
    s = Server(bin_dir, workdir)
    out = {}
    try:
        engine = json.loads(s.call("GET", "/api/v1/health")[1])["engine_version"]
        t0 = time.time()
        map_sweeps = [create(s, sweep_body("map-%d" % k, k, 0.4, priority=10)) for k in range(MAP_SWEEPS)]
        phis = [round(0.2 + 0.01 * i, 2) for i in range(61) if round(0.2 + 0.01 * i, 2) != 0.4]
        for k in range(OTHER_SWEEPS):
            create(s, sweep_body("other-%d" % k, 0, phis.pop(0)))
        print("  %d sweeps created in %.1f s; filling the map ..." % (MAP_SWEEPS + OTHER_SWEEPS,
              time.time() - t0), file=sys.stderr)
        t0 = time.time()
        while any(json.loads(s.call("GET", "/api/v1/sweeps/%d" % i)[1])["counts"]["queued"] > 0
                  for i in map_sweeps):
            cycles(s, engine, 32, 5.0, clients[0])
        print("  map filled in %.1f s" % (time.time() - t0), file=sys.stderr)
        out["readers"] = readers(s, "/api/v1/phase-map?phi=0.4&sweep=%d" % map_sweeps[0])
        out["map"] = one_reader(s, "/api/v1/phase-map?phi=0.4", engine)
        out["cycles"] = {}
        rate = 100.0
        for client in clients:
            out["cycles"][client] = {}
            for n in CLIENTS:
                rounds = []
                for _ in range(ROUNDS):
                    while queued(s) < rate * ROUND_SECONDS * 2 + 2000:  # never dry within a round
                        create(s, sweep_body("feed", 0, phis.pop(0)))
                    rounds.append(cycles(s, engine, n, ROUND_SECONDS, client))
                    rate = max(rate, rounds[-1][0])
                out["cycles"][client][n] = (statistics.median(r[0] for r in rounds),
                                            statistics.median(r[1] for r in rounds),
                                            sum(r[2] for r in rounds),
                                            statistics.median(r[3] for r in rounds))
                print("  %s: %d clients: %.1f cycles/s" % (client_name(client), n,
                      out["cycles"][client][n][0]), file=sys.stderr)
    finally:
        s.stop()
    return out


def client_name(client):
    kind, protocol = client
    return "%s workers, %s" % ("Python" if kind == "python" else "C++ (the worker's client)", protocol)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin", required=True, help="folder of the compaction-server to measure")
    ap.add_argument("--baseline", help="folder of another compaction-server, measured alike")
    ap.add_argument("--out", default=os.path.join(REPO, "bench", "results", "queue_bench.md"))
    ap.add_argument("--bin-rev", help="the commit --bin was built from, when its folder is not "
                    "in a git checkout (default: the checkout's HEAD)")
    ap.add_argument("--baseline-rev", help="the same for --baseline")
    ap.add_argument("--baseline-protocol", default="kept", choices=("next", "kept", "separate"),
                    help="the cycle's protocol for the baseline's Python workers: kept for a "
                    "server without next_lease (before 2026-12-03) [kept]")
    ap.add_argument("--fake-workers", default=os.path.join(REPO, "build", "bin", "queue_fake_workers"),
                    help="the C++ fake workers (bench/server/fake_workers.cpp) [build/bin/...]")
    a = ap.parse_args()
    if not os.access(a.fake_workers, os.X_OK):
        sys.exit("queue_bench.py: --fake-workers %s is not a program (build the target "
                 "queue_fake_workers)" % a.fake_workers)
    workdir = tempfile.mkdtemp(prefix="queue-bench-")
    load_before = os.getloadavg()
    try:
        runs = []  # (server's name, its measures, its clients)
        if a.baseline:
            rev = a.baseline_rev or revision_of(a.baseline)
            print("measuring the baseline %s ..." % a.baseline, file=sys.stderr)
            # A baseline that knows next_lease is measured with both clients, as the build is.
            clients = [("python", a.baseline_protocol)]
            if a.baseline_protocol == "next":
                clients.append((a.fake_workers, "next"))
            runs.append(("baseline (at %s)" % rev, measure(a.baseline, workdir, clients), clients))
        print("measuring %s ..." % a.bin, file=sys.stderr)
        clients = [("python", "next"), (a.fake_workers, "next")]
        runs.append(("this build (at %s)" % (a.bin_rev or revision_of(a.bin)),
                     measure(a.bin, workdir, clients), clients))
    except BaseException:
        shutil.rmtree(workdir, ignore_errors=True)
        raise
    load_after = os.getloadavg()
    rev = subprocess.run(["git", "-C", REPO, "rev-parse", "--short", "HEAD"], capture_output=True,
                         text=True).stdout.strip()
    lines = ["# The queue and the phase map under load: fake workers and dashboard readers", "",
             "Made by `bench/server/queue_bench.py %s` (checkout at %s), %s, on %d cores shared "
             "with other work: load average %.1f before, %.1f after (1 min)."
             % (" ".join(sys.argv[1:]), rev, time.strftime("%Y-%m-%d"), os.cpu_count(),
                load_before[0], load_after[0]), "",
             "Lease + complete cycles per second (median of %d rounds of %.0f s; in brackets the "
             "median cycle's time, the server's CPU time per cycle (from /proc, the round's "
             "connecting half second included), and the connections the server reset in the %d "
             "rounds, each request sent again):" % (ROUNDS, ROUND_SECONDS, ROUNDS), "",
             "| server | fake workers, protocol | " + " | ".join("%d clients" % n for n in CLIENTS) + " |",
             "|---|---|" + "---|" * len(CLIENTS)]
    for name, m, clients in runs:
        for client in clients:
            c = m["cycles"][client]
            lines.append("| %s | %s | " % (name, client_name(client)) + " | ".join(
                "%.0f (%.1f ms, CPU %.2f ms, %d resets)" % (c[n][0], c[n][1] * 1e3, c[n][3] * 1e3, c[n][2])
                for n in CLIENTS) + " |")
    lines += ["", "Dashboard readers and the map (a reader that failed, reset or silent for 60 s, "
              "counts with the time it waited; statuses: HTTP codes or the client's error):", "",
              "| server | %d readers of a 2 000-job map: p50 / p90, answer, failed | the same polling "
              "with If-None-Match: p50 / p90, status, answer | 10 000-job map after a change, one client: median, answer |"
              % READERS, "|---|---|---|---|"]
    for name, m, _ in runs:
        first, again = m["readers"]
        poll = ("%.0f / %.0f ms, %s, %.0f B" % (again["p50"] * 1e3, again["p90"] * 1e3,
                                                ",".join(map(str, again["statuses"])), again["bytes"])
                if again else "no ETag: every poll is the full answer")
        lines.append("| %s | %.0f / %.0f ms, %.0f KB, %d | %s | %.1f ms, %.0f KB |"
                     % (name, first["p50"] * 1e3, first["p90"] * 1e3, first["bytes"] / 1e3,
                        first["failed"], poll,
                        m["map"][0] * 1e3, m["map"][1] / 1e3))
    if len(runs) == 2:
        (_, b, b_clients), (_, t, t_clients) = runs
        # Cycles compared per kind of fake worker that measured both servers.
        kinds = [(bcl, tcl) for bcl in b_clients for tcl in t_clients if bcl[0] == tcl[0]]
        cycles = "; ".join("%s: cycles %s" % (client_name(bcl).split(",")[0], ", ".join(
            "%.2fx at %d" % (t["cycles"][tcl][n][0] / b["cycles"][bcl][n][0], n) for n in CLIENTS))
            for bcl, tcl in kinds)
        lines += ["", "Ratios (this build / baseline, the same fake workers): " + cycles +
                  "; readers' p50 %.1fx faster; the 10 000-job map %.1fx faster."
                  % (b["readers"][0]["p50"] / t["readers"][0]["p50"], b["map"][0] / t["map"][0])]
    with open(a.out, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))
    shutil.rmtree(workdir, ignore_errors=True)  # tens of thousands of artifact folders: slow


if __name__ == "__main__":
    main()
