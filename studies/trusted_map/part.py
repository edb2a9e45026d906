"""One part of the trusted map (issue 47, item 4): the adaptive sweep with replicates and two
levels over the (a)/(b)/(d) meeting region at phi = 0.4, run by the project's own server and
workers for a while, then exported, so that the map grows across sessions.

Each part starts a server on a fresh database in --work, imports the sweep's export of the part
before it (results/trusted.export.json, when there is one), submits the same request (REQUEST
below: its runs done before are found by identity and reused at once, and the planner goes on from
them), runs --workers workers until the planner has nothing left, --hours have passed or SIGINT or
SIGTERM asks it to end, stops them (a run cut short checkpoints into this part's database and is
run again by a later part), and writes the sweep's export over results/trusted.export.json (the
archive the next part imports) and results/trusted.map.json (its points and runs), a line per part
to results/parts.md: the runs done per level, the CPU-hours the runs took (their wall time on one
core each) and the cost model's, the plan's state; then the report (report.py, results/report.md)
is made again from the new export.

    PYTHONPATH=python python3 -m studies.trusted_map.part --hours 2
"""
import argparse
import datetime
import json
import os
import signal
import subprocess
import sys
import tempfile
import time

from compaction_client import Client
from studies.lib import kept_notes
from studies.trusted_map import report

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
RESULTS = os.path.join(ROOT, "studies", "trusted_map", "results")
EXPORT = os.path.join(RESULTS, "trusted.export.json")  # the archive the next part imports
MAP = os.path.join(RESULTS, "trusted.map.json")  # the sweep's JSON export: its points, the report's

# Issue 47's body: the box S 3e-3..3e-2, R 1e-5..1e-2 at phi 0.4 (examples (a) and (b) inside),
# 4 replicates perturbed by 1 % of the particle spacing, the default preset and 8 cells across a
# strut, a quarter decade.
REQUEST = {"name": "trusted", "phi": 0.4, "replicates": {"n": 4, "perturbation": 0.01},
           "adaptive": {"S": {"min": 3e-3, "max": 3e-2}, "R": {"min": 1e-5, "max": 1e-2},
                        "initial": {"S": 3, "R": 4}, "resolution_decades": 0.25, "budget": 400,
                        "budget_cpu_hours": 40,
                        "levels": [{"preset": "default"}, {"cells_per_strut": 8}]}}


def start_server(bin_dir, work):
    port_file = os.path.join(work, "port")
    log = open(os.path.join(work, "server.log"), "w")
    server = subprocess.Popen([os.path.join(bin_dir, "compaction-server"), "--db",
                               os.path.join(work, "trusted.db"), "--port", "0", "--port-file",
                               port_file], stdout=log, stderr=subprocess.STDOUT)
    for _ in range(100):
        if os.path.exists(port_file) and open(port_file).read().strip():
            return server, "http://127.0.0.1:%s" % open(port_file).read().strip()
        time.sleep(0.1)
    server.kill()
    sys.exit("the server did not start; see %s" % log.name)


def start_workers(bin_dir, work, url, n):
    workers = []
    for i in range(n):
        log = open(os.path.join(work, "worker-%d.log" % i), "w")
        workers.append(subprocess.Popen(
            [os.path.join(bin_dir, "compaction-worker"), "--server", url, "--name", "trusted-%d" % i,
             "--work-dir", os.path.join(work, "w%d" % i)], stdout=log, stderr=subprocess.STDOUT))
    return workers


class StopEarly:
    """SIGINT or SIGTERM ends the part at its next look at the plan, as its deadline would: the
    workers stop (a run cut short checkpoints), the export and the line in parts.md are written."""

    def __init__(self):
        self.asked = False
        for sig in (signal.SIGINT, signal.SIGTERM):
            signal.signal(sig, self.ask)

    def ask(self, signum, _frame):
        print("%s: ending the part" % signal.Signals(signum).name, flush=True)
        self.asked = True


def level_of(job, levels):
    return levels.get(job["cells_per_unit"])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "bin"))
    ap.add_argument("--hours", type=float, default=1.0, help="wall hours of this part")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--work", help="the part's folder (a new temporary one by default)")
    a = ap.parse_args()
    if a.hours <= 0 or a.workers < 1:
        ap.error("--hours must be > 0 and --workers >= 1")
    work = a.work or tempfile.mkdtemp(prefix="trusted-map-")
    os.makedirs(work, exist_ok=True)
    started = time.time()
    server, url = start_server(a.bin, work)
    workers = []
    try:
        client = Client(url)
        engine = client.health()["engine_version"]
        if os.path.exists(EXPORT):
            print("imported:", client.import_archive(EXPORT))
        sweep = client._json("POST", "/sweeps", REQUEST, write=True)
        print("sweep %d: %s" % (sweep["id"], sweep["created"]))
        before = {j["id"] for j in client.jobs(sweep=sweep) if j["state"] == "succeeded"}
        workers = start_workers(a.bin, work, url, a.workers)
        deadline = started + a.hours * 3600
        stop = StopEarly()
        plan = client.plan(sweep)
        while time.time() < deadline and not stop.asked:
            plan = client.plan(sweep)
            if plan["state"] not in ("running", "planning"):
                break
            print("%s %s runs %s, %.2f CPU-hours by the model" % (
                time.strftime("%H:%M:%S"), plan["state"], plan["runs"], plan["cpu_hours"]["spent"]),
                flush=True)
            for _ in range(60):
                if stop.asked:
                    break
                time.sleep(1)
    finally:
        for w in workers:
            w.send_signal(signal.SIGTERM)
        for w in workers:
            w.wait(timeout=600)
    plan = client.plan(sweep)
    jobs = client.jobs(sweep=sweep)
    levels = {lvl["cells_per_unit"]: i for i, lvl in enumerate(plan["levels"])}
    new = [j for j in jobs if j["state"] == "succeeded" and j["id"] not in before]
    cpu = sum((j["result"] or {}).get("wall_seconds") or 0 for j in new) / 3600
    per_level = {}
    for j in new:
        per_level[level_of(j, levels)] = per_level.get(level_of(j, levels), 0) + 1
    client.export_archive(sweep, EXPORT, artifacts="none")
    with open(MAP, "w") as f:
        json.dump(client._json("GET", "/sweeps/%d/export" % sweep["id"], query={"format": "json"}),
                  f, indent=1, sort_keys=True)
    server.send_signal(signal.SIGTERM)
    server.wait(timeout=60)
    line = ("- %s, %.2f h, %d workers: %d new runs (per level %s), %.2f CPU-hours of run time; "
            "the sweep holds %d runs (%s), %.2f CPU-hours by the cost model, plan %s; engine %s" % (
                datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
                (time.time() - started) / 3600, a.workers, len(new),
                json.dumps({str(k): v for k, v in sorted(per_level.items())}), cpu,
                plan["runs"]["done"], ", ".join("level %d: %d points, %d robust" % (
                    i, lvl["points"], lvl["robust"]) for i, lvl in enumerate(plan["levels"])),
                plan["cpu_hours"]["spent"], plan["state"], engine))
    parts = os.path.join(RESULTS, "parts.md")
    if not os.path.exists(parts):
        with open(parts, "w") as f:
            f.write("# The trusted map, part by part\n\nMade by `PYTHONPATH=python python3 -m "
                    "studies.trusted_map.part --hours H`, one line per part, oldest first; the "
                    "sweep's export after the last part is [trusted.export.json](trusted.export.json).\n\n")
    with open(parts, "a") as f:
        f.write(line + "\n")
    print(line)
    with open(MAP) as f:
        kept_notes.write(report.REPORT, "\n".join(report.report(json.load(f))))
    print("report:", report.REPORT)


if __name__ == "__main__":
    main()
