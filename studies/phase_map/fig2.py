"""The paper's Fig. 2 from an adaptive sweep of the service: the phase map at one phi, the six
examples marked, and what the sweep cost against the full grid of the same resolution.

It reads a running or finished server through the Python client (python/compaction_client):
the sweep's export (every job with its scene, timings and result), its plan (GET
/sweeps/{id}/plan: state, runs against the budget, the equivalent full grid) and, when the
server serves them, the predicted regions (GET /phase-map/regions) drawn as the background.

usage: PYTHONPATH=python python3 -m studies.phase_map.fig2 --server URL --sweep ID
       [--out studies/phase_map/results]

Writes OUT/fig2.png (the map), OUT/fig2.md (the tables the doc quotes) and
OUT/sweep-ID.export.json (the sweep's export without artifacts, which another server imports, to
commit beside the doc).
"""
import argparse
import math
import os
import re
import sys

from compaction_client import ApiError, Client
from studies.lib import examples
from studies.lib.cells import fmt
from studies.lib.runs import ROOT
from studies.phase_map.compare import comparison


def class_looks():
    """Colour and name of each class, from the dashboard's one home of them (web/js/classes.js)."""
    text = open(os.path.join(ROOT, "web", "js", "classes.js")).read()
    found = re.findall(r"^\s*([a-f]): \{ name: '([^']+)', color: '(#[0-9A-Fa-f]{6})'", text, re.M)
    if len(found) != 6:
        sys.exit("fig2.py: web/js/classes.js no longer lists the six classes as expected")
    return {k: (name, color) for k, name, color in found}


MARKERS = {"a": "o", "b": "s", "c": "D", "d": "^", "e": "v", "f": "h"}  # as web/js/classes.js


def buckling_onset(phi):
    """R_crit = pi^2 a^2 / 12 with the strut aspect ratio a = t / (L sqrt(1 - phi)),
    t = L (1 - sqrt(1 - phi)) (the paper; web/js/physics.js draws the same line)."""
    a = (1 - math.sqrt(1 - phi)) / math.sqrt(1 - phi)
    return math.pi ** 2 * a ** 2 / 12


def load(client, sweep_id):
    sweep = client.sweep(sweep_id)
    rows = client.results(sweep_id, frame=False)
    plan = client.plan(sweep_id, limit=0)
    phi = float(sweep["request"]["phi"])
    try:
        regions = client.regions(phi, sweep=sweep_id)
    except ApiError:
        regions = None  # a server without the endpoint: the map without a background
    return sweep, rows, plan, phi, regions


def nearest(jobs, S, R):
    """The labelled job nearest to (S, R) in log space, and its distance in decades."""
    best = None
    for j in jobs:
        d = math.hypot(math.log10(j["S"] / S), math.log10(j["R"] / R))
        if best is None or d < best[1]:
            best = (j, d)
    return best


# A run this close (in decades of log S and log R at once) stands for an example's point; further
# away the map's predicted region answers instead.
NEAR_DECADES = 0.25


def predicted(regions, S, R):
    """The class the regions endpoint predicts at (S, R) and its uncertainty, or (None, None)."""
    if not regions or not regions.get("classes"):
        return None, None
    n = regions["grid"]
    fx = (math.log10(S) - regions["S"]["log_min"]) / (regions["S"]["log_max"] - regions["S"]["log_min"])
    fy = (math.log10(R) - regions["R"]["log_min"]) / (regions["R"]["log_max"] - regions["R"]["log_min"])
    if not (0 <= fx <= 1 and 0 <= fy <= 1):
        return None, None
    i, j = min(int(fx * n), n - 1), min(int(fy * n), n - 1)
    c = regions["classes"][j][i]
    return (None if c == "." else c), regions["uncertainty"][j][i]


def job_of(r):
    """One run of the sweep's results as the figure and tables read it. The label that counts is
    a person's where there is one (docs/service.md, "Human labels"), certain, with the
    classifier's beside it, as the map, its regions and the planner read it."""
    human = r.get("human_label")
    return {"id": r["job_id"], "S": r["S"], "R": r["R"], "state": r["state"],
            "label": human["label"] if human else r["class"],
            "classifier": r["class"], "person": human is not None,
            "confidence": 1.0 if human else r["confidence"],
            "runner_up": r["class"] if human else r["runner_up"],
            "n_reflections": r["n_reflections"], "c_b": r["band_speed_ratio"],
            "wall": r["wall_seconds"], "status": r["status"], "started": r.get("started_at"),
            "finished": r.get("finished_at"), "revision": r["source_revision"]}


def label_text(j):
    """A run's label for the tables: a person's marked as such, with the classifier's."""
    if j["person"]:
        return "%s (person; classifier %s)" % (j["label"], j["classifier"] or "-")
    return j["label"] or "-"


def draw(path, phi, jobs, regions, looks, box):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import ListedColormap
    import numpy as np

    fig, ax = plt.subplots(figsize=(7.2, 6.0))
    (s_lo, s_hi), (r_lo, r_hi) = box
    if regions and regions.get("classes"):
        letters = "abcdef"
        rows = regions["classes"]  # one string per row of R, low R first; '.' no class
        grid = np.array([[letters.index(c) if c in letters else np.nan for c in row]
                         for row in rows], dtype=float)
        unc = np.array(regions["uncertainty"], dtype=float)
        extent = [regions["S"]["log_min"], regions["S"]["log_max"],
                  regions["R"]["log_min"], regions["R"]["log_max"]]
        cmap = ListedColormap([looks[k][1] for k in letters])
        ax.imshow(grid, origin="lower", extent=extent, aspect="auto", cmap=cmap, vmin=-0.5,
                  vmax=5.5, alpha=0.28, interpolation="nearest")
        ax.imshow(np.where(unc > 0.5, 1.0, np.nan), origin="lower", extent=extent, aspect="auto",
                  cmap=ListedColormap(["#ffffff"]), alpha=0.55, interpolation="nearest")
    scatter_classes(ax, jobs, looks, size=(20, 50))
    for j in jobs:
        if j["label"] == "b" and j["n_reflections"] is not None:
            ax.annotate(str(j["n_reflections"]), (math.log10(j["S"]), math.log10(j["R"])),
                        xytext=(4, 3), textcoords="offset points", fontsize=6, zorder=4)
    mark_people_and_unlabelled(ax, jobs)
    for k, (S, R) in examples.EXAMPLES.items():
        ax.scatter([math.log10(S)], [math.log10(R)], marker="*", s=260, facecolors="none",
                   edgecolors="black", linewidths=1.0, zorder=5)
        ax.annotate("(%s)" % k, (math.log10(S), math.log10(R)), xytext=(7, -10),
                    textcoords="offset points", fontsize=9, weight="bold", zorder=5)
    rc = buckling_onset(phi)
    ax.axhline(math.log10(rc), color="#CC79A7", ls="--", lw=1)
    ax.text(math.log10(s_hi), math.log10(rc) - 0.12, "R_crit = pi^2 a^2/12 = %.3f" % rc,
            fontsize=7, color="#7a3d64", ha="right")
    ax.set_xlim(math.log10(s_lo) - 0.08, math.log10(s_hi) + 0.08)
    ax.set_ylim(math.log10(r_lo) - 0.15, math.log10(r_hi) + 0.15)
    ax.set_xlabel("log10 S = log10 V / sqrt(E / rho)")
    ax.set_ylabel("log10 R = log10 q_y / E")
    ax.set_title("phi = %g: %d runs; stars: the paper's six examples; numbers: N_r of (b)"
                 % (phi, len(jobs)), fontsize=9)
    save(fig, ax, path)


def scatter_classes(ax, jobs, looks, size):
    """One marker per run in its class's shape and colour (web/js/classes.js), of area
    size[0] + size[1] x confidence, with a legend entry per class that has runs."""
    for k in "abcdef":
        pts = [j for j in jobs if j["label"] == k]
        if pts:
            ax.scatter([math.log10(j["S"]) for j in pts], [math.log10(j["R"]) for j in pts],
                       marker=MARKERS[k], s=[size[0] + size[1] * (j["confidence"] or 0) for j in pts],
                       c=looks[k][1], edgecolors="#1d2433", linewidths=0.5,
                       label="(%s) %s: %d" % (k, looks[k][0], len(pts)), zorder=3)


def mark_people_and_unlabelled(ax, jobs):
    """The dashboard's dot on a label a person set (web/js/humanlabels.js), a cross on no label."""
    people = [j for j in jobs if j["person"]]
    if people:
        ax.scatter([math.log10(j["S"]) for j in people], [math.log10(j["R"]) for j in people],
                   marker="o", s=9, c="black", edgecolors="white", linewidths=0.6, zorder=4,
                   label="dot: label set by a person: %d" % len(people))
    other = [j for j in jobs if not j["label"]]
    if other:
        ax.scatter([math.log10(j["S"]) for j in other], [math.log10(j["R"]) for j in other],
                   marker="x", s=25, c="#555555", label="no label: %d" % len(other), zorder=3)


def save(fig, ax, path):
    """The legend beside the axes, the figure written to `path` and closed."""
    import matplotlib.pyplot as plt
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--server", required=True, help="the server's URL, e.g. http://127.0.0.1:8080")
    ap.add_argument("--sweep", type=int, required=True, help="the adaptive sweep's id")
    ap.add_argument("--out", default=os.path.join(ROOT, "studies", "phase_map", "results"))
    a = ap.parse_args()
    client = Client(a.server)
    sweep, rows, plan, phi, regions = load(client, a.sweep)
    os.makedirs(a.out, exist_ok=True)
    # The file another server imports (compaction-server --import), without the runs' files:
    # a few kB a run (schema/sweep-export.md).
    client.export_archive(a.sweep, os.path.join(a.out, "sweep-%d.export.json" % a.sweep),
                          artifacts="none")

    jobs = [job_of(r) for r in rows]
    done = [j for j in jobs if j["state"] == "succeeded"]
    req = sweep["request"]["adaptive"]
    box = ((req["S"]["min"], req["S"]["max"]), (req["R"]["min"], req["R"]["max"]))
    looks = class_looks()
    draw(os.path.join(a.out, "fig2.png"), phi, done, regions, looks, box)

    cpu = sum(j["wall"] for j in done if j["wall"])
    starts = [j["started"] for j in jobs if j["started"]]
    ends = [j["finished"] for j in jobs if j["finished"]]
    elapsed = (max(ends) - min(starts)) / 1000 if starts and ends else None
    counts = {k: sum(1 for j in done if j["label"] == k) for k in "abcdef"}
    lines = ["<!-- written by python3 -m studies.phase_map.fig2 --server %s --sweep %d; do not edit -->"
             % (a.server, a.sweep), ""]
    lines += ["| | |", "|---|---|",
              "| sweep | %d, %s, state of its plan: **%s** |" % (a.sweep, sweep["name"],
                                                              plan["state"]),
              "| runs done / queued or running / budget | %d / %d / %d |"
              % (plan["runs"]["done"], plan["runs"]["pending"], plan["runs"]["budget"]),
              "| full grid of the same resolution | %d x %d = %d points (%.3g x %.3g decades) |"
              % (plan["lattice"]["S"], plan["lattice"]["R"], plan["lattice"]["points"],
                 plan["lattice"]["step_S_decades"], plan["lattice"]["step_R_decades"]),
              "| runs of the sweep against that grid | %.1f %% |"
              % (100.0 * len(jobs) / plan["lattice"]["points"]),
              "| run time, summed over the runs (one core each) | %.0f s = %.2f core-hours |"
              % (cpu, cpu / 3600),
              "| wall time, first start to last finish | %s |"
              % ("-" if elapsed is None else "%.0f s = %.2f h" % (elapsed, elapsed / 3600)),
              "| labels | %s; no label %d |" % (", ".join("(%s) %d" % (k, counts[k]) for k in "abcdef"),
                                               len(done) - sum(counts.values())),
              "| labels set by a person (the classifier's beside them below) | %d |"
              % sum(1 for j in done if j["person"]),
              "| engine revisions | %s |" % ", ".join(sorted({j["revision"] or "-" for j in done})),
              ""]
    lines += ["The paper's six examples: the run of the map within %g decade (of log S and log R "
              "at once), if any, and the class the map's regions predict there (uncertainty in "
              "[0, 1], GET /phase-map/regions):" % NEAR_DECADES, "",
              "| example | S | R | run | label | confidence | runner-up | N_r | c_b/V | "
              "predicted | uncertainty |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    labelled = [j for j in done if j["label"]]
    for k, (S, R) in examples.EXAMPLES.items():
        hit = nearest(labelled, S, R) if labelled else None
        guess, unc = predicted(regions, S, R)
        tail = "%s | %s |" % (guess or "-", fmt(unc, 2))
        if hit is None or hit[1] > NEAR_DECADES:
            lines.append("| (%s) | %g | %g | - | - | - | - | - | - | %s" % (k, S, R, tail))
            continue
        j, d = hit
        lines.append("| (%s) | %g | %g | job %d (%s, %s) | **%s** | %s | %s | %s | %s | %s"
                     % (k, S, R, j["id"], fmt(j["S"]), fmt(j["R"]), label_text(j),
                        fmt(j["confidence"], 2), j["runner_up"] or "-",
                        "-" if j["n_reflections"] is None else j["n_reflections"], fmt(j["c_b"]),
                        tail))
    lines += ["", "Every run, by S then R:", "",
              "| job | S | R | state | label | confidence | runner-up | N_r | c_b/V | run time (s) |",
              "|---|---|---|---|---|---|---|---|---|---|"]
    for j in sorted(jobs, key=lambda j: (j["S"], j["R"])):
        lines.append("| %d | %s | %s | %s | %s | %s | %s | %s | %s | %s |"
                     % (j["id"], fmt(j["S"]), fmt(j["R"]), j["state"] + (
                         "" if j["status"] in (None, "ok") else " (%s)" % j["status"]),
                        label_text(j), fmt(j["confidence"], 2), j["runner_up"] or "-",
                        "-" if j["n_reflections"] is None else j["n_reflections"], fmt(j["c_b"]),
                        fmt(j["wall"], 4)))
    lines += [""] + comparison(done, phi, buckling_onset(phi))
    with open(os.path.join(a.out, "fig2.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("fig2.py: %d runs (%d done), plan %s; wrote %s" % (len(jobs), len(done), plan["state"], a.out))


if __name__ == "__main__":
    main()
