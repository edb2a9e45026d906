"""The trusted map's report (issue 47, item 4): what the sweep's export says of its labels' trust.

Reads the sweep's JSON export that the parts leave (results/trusted.map.json, made by part.py:
the points and the runs, as GET /api/v1/sweeps/{id}/export?format=json answers) and writes
results/report.md: per level of numerics the points, runs and robust points; the share of
robust labels per class at each point's finest level; every point whose label changed between
levels; the (a)/(b) boundary in R/S^2 at each level with its bracket; c_b/V of (b) as mean +- sd
per point at the finer level; the CPU-hours spent against the brute force (every lattice point
at the finest level with all replicates); and how often the coarser level's label agrees with
the finer one's. Text written below the report's marker is kept when it is made again.

    python3 -m studies.trusted_map.report [--map FILE] [--out FILE]
"""
import argparse
import json
import math
import os
import statistics

from studies.lib import kept_notes
from studies.lib.cells import fmt

HERE = os.path.dirname(os.path.abspath(__file__))
MAP = os.path.join(HERE, "results", "trusted.map.json")
REPORT = os.path.join(HERE, "results", "report.md")
CLASSES = "abcdef"


def key(point):
    """A lattice node of the (S, R) plane, the same for a point at every level."""
    return ("%.6g" % point["S"], "%.6g" % point["R"])


def x_of(point):
    """R/S^2, the paper's axis along which (a) turns into (b)."""
    return point["R"] / point["S"] ** 2


def labelled(points):
    """The points with a majority label (at least one finished, classified run)."""
    return [p for p in points if p.get("label")]


def grids_of(points, request):
    """The cells per unit of each level the request names, coarsest first; None for a level
    without a point yet (the points' grids fill the first levels, as the planner runs them)."""
    grids = sorted({p["cells_per_unit"] for p in points})
    n = max(len(request["adaptive"].get("levels") or [None]), len(grids))
    return grids + [None] * (n - len(grids))


def by_level(points, grids):
    """{level: {node: point}} for every level of `grids` (grids_of)."""
    out = {i: {} for i in range(len(grids))}
    for p in points:
        out[grids.index(p["cells_per_unit"])][key(p)] = p
    return out


def finest(levels):
    """{node: (level, point)}: each node's labelled point at its finest level."""
    out = {}
    for lvl in sorted(levels):
        for node, p in levels[lvl].items():
            if p.get("label"):
                out[node] = (lvl, p)
    return out


def robust_per_class(points):
    """{class: (points, robust points)} over `points`, by majority label."""
    out = {}
    for p in labelled(points):
        n, r = out.get(p["label"], (0, 0))
        out[p["label"]] = (n + 1, r + (1 if p.get("robust") else 0))
    return out


def changed(levels):
    """[(node, [label or None per level])] for the nodes whose majority label differs between two
    levels that both labelled them."""
    out = []
    nodes = sorted({n for grid in levels.values() for n in grid}, key=lambda n: (float(n[0]),
                                                                                 float(n[1])))
    for node in nodes:
        labels = [(levels[lvl].get(node) or {}).get("label") for lvl in sorted(levels)]
        if len({lab for lab in labels if lab}) > 1:
            out.append((node, labels))
    return out


def boundary(points, below="a", above="b"):
    """Where `below` turns into `above` along R/S^2: {"below": largest R/S^2 labelled `below`,
    "above": smallest labelled `above`, "middle": their geometric mean and "half_decades": half
    the bracket in decades when the two do not overlap, and "overlap": the points inside the
    other label's range when they do}. None when either label is missing."""
    lo = [x_of(p) for p in labelled(points) if p["label"] == below]
    hi = [x_of(p) for p in labelled(points) if p["label"] == above]
    if not lo or not hi:
        return None
    out = {"below": max(lo), "above": min(hi), "middle": None, "half_decades": None,
           "overlap": []}
    if out["below"] < out["above"]:
        out["middle"] = math.sqrt(out["below"] * out["above"])
        out["half_decades"] = 0.5 * math.log10(out["above"] / out["below"])
    else:
        out["overlap"] = sorted(
            (p for p in labelled(points)
             if (p["label"] == below and x_of(p) >= out["above"])
             or (p["label"] == above and x_of(p) <= out["below"])), key=x_of)
    return out


def agreement(levels, coarse, fine):
    """(agreeing, both): nodes labelled at both levels and those of them with one majority label."""
    both = [n for n, p in levels.get(coarse, {}).items()
            if p.get("label") and (levels.get(fine, {}).get(n) or {}).get("label")]
    same = [n for n in both if levels[coarse][n]["label"] == levels[fine][n]["label"]]
    return len(same), len(both)


def lattice_points(request):
    """The nodes of the adaptive sweep's finest lattice over its box."""
    ad = request["adaptive"]
    step = ad["resolution_decades"]
    per_axis = [round(math.log10(ad[a]["max"] / ad[a]["min"]) / step) + 1 for a in ("S", "R")]
    return per_axis[0] * per_axis[1]


def run_hours(jobs, grids):
    """{level: {"runs": finished runs, "hours": their run time (one core each),
    "median_s": a run's median wall seconds}} of the succeeded jobs."""
    out = {}
    for j in jobs:
        wall = (j.get("result") or {}).get("wall_seconds")
        if j.get("state") != "succeeded" or wall is None:
            continue
        out.setdefault(grids.index(j["cells_per_unit"]), []).append(wall)
    return {lvl: {"runs": len(w), "hours": sum(w) / 3600, "median_s": statistics.median(w)}
            for lvl, w in out.items()}


def node_text(node):
    s, r = float(node[0]), float(node[1])
    return "S %s, R %s (R/S^2 %s)" % (fmt(s), fmt(r), fmt(r / s ** 2))


def reading(r):
    """A mean +- sd (n) reading of a point."""
    if not r or r.get("mean") is None:
        return "-"
    sd = "" if r.get("sd") is None else " +- %s" % fmt(r["sd"], 2)
    return "%s%s (n %d)" % (fmt(r["mean"]), sd, r["n"])


def level_lines(levels, grids, hours):
    lines = ["| level | cells per unit | points labelled | robust | runs done | run time (CPU-h) "
             "| median run (s) |", "|---|---|---|---|---|---|---|"]
    for lvl in sorted(levels):
        pts = labelled(levels[lvl].values())
        h = hours.get(lvl, {"runs": 0, "hours": 0.0, "median_s": None})
        lines.append("| %d | %s | %d | %d | %d | %.2f | %s |" % (
            lvl, fmt(grids[lvl]), len(pts), sum(1 for p in pts if p.get("robust")), h["runs"],
            h["hours"], fmt(h["median_s"])))
    return lines


def class_lines(best):
    counts = robust_per_class([p for _, p in best.values()])
    lines = ["| class | points | robust | share robust |", "|---|---|---|---|"]
    for c in CLASSES:
        if c in counts:
            n, r = counts[c]
            lines.append("| (%s) | %d | %d | %.0f %% |" % (c, n, r, 100.0 * r / n))
    return lines


def changed_lines(levels):
    moved = changed(levels)
    if not moved:
        return ["No point labelled at two levels changed its label."]
    lines = ["| point | " + " | ".join("level %d" % lvl for lvl in sorted(levels)) + " |",
             "|---|" + "---|" * len(levels)]
    for node, labels in moved:
        cells = []
        for lvl, lab in zip(sorted(levels), labels):
            p = levels[lvl].get(node)
            cells.append("(%s) %.2f" % (lab, p["share"]) if lab else "-")
        lines.append("| %s | %s |" % (node_text(node), " | ".join(cells)))
    return lines


def boundary_lines(levels, grids):
    lines = ["| level | cells per unit | largest R/S^2 of (a) | smallest of (b) | boundary | "
             "+- decades |", "|---|---|---|---|---|---|"]
    overlaps = []
    for lvl in sorted(levels):
        b = boundary(list(levels[lvl].values()))
        if b is None:
            lines.append("| %d | %s | - | - | not both labels yet | - |" % (lvl, fmt(grids[lvl])))
            continue
        lines.append("| %d | %s | %s | %s | %s | %s |" % (
            lvl, fmt(grids[lvl]), fmt(b["below"]), fmt(b["above"]),
            fmt(b["middle"]) if b["middle"] else "overlap",
            fmt(b["half_decades"], 2) if b["half_decades"] is not None else "-"))
        overlaps += ["- level %d: (%s) at %s" % (lvl, p["label"], node_text(key(p)))
                     for p in b["overlap"]]
    if overlaps:
        lines += ["", "Points inside the other label's range of R/S^2 (the boundary is not a "
                  "line of constant R/S^2 there, or a label is not yet robust):", ""] + overlaps
    return lines


def band_lines(levels):
    """c_b/V of the (b) points at the finest level that has any (the finer level once it ran)."""
    for top in sorted(levels, reverse=True):
        bs = sorted((p for p in labelled(levels[top].values()) if p["label"] == "b"), key=x_of)
        if bs:
            break
    else:
        return ["No point is labelled (b) yet."]
    lines = ["Level %d%s, the points labelled (b): c_b/V by the classifier's fit over the point's "
             "majority runs." % (top, "" if top == max(levels) else
                                 " (the finest level with a (b) so far)"), "",
             "| point | share | c_b/V mean +- sd (n) | early stage |", "|---|---|---|---|"]
    for p in bs:
        lines.append("| %s | %.2f | %s | %s |" % (node_text(key(p)), p["share"],
                                                  reading(p.get("band_speed_ratio")),
                                                  reading(p.get("band_speed_early"))))
    return lines


def cost_lines(request, hours, levels):
    n = request.get("replicates", {}).get("n", 1)
    nodes = lattice_points(request)
    top = max(levels) if levels else 0
    spent = sum(h["hours"] for h in hours.values())
    lines = ["Run time spent: %.2f CPU-hours (the runs' wall time, one core each)." % spent]
    if top in hours:
        brute = nodes * n * hours[top]["median_s"] / 3600
        lines.append("Brute force, every one of the %d lattice points at level %d with %d "
                     "replicates at its median run time (%s s): %.1f CPU-hours; spent so far "
                     "%.0f %% of it." % (nodes, top, n, fmt(hours[top]["median_s"]), brute,
                                         100.0 * spent / brute))
    else:
        lines.append("No run of level %d has finished: the brute force's cost is not measured "
                     "yet (%d lattice points x %d replicates)." % (top, nodes, n))
    for coarse in sorted(levels)[:-1]:
        same, both = agreement(levels, coarse, coarse + 1)
        lines.append("Level %d agrees with level %d on %d of the %d points labelled at both." % (
            coarse, coarse + 1, same, both))
    return lines


def report(export):
    points, jobs, request = export["points"], export["jobs"], export["sweep"]["request"]
    grids = grids_of(points, request)
    levels = by_level(points, grids)
    hours = run_hours(jobs, grids)
    best = finest(levels)
    return (["# The trusted map: report", "",
             "Made by `python3 -m studies.trusted_map.report` from [trusted.map.json]"
             "(trusted.map.json) (the parts are in [parts.md](parts.md)). Request: `%s`." %
             json.dumps(request, sort_keys=True), "",
             "## Levels", ""] + level_lines(levels, grids, hours) +
            ["", "## Robust labels per class, at each point's finest level", ""] +
            class_lines(best) +
            ["", "## Points whose label changed between levels", ""] + changed_lines(levels) +
            ["", "## The (a)/(b) boundary in R/S^2", ""] + boundary_lines(levels, grids) +
            ["", "## c_b/V of (b)", ""] + band_lines(levels) +
            ["", "## Cost and agreement", ""] + cost_lines(request, hours, levels))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--map", default=MAP, help="the sweep's JSON export (format=json)")
    ap.add_argument("--out", default=REPORT)
    a = ap.parse_args()
    with open(a.map) as f:
        text = "\n".join(report(json.load(f)))
    kept_notes.write(a.out, text)
    print(text)


if __name__ == "__main__":
    main()
