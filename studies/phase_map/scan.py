"""A grid sweep of the service as a table of labels: how a region of the phase map looks at a
resolution finer than the map's, e.g. around one of the paper's examples.

usage: PYTHONPATH=python python3 -m studies.phase_map.scan --server URL --sweep ID --name NAME
       [--out studies/phase_map/results]

Writes OUT/NAME.png (labels on the grid, marker size by confidence, the paper's examples as
stars), OUT/NAME.md (the label table and how often neighbouring points differ) and
OUT/NAME.export.json (the sweep's export without artifacts, which another server imports).
"""
import argparse
import math
import os
import sys

from compaction_client import Client
from studies.lib import examples
from studies.lib.cells import fmt
from studies.phase_map.fig2 import ROOT, class_looks, job_of, mark_people_and_unlabelled, save, scatter_classes


def table(done):
    """{(S, R): job}, the sorted S values and the sorted R values of a grid sweep's runs."""
    at = {(j["S"], j["R"]): j for j in done}
    return at, sorted({j["S"] for j in done}), sorted({j["R"] for j in done})


def neighbour_changes(at, ss, rs):
    """How many pairs of grid neighbours, along R and along S, carry different labels."""
    counts = {}
    for axis in ("R", "S"):
        pairs = differ = 0
        for i, S in enumerate(ss):
            for k, R in enumerate(rs):
                nxt = (S, rs[k + 1]) if axis == "R" and k + 1 < len(rs) else \
                    (ss[i + 1], R) if axis == "S" and i + 1 < len(ss) else None
                if nxt is None or (S, R) not in at or nxt not in at:
                    continue
                a, b = at[(S, R)]["label"], at[nxt]["label"]
                if a and b:
                    pairs += 1
                    differ += a != b
        counts[axis] = (differ, pairs)
    return counts


def draw(path, done, looks, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 6.4))
    scatter_classes(ax, done, looks, size=(15, 60))
    mark_people_and_unlabelled(ax, done)
    xs = [math.log10(j["S"]) for j in done]
    ys = [math.log10(j["R"]) for j in done]
    for k, (S, R) in examples.EXAMPLES.items():
        x, y = math.log10(S), math.log10(R)
        if min(xs) - 0.05 <= x <= max(xs) + 0.05 and min(ys) - 0.05 <= y <= max(ys) + 0.05:
            ax.scatter([x], [y], marker="*", s=420, facecolors="none", edgecolors="black",
                       linewidths=1.2, zorder=5)
            ax.annotate("(%s)" % k, (x, y), xytext=(9, -12), textcoords="offset points",
                        fontsize=10, weight="bold", zorder=5)
    ax.set_xlim(min(xs) - 0.04, max(xs) + 0.04)
    ax.set_ylim(min(ys) - 0.06, max(ys) + 0.06)
    ax.set_xlabel("log10 S")
    ax.set_ylabel("log10 R")
    ax.set_title(title, fontsize=9)
    save(fig, ax, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--server", required=True, help="the server's URL, e.g. http://127.0.0.1:8080")
    ap.add_argument("--sweep", type=int, required=True, help="the grid sweep's id")
    ap.add_argument("--name", required=True, help="the files' name, e.g. example-c")
    ap.add_argument("--out", default=os.path.join(ROOT, "studies", "phase_map", "results"))
    a = ap.parse_args()
    client = Client(a.server)
    sweep = client.sweep(a.sweep)
    if "adaptive" in sweep["request"]:
        sys.exit("scan.py: sweep %d is adaptive; studies/phase_map/fig2.py draws those" % a.sweep)
    os.makedirs(a.out, exist_ok=True)
    client.export_archive(a.sweep, os.path.join(a.out, "%s.export.json" % a.name), artifacts="none")
    jobs = [job_of(r) for r in client.results(a.sweep, frame=False)]
    done = [j for j in jobs if j["state"] == "succeeded"]
    if not done:
        sys.exit("scan.py: sweep %d has no finished run yet" % a.sweep)
    at, ss, rs = table(done)
    looks = class_looks()
    step = lambda v: math.log10(v[-1] / v[0]) / (len(v) - 1) if len(v) > 1 else 0.0  # noqa: E731
    draw(os.path.join(a.out, "%s.png" % a.name), done, looks,
         "sweep %d, %s: %d runs, %.3g x %.3g decades" % (a.sweep, sweep["name"], len(done),
                                                         step(ss), step(rs)))
    cpu = sum(j["wall"] for j in done if j["wall"])
    counts = {k: sum(1 for j in done if j["label"] == k) for k in "abcdef"}
    changes = neighbour_changes(at, ss, rs)
    lines = ["<!-- written by python3 -m studies.phase_map.scan --server %s --sweep %d --name %s; do not "
             "edit -->" % (a.server, a.sweep, a.name), "",
             "| | |", "|---|---|",
             "| sweep | %d, %s, %s |" % (a.sweep, sweep["name"], sweep["state"]),
             "| runs done / in the sweep | %d / %d |" % (len(done), len(jobs)),
             "| grid | %d S from %s to %s x %d R from %s to %s: steps of %.3g and %.3g decades |"
             % (len(ss), fmt(ss[0]), fmt(ss[-1]), len(rs), fmt(rs[0]), fmt(rs[-1]), step(ss),
                step(rs)),
             "| run time, summed over the runs | %.0f s = %.2f core-hours |" % (cpu, cpu / 3600),
             "| labels | %s; no label %d |" % (", ".join("(%s) %d" % (k, counts[k]) for k in "abcdef"),
                                              len(done) - sum(counts.values())),
             "| neighbours with different labels | along R: %d of %d; along S: %d of %d |"
             % (changes["R"] + changes["S"]), ""]
    lines += ["Labels (and confidence in tenths, 0 to 9, X for 1.0): R downwards from the top, "
              "S across; a person's label in capitals:", "",
              "| R \\ S | " + " | ".join(fmt(S, 3) for S in ss) + " |",
              "|---|" + "---|" * len(ss)]
    for R in reversed(rs):
        cells = []
        for S in ss:
            j = at.get((S, R))
            if j is None:
                cells.append(" ")
            elif not j["label"]:
                cells.append("-")
            else:
                c = j["confidence"] or 0
                cells.append("%s%s" % (j["label"].upper() if j["person"] else j["label"],
                                       "X" if c >= 0.95 else int(c * 10)))
        lines.append("| %s | %s |" % (fmt(R, 3), " | ".join(cells)))
    with open(os.path.join(a.out, "%s.md" % a.name), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("scan.py: %d runs of %d done; wrote %s/%s.{png,md,export.json}"
          % (len(done), len(jobs), a.out, a.name))


if __name__ == "__main__":
    main()
