"""The time of one long run of an example on N threads, as a researcher would run it.

Runs one of the paper's examples (studies/lib/examples.py; phi = 0.4, pseudo-1D) with
compaction-run at the resolution and pore contact given (default: the reference preset's
9 cells across a strut, 40 per unit cell, with its pore contact auto) to --eps-end on
--threads threads, and writes a Markdown report: wall and CPU time (the runner's own, from
wait4), ns per particle-step and per stage, the label and both readings of c_b/V that the
classifier gives, and the machine's state before the run (load average, CPUs). A single run
has no median: the report says so, and the engine's per-stage split shows where the time went.

usage: python3 -m bench.threads.long_run [--example b] [--cells-per-strut 9] [--eps-end 0.6]
       [--threads 2] [--pore-contact auto] [--bin DIR] [--work DIR] [--out FILE]
"""
import argparse
import datetime
import os
import subprocess
import sys
import time

from studies.lib import examples, runs

STAGES = ("p2g", "grid_update", "g2p", "diagnostics")


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown CPU"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--example", default="b", choices=sorted(examples.EXAMPLES))
    ap.add_argument("--cells-per-strut", type=float, default=9.0,
                    help="resolution across the thinnest strut [9: the reference preset]")
    ap.add_argument("--eps-end", type=float, default=0.6)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--pore-contact", default="auto", choices=("auto", "single_field", "split_fields"))
    ap.add_argument("--bin", default=os.path.join(runs.ROOT, "build", "bin"))
    ap.add_argument("--work", default=None, help="the run's bundle goes here [a temporary name]")
    ap.add_argument("--out", help="write the report here as well as to stdout")
    a = ap.parse_args()
    if a.threads < 1:
        ap.error("--threads must be at least 1")
    run_bin = os.path.join(a.bin, "compaction-run")
    if not os.access(run_bin, os.X_OK):
        ap.error("--bin: %s is not an executable" % run_bin)
    S, R = examples.EXAMPLES[a.example]
    out = a.work or "/tmp/long_run-%s-%d" % (a.example, os.getpid())
    if os.path.exists(os.path.join(out, "summary.json")):
        ap.error("--work: %s holds a finished run; give a new folder" % out)
    flags = {"phi": examples.PHI, "S": S, "R": R, "cells_per_strut": a.cells_per_strut,
             "eps_end": a.eps_end, "pore_contact": a.pore_contact, "snapshot_eps": "",
             "threads": a.threads, "progress": "log"}  # the last --threads, --progress wins
    cmd = runs.command(out, flags, run=run_bin)
    load = os.getloadavg()
    started = datetime.datetime.now(datetime.timezone.utc)
    print("running:", " ".join(cmd), file=sys.stderr, flush=True)
    t0 = time.monotonic()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL)  # its errors (a bad flag) pass through
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.monotonic() - t0
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit("compaction-run failed (exit %d); its bundle is in %s"
                 % (os.waitstatus_to_exitcode(status), out))
    cpu = usage.ru_utime + usage.ru_stime
    s = runs.summary(out)
    m = runs.reading(out, os.path.join(a.bin, "compaction-classify"))
    per = 1e9 / (s["steps"] * s["n_particles"])
    rev = subprocess.run(["git", "-C", runs.ROOT, "rev-parse", "--short", "HEAD"],
                         capture_output=True, text=True).stdout.strip() or "unknown"

    def fmt(v, digits=4):
        return "-" if v is None else "%.*g" % (digits, v)
    lines = [
        "## (%s) at %g cells across a strut to eps = %g on %d thread(s), pore contact %s"
        % (a.example, a.cells_per_strut, a.eps_end, a.threads, a.pore_contact), "",
        "Made by `python3 -m bench.threads.long_run %s`, started %s, %d CPUs (%s), load average %.2f "
        "%.2f %.2f (1, 5, 15 min) before; checkout at %s, engine %s (source revision %s). One "
        "run: no median; this machine's speed drifts by up to 20 %% within an hour "
        "(bench/results/threads_before_after.md)."
        % (" ".join(sys.argv[1:]), started.strftime("%Y-%m-%dT%H:%M:%S UTC"), os.cpu_count(),
           cpu_model(), load[0], load[1], load[2], rev, s["engine_version"], s["source_revision"]),
        "",
        "| S | R | particles | grid | steps | wall [s] | CPU [s] | CPU / wall | ns / particle-step | P2G | grid update | G2P | diagnostics |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
        "| %g | %g | %d | %d x %d, %s | %d | %.1f | %.1f | %.2f | %.1f | %s |"
        % (S, R, s["n_particles"], s["grid"]["nx"], s["grid"]["ny"], s["grid"]["pore_contact"],
           s["steps"], wall, cpu, cpu / wall, s["ns_per_particle_step"],
           " | ".join("%.1f" % (s["stage_seconds"][k] * per) for k in STAGES)),
        "",
        "Status %s, eps reached %g; label %s (confidence %s), N_r %s, c_b/V %s +- %s (fit), "
        "%s +- %s (transit)."
        % (s["status"], s["eps_reached"], m["label"], fmt(m["confidence"], 2), m["n_r"],
           fmt(m["fit"]), fmt(m["fit_err"], 2), fmt(m["transit"]), fmt(m["transit_err"], 2)),
        ""]
    text = "\n".join(lines)
    print(text)
    if a.out:
        with open(a.out, "a") as f:
            f.write(text + "\n")


if __name__ == "__main__":
    main()
