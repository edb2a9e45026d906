"""Engine speed of two builds of compaction-run on one scene, run alternately in one session.

Runs each binary on the large scene (pseudo-1D, phi = 0.4, 40 cells per unit cell, 86 904
particles, eps 0 -> 0.002) with one and with two velocity fields, on one and on two threads,
`--rounds` times in alternation (the first build of each pair changing every round), and
prints a Markdown report: medians of ns per particle-step and of each stage, the two-thread
speed-up of each build and after / before. The bundles' space-time maps of the two builds are
compared byte for byte on one thread.

usage: python3 -m bench.threads.before_after --before BIN --after BIN [--rounds 3] [--out FILE]
"""
import argparse
import filecmp
import os
import statistics
import subprocess
import sys
import tempfile

from studies.lib import runs

SCENE = {"cells_per_unit": 40, "eps_end": 0.002, "snapshot_eps": "", "movie_d_eps": 0}
CASES = [(contact, threads) for contact in ("single_field", "split_fields") for threads in (1, 2)]
STAGES = ("p2g", "grid_update", "g2p")


def run(binary, contact, threads, out):
    flags = {**SCENE, "pore_contact": contact, "threads": threads}  # the last --threads wins
    subprocess.run(runs.command(out, flags, run=binary), check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    s = runs.summary(out)
    per = 1e9 / (s["steps"] * s["n_particles"])
    row = {"total": s["ns_per_particle_step"], "particles": s["n_particles"]}
    row.update({k: s["stage_seconds"][k] * per for k in STAGES})
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--before", required=True, help="compaction-run of the earlier build")
    ap.add_argument("--after", required=True, help="compaction-run of the later build")
    ap.add_argument("--rounds", type=int, default=3, help="alternating rounds (default 3)")
    ap.add_argument("--out", help="write the report here as well as to stdout")
    a = ap.parse_args()
    if a.rounds < 1:
        ap.error("--rounds must be at least 1")
    builds = {"before": a.before, "after": a.after}
    for name, path in builds.items():
        if not os.access(path, os.X_OK):
            ap.error(f"--{name}: {path} is not an executable")
    rows = {(b, c, t): [] for b in builds for c, t in CASES}
    same = {}
    with tempfile.TemporaryDirectory() as work:
        for r in range(a.rounds):
            for c, t in CASES:
                order = list(builds.items())
                if r % 2:  # every other round the after build first: no bias of the order
                    order.reverse()
                for b, path in order:
                    out = os.path.join(work, f"{b}-{c}-{t}")
                    rows[(b, c, t)].append(run(path, c, t, out))
                    print(f"round {r + 1}: {b} {c} {t} thread(s): "
                          f"{rows[(b, c, t)][-1]['total']:.1f} ns", file=sys.stderr)
                if t == 1 and r == 0:
                    same[c] = filecmp.cmp(os.path.join(work, f"before-{c}-1", "spacetime.npy"),
                                          os.path.join(work, f"after-{c}-1", "spacetime.npy"),
                                          shallow=False)
    med = {k: {f: statistics.median(x[f] for x in v) for f in ("total", *STAGES)}
           for k, v in rows.items()}
    n = rows[("after", "single_field", 1)][0]["particles"]
    lines = ["| build | pore contact | threads | ns / particle-step | P2G | grid update | G2P |",
             "|---|---|---|---|---|---|---|"]
    for c, t in CASES:
        for b in builds:
            m = med[(b, c, t)]
            lines.append(f"| {b} | {c} | {t} | {m['total']:.1f} | {m['p2g']:.1f} | "
                         f"{m['grid_update']:.1f} | {m['g2p']:.1f} |")
    lines += ["", "Two threads against one (one thread's ns over two threads'):", ""]
    for c in ("single_field", "split_fields"):
        for b in builds:
            one, two = med[(b, c, 1)], med[(b, c, 2)]
            lines.append(f"- {b}, {c}: {one['total'] / two['total']:.2f} (P2G "
                         f"{one['p2g'] / two['p2g']:.2f}, G2P {one['g2p'] / two['g2p']:.2f})")
    lines += ["", "After over before (ns / particle-step):", ""]
    for c, t in CASES:
        lines.append(f"- {c}, {t} thread(s): "
                     f"{med[('after', c, t)]['total'] / med[('before', c, t)]['total']:.2f}")
    lines += ["", "Space-time maps of the two builds on one thread, byte for byte: " +
              ", ".join(f"{c} {'identical' if ok else 'DIFFERENT'}" for c, ok in same.items())]
    head = [f"{n} particles, medians of {a.rounds} alternating rounds.", ""]
    text = "\n".join(head + lines) + "\n"
    print(text)
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()
