#!/usr/bin/env python3
"""The run table (GET /api/v1/jobs, docs/service.md "The run table") at 100 000 runs, measured
on real HTTP on loopback against a real database filled as a server fills one:

  fill     a server on a new database: 46 sweeps of 2 000 runs (phi 0.3 to 0.6; a quarter at the
           default preset, the others fast; every fifth of 500 points x 4 replicates), completed
           by fake workers (bench/server/queue_bench.py's upload: the leased scene's summary,
           with a class, confidence, N_r and c_b/V drawn from the scene by a made-up rule shaped
           like the paper's map, 2 % unstable; 2 % of the leases fail instead); 4 000 runs of two
           sweeps computed on a second server, exported (artifacts=none) and imported; a
           person's label on 1 % of the runs; a sweep of 2 000 left queued, one cancelled
  answers  each request after a heartbeat (a commit, so no cached answer serves it): median and
           90th percentile of its time over --rounds, the server's CPU time per request (from
           /proc, its clock ticks summed over the rounds) and the answer's size: the first page
           (table and full jobs), sorted pages, a filtered and sorted page, a sweep's page, a
           text search, deep pages by cursor and by offset, the count (limit=1), a feature's
           filter, the CSV of every run (all columns, and a plot's columns= only)
  upgrade  migrations 0012, 0014 and 0015 on a copy of the filled database without them (the
           run table, its triggers and their records dropped): the server's start, migrations
           included
  writes   with --baseline (a build before the run table): the time of POST /sweeps of 2 000
           jobs and lease + complete cycles per second of 16 fake workers (queue_bench's), each
           server on a new database, alternately

usage: bench/dashboard/jobs_table_bench.py --bin build/bin [--baseline OLD_BIN_DIR]
         [--db FILLED.db] [--keep FILLED.db] [--rounds 15] [--out bench/results/jobs_table.md]
--keep writes the filled database there (and its artifacts beside it); --db measures one filled
before instead of filling. Standard library only. Writes a Markdown report with the command
that made it and the machine's load average (the cores may be shared).
"""
import argparse
import hashlib
import json
import math
import os
import shutil
import sqlite3
import statistics
import sys
import tempfile
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "server"))

import queue_bench as q  # noqa: E402
from http_bench import REPO, Server, revision_of  # noqa: E402

SWEEPS = 46           # of 2 000 runs, completed (--sweeps)
QUEUED_SWEEPS = 1     # of 2 000 runs left queued
CANCELLED_SWEEPS = 1  # of 2 000 runs cancelled
IMPORTED_SWEEPS = 2   # of 2 000 runs, computed on another server
PHIS = [0.3, 0.35, 0.4, 0.45, 0.5, 0.55, 0.6]
WORKERS = 8           # fake workers' threads
LABELS = ["a", "b", "c", "d", "e", "f"]
REASONS = ["two reflections in the space-time map", "the band stalls at the plate",
           "buckling before the band", "a slow band, not (b)"]


def sweep_body(name, k, phi, preset, replicates):
    """2 000 runs: 50 x 40 points of S and R (or 25 x 20 points x 4 replicates), shifted by k."""
    n_S, n_R = (25, 20) if replicates else (50, 40)
    body = {"name": name, "phi": [phi], "numerics": {"preset": preset},
            "S": {"min": 0.001 + 1e-5 * k, "max": 0.09 + 1e-5 * k, "n": n_S, "scale": "linear"},
            "R": {"min": 1e-5, "max": 1e-1, "n": n_R, "scale": "log"}}
    if replicates:
        body["replicates"] = {"n": 4, "perturbation": 0.01}
    return body


def unit(*key):
    """A number in [0, 1) fixed by the key (the same run gets the same draw)."""
    return int.from_bytes(hashlib.sha256(repr(key).encode()).digest()[:6], "big") / 2 ** 48


def classification(scene):
    """A class from (S, R) shaped like the paper's map (made up), a confidence, N_r, c_b/V."""
    S, R, seed = scene["S"], scene["R"], scene.get("seed", 1)
    x = math.log10(S / 0.001) / 2 + 0.2 * (unit(S, R, seed, "x") - 0.5)  # 0 .. 1 over S
    y = math.log10(R / 1e-5) / 4                                         # 0 .. 1 over R
    cls = "abcdef"[min(5, int(3 * x) + 3 * (y > 0.5))]
    conf = round(0.35 + 0.65 * unit(S, R, seed, "c"), 4)
    speed = round(1 / (1 - scene["phi"]) * (0.6 + 0.8 * unit(S, R, seed, "v")), 4)
    return {"class": cls, "confidence": conf, "runner_up": "abcdef"[(LABELS.index(cls) + 1) % 6],
            "n_reflections": int(4 * unit(S, R, seed, "n")), "band_speed_ratio": speed,
            "features": {"band_speed_ratio": speed, "band_speed_error": 0.01,
                         "deflection_before_yield": round(0.2 * unit(S, R, seed, "d") ** 3, 6),
                         "coherence": round(unit(S, R, seed, "h"), 4),
                         "n_fronts": int(3 * unit(S, R, seed, "f"))}}


def fake_worker(port, engine, name, counts):
    """Leases and completes (or fails) jobs until the queue is empty."""
    resets, lease = [0], None
    lease_body = json.dumps({"worker": name, "engine_version": engine})
    while True:
        if lease is None:
            status, body, _ = q.post(port, "/api/v1/leases", lease_body, "application/json", resets)
            if status == 204:
                return
            assert status == 200, (status, body[:200])
            lease = json.loads(body)
        scene = lease["scene"]
        draw = unit(scene["S"], scene["R"], scene["phi"], scene.get("seed", 1), "fate")
        if draw < 0.02:  # a failure that is not retried
            status, body, _ = q.post(port, "/api/v1/jobs/%d/fail" % lease["job_id"],
                                     json.dumps({"lease_token": lease["lease_token"],
                                                 "reason": "the runner crashed", "retryable": False}),
                                     "application/json", resets)
            assert status == 200, (status, body[:200])
            counts["failed"] += 1
            lease = None
            continue
        status, body, _ = q.post(port, "/api/v1/jobs/%d/complete" % lease["job_id"],
                                 q.multipart(lease, engine, lease_body, classification(scene),
                                             "unstable" if draw < 0.04 else "ok"),
                                 "multipart/form-data; boundary=benchboundary", resets)
        assert status == 200, (status, body[:200])
        counts["done"] += 1
        lease = json.loads(body).get("next")


def run_workers(server, engine):
    counts, errors = {"done": 0, "failed": 0}, []

    def work(name):
        try:
            fake_worker(server.port, engine, name, counts)
        except Exception as e:  # noqa: BLE001 - reported after the others end
            errors.append(repr(e))

    threads = [threading.Thread(target=work, args=("w%d" % i,)) for i in range(WORKERS)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    if errors:
        raise RuntimeError("fake workers failed: %s" % errors[:3])
    return counts


def call_json(server, method, path, body=None, expect=200):
    status, answer = server.call(method, path, body, timeout=600)
    if status != expect:
        raise RuntimeError("%s %s -> %d %s" % (method, path, status, answer[:300]))
    return json.loads(answer) if answer else None


def fill(bin_dir, workdir, db, sweeps):
    """Fills `db` as the module's docstring says; returns what it holds and how long it took."""
    t0 = time.time()
    notes = {}
    other = Server(bin_dir, workdir)
    try:
        engine = call_json(other, "GET", "/api/v1/health")["engine_version"]
        parts = [q.create(other, sweep_body("part %s" % c, 100 + i, 0.42, "fast", False))
                 for i, c in enumerate("AB"[:IMPORTED_SWEEPS])]
        run_workers(other, engine)
        exports = [other.call("GET", "/api/v1/sweeps/%d/export?format=archive&artifacts=none" % p,
                              timeout=600)[1] for p in parts]
    finally:
        other.stop()
    s = Server(bin_dir, workdir, db=db)
    try:
        for k in range(sweeps):
            q.create(s, sweep_body("sweep %d%s" % (k, " trusted map" if k % 9 == 4 else ""), k,
                                   PHIS[k % len(PHIS)], "default" if k % 4 == 3 else "fast",
                                   k % 5 == 0))
        notes["fill_sweeps_s"] = time.time() - t0
        counts = run_workers(s, engine)
        notes.update(counts)
        for e in exports:
            status, answer = s.call("POST", "/api/v1/imports", json.loads(e), timeout=600)
            assert status == 200, (status, answer[:300])
        done = call_json(s, "GET", "/api/v1/jobs?format=table&state=succeeded&limit=1")["total"]
        labelled = 0
        for job in range(1, done, 97):  # about 1 % of the runs
            status, _ = s.call("PUT", "/api/v1/jobs/%d/label" % job,
                               {"label": LABELS[job % 6], "reason": REASONS[job % 4],
                                "by": ["ana", "ben"][job % 2]})
            labelled += status == 200
        notes["labelled"] = labelled
        for k in range(QUEUED_SWEEPS):
            q.create(s, sweep_body("queued %d" % k, 200 + k, 0.4, "fast", False))
        for k in range(CANCELLED_SWEEPS):
            c = q.create(s, sweep_body("cancelled %d" % k, 300 + k, 0.5, "fast", False))
            call_json(s, "POST", "/api/v1/sweeps/%d/cancel" % c, {})
    finally:
        s.stop()
    notes["fill_s"] = time.time() - t0
    return notes


def percentile(values, p):
    v = sorted(values)
    return v[min(len(v) - 1, int(math.ceil(p * len(v))) - 1)]


class Reader:
    """GETs of one server, each after a heartbeat of a job it leased: a commit, so that no
    answer of an earlier version serves it."""

    def __init__(self, server, engine):
        self.server = server
        self.lease = call_json(server, "POST", "/api/v1/leases", {"worker": "bench-poller", "engine_version": engine})
        self.eps = 0.0

    def measure(self, path, rounds):
        """(median s, p90 s, the server's CPU ms per request, bytes) of GET path."""
        times, cpu, size = [], 0.0, 0
        for _ in range(rounds):
            self.eps += 1e-6
            status, _ = self.server.call("POST", "/api/v1/jobs/%d/heartbeat" % self.lease["job_id"],
                                         {"lease_token": self.lease["lease_token"], "eps": self.eps})
            assert status == 200, status
            c0 = q.cpu_seconds(self.server.proc.pid)
            t0 = time.perf_counter()
            status, body = self.server.call("GET", path, timeout=600)
            times.append(time.perf_counter() - t0)
            cpu += q.cpu_seconds(self.server.proc.pid) - c0
            assert status == 200, (path, status, body[:300])
            size = len(body)
        return statistics.median(times), percentile(times, 0.9), 1e3 * cpu / rounds, size


def cursor_at(server, query, row):
    """The cursor of the page after `row` rows of the query (read once, by offset)."""
    page = call_json(server, "GET", "/api/v1/jobs?format=table&limit=1&offset=%d&%s" % (row - 1, query))
    return page["next"]


def answers(bin_dir, workdir, db, rounds):
    s = Server(bin_dir, workdir, db=db, start_seconds=600)
    try:
        engine = call_json(s, "GET", "/api/v1/health")["engine_version"]
        count = lambda query: call_json(s, "GET", "/api/v1/jobs?format=table&limit=1&" + query)["total"]  # noqa: E731
        total = count("")
        held = {state: count("state=" + state) for state in ("succeeded", "failed", "queued", "cancelled")}
        held.update(imported=count("imported=true"), labelled=count("human_label=any"),
                    presets={p: count("preset=" + p) for p in ("fast", "default")})
        reader = Reader(s, engine)
        table = "/api/v1/jobs?format=table"
        filt = "phi=0.4&class=b,c&confidence_max=0.6&sort=-band_speed_ratio"
        feat = "deflection_before_yield_min=0.01&sort=-coherence"
        plot_cols = "columns=id,S,R,phi,state,status,class,label,band_speed_ratio"
        cases = [
            ("first page (table, 100 rows)", table),
            ("first page (full jobs, 100)", "/api/v1/jobs"),
            ("sorted by -confidence", table + "&sort=-confidence"),
            ("filtered and sorted: " + filt, table + "&" + filt),
            ("one sweep, sorted by S: sweep=7&sort=S", table + "&sweep=7&sort=S"),
            ("a point's replicates: point=5", table + "&point=5"),
            ("human labels: human_label=any&sort=label", table + "&human_label=any&sort=label"),
            ("imported: imported=true&sort=-source_job", table + "&imported=true&sort=-source_job"),
            ("text search: q=trusted", table + "&q=trusted"),
            ("deep page by cursor, id order (row 99 000)",
             table + "&cursor=" + cursor_at(s, "", min(99000, total - 100))),
            ("deep page by cursor, -confidence (row 90 000)",
             table + "&sort=-confidence&cursor=" + cursor_at(s, "sort=-confidence", min(90000, total - 100))),
            ("deep page by offset, id order (offset=99000)", table + "&offset=%d" % min(99000, total - 100)),
            ("deep page by offset, -confidence (offset=90000)",
             table + "&sort=-confidence&offset=%d" % min(90000, total - 100)),
            ("count of all (limit=1)", table + "&limit=1"),
            ("count of a filter (limit=1): " + filt, table + "&limit=1&" + filt),
            ("filtered by a feature: " + feat, table + "&" + feat),
            ("CSV of every run", "/api/v1/jobs?format=csv"),
            ("CSV of every run, a plot's columns: " + plot_cols, "/api/v1/jobs?format=csv&" + plot_cols),
        ]
        out = []
        for name, path in cases:
            out.append((name, path) + reader.measure(path, rounds if "CSV" not in name else max(3, rounds // 3)))
            print("  %-60s %7.1f ms" % (name[:60], out[-1][2] * 1e3), file=sys.stderr)
        return total, held, out
    finally:
        s.stop()


# The migrations that make run_rows: the table (0012), its geometry (0014), its features (0015).
RUN_ROWS_MIGRATIONS = (12, 14, 15)


def upgrade(bin_dir, workdir, db):
    """Seconds from the start of a server on a copy of db without migration 0012 until it
    listens (the migration's backfill of every run included)."""
    copy = os.path.join(tempfile.mkdtemp(dir=workdir), "before-0012.db")
    for suffix in ("", "-wal"):
        if os.path.exists(db + suffix):
            shutil.copy(db + suffix, copy + suffix)
    c = sqlite3.connect(copy)
    for (trigger,) in c.execute("SELECT name FROM sqlite_master WHERE type = 'trigger' AND name LIKE 'run_rows_%'").fetchall():
        c.execute("DROP TRIGGER %s" % trigger)
    c.execute("DROP TABLE run_rows")
    c.execute("DELETE FROM schema_migrations WHERE version IN %s" % (RUN_ROWS_MIGRATIONS,))
    c.commit()
    c.close()
    t0 = time.time()
    s = Server(bin_dir, workdir, db=copy, start_seconds=600)
    took = time.time() - t0
    s.stop()
    return took


def writes(bin_dir, workdir, rounds=3):
    """(median seconds of POST /sweeps of 2 000 jobs, median cycles per second of 16 Python fake
    workers) on a new database."""
    s = Server(bin_dir, workdir)
    try:
        engine = call_json(s, "GET", "/api/v1/health")["engine_version"]
        creates = []
        for k in range(rounds + 2):
            t0 = time.perf_counter()
            q.create(s, sweep_body("w%d" % k, k, PHIS[k % len(PHIS)], "default" if k % 2 else "fast", False))
            creates.append(time.perf_counter() - t0)
        rates = [q.cycles(s, engine, 16, 3.0, ("python", "next"))[0] for _ in range(rounds)]
        return statistics.median(creates), statistics.median(rates)
    finally:
        s.stop()


def report(args, notes, total, held, rows, upgrade_s, write_rows, load):
    lines = ["# The run table (GET /api/v1/jobs) at 100 000 runs", ""]
    lines.append("Made by `%s` (checkout at %s), %s, on %d cores shared with other work: load "
                 "average %.1f before, %.1f after (1 min)."
                 % (" ".join(["bench/dashboard/jobs_table_bench.py"] + sys.argv[1:]), revision_of(args.bin),
                    time.strftime("%Y-%m-%d"), os.cpu_count(), load[0], load[1]))
    lines.append("")
    lines.append("The database: %d runs: %d succeeded (%d of them imported from a second server, "
                 "%d labelled by a person), %d failed, %d queued, %d cancelled (the rest running); "
                 "%d of the fast preset, %d of the default%s."
                 % (total, held["succeeded"], held["imported"], held["labelled"], held["failed"],
                    held["queued"], held["cancelled"], held["presets"]["fast"], held["presets"]["default"],
                    ", filled in %.0f s" % notes["fill_s"] if notes else ", filled before (%s)" % args.db))
    lines += ["", "Each request after a commit (no cached answer); %d rounds (the CSV %d)." % (
        args.rounds, max(3, args.rounds // 3)), "",
        "| request | median | p90 | server CPU / request | answer |", "|---|---|---|---|---|"]
    for name, path, med, p90, cpu, size in rows:
        lines.append("| %s | %.1f ms | %.1f ms | %.1f ms | %s |" % (
            name, med * 1e3, p90 * 1e3, cpu, "%.1f MB" % (size / 1e6) if size > 1e6 else "%.1f kB" % (size / 1e3)))
    lines += ["", "Migrations 0012, 0014 and 0015 on a copy of this database without the run table (the "
              "backfill of every run: the preset read from each scene, the geometry, the features read "
              "from each result): the server listened %.1f s after its start." % upgrade_s]
    if write_rows:
        lines += ["", "What the triggers cost the writes (a new database each; medians):", "",
                  "| server | POST /sweeps of 2 000 jobs | lease + complete cycles/s, 16 Python fake workers |",
                  "|---|---|---|"]
        for who, (create_s, rate) in write_rows:
            lines.append("| %s | %.0f ms | %.0f |" % (who, create_s * 1e3, rate))
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default=os.path.join(REPO, "build", "bin"))
    ap.add_argument("--baseline")
    ap.add_argument("--db", help="a database filled before: measure it instead of filling one")
    ap.add_argument("--keep", help="where to write the filled database")
    ap.add_argument("--rounds", type=int, default=15)
    ap.add_argument("--sweeps", type=int, default=SWEEPS, help="completed sweeps of 2 000 runs (a smaller fill to try the script)")
    ap.add_argument("--baseline-rev", help="the commit of --baseline, when its folder is no checkout")
    ap.add_argument("--out", default=os.path.join(REPO, "bench", "results", "jobs_table.md"))
    args = ap.parse_args()
    workdir = tempfile.mkdtemp(prefix="jobs-table-bench-")
    load = [os.getloadavg()[0]]
    try:
        notes = {}
        db = args.db
        if not db:
            db = args.keep or os.path.join(workdir, "table.db")
            notes = fill(args.bin, workdir, db, args.sweeps)
            print("filled in %.0f s: %s" % (notes["fill_s"], notes), file=sys.stderr)
        total, held, rows = answers(args.bin, workdir, db, args.rounds)
        upgrade_s = upgrade(args.bin, workdir, db)
        write_rows = []
        if args.baseline:
            for _ in range(2):
                for who, b in (("baseline (%s)" % (args.baseline_rev or revision_of(args.baseline)), args.baseline),
                               ("this build (%s)" % revision_of(args.bin), args.bin)):
                    write_rows.append((who, writes(b, workdir)))
        load.append(os.getloadavg()[0])
        text = report(args, notes, total, held, rows, upgrade_s, write_rows, load)
        with open(args.out, "w") as f:
            f.write(text)
        print(text)
    finally:
        shutil.rmtree(workdir, ignore_errors=True)


if __name__ == "__main__":
    main()
