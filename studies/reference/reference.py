"""The converged-reference study: examples (a) and (b) of the paper (phi = 0.4, S = 4e-3, R = 1e-5
and 4e-4), pseudo-1D, to eps = 0.2, at rising resolution. Runs what is missing, one run at a time
on one thread, then writes studies/reference/README.md: per resolution the label, both readings of c_b/V
with their uncertainties, the plateau stress, the cost; the change between levels, and where
three levels allow it the observed order and a Richardson extrapolation.

usage: python3 -m studies.reference.reference [--cells 20,30,40,60,80] [--examples a,b]
       [--runs DIR] [--bin build/bin] [--summarise-only] [--out studies/reference/README.md]
  --runs DIR         where the bundles live (default ./out/reference): a run whose bundle is
                     there is not made again
  --examples a,b     the examples to run (both are summarised)
  --summarise-only   make no run, only summarise the bundles that exist
A level whose bundle is not in --runs keeps its row of the existing --out (a run made on an
earlier machine: studies/lib/kept_rows.py), read back into the summary. The text below the notes
marker of an existing studies/reference/README.md is kept (studies/lib/kept_notes.py).
Cost: CPU seconds grow as (cells)^3; on this machine 40 cells takes about 490 s of CPU per run,
60 cells about 3.4 times that, 80 cells about 8 times.
"""
import argparse
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import time

from studies.lib import kept_notes, kept_rows

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXAMPLES = {"a": 1e-5, "b": 4e-4}
S, PHI, EPS_END = 4e-3, 0.4, 0.2
# Quadratic B-spline MPM converges at most at second order in space (smooth solutions).
FORMAL_ORDER = 2
# The largest grid convergence index of a converged value: a reference must be more accurate
# than the 5 % within which the accuracy targets ask runs to agree with it.
REFERENCE_GCI = 0.05


def run(bin_dir, runs, ex, cells):
    out = os.path.join(runs, "%s-%d" % (ex, cells))
    if os.path.exists(os.path.join(out, "summary.json")):
        with open(os.path.join(out, "summary.json")) as f:
            status = json.load(f)["status"]
        if status != "cancelled":
            return
        # A run stopped by SIGTERM wrote a complete bundle of a shorter run: make it again.
        shutil.rmtree(out)
    t0 = time.time()
    cpu0 = os.times()
    subprocess.run([os.path.join(bin_dir, "compaction-run"), "--S", str(S), "--R", str(EXAMPLES[ex]),
                    "--phi", str(PHI), "--cells-per-unit", str(cells), "--eps-end", str(EPS_END),
                    "--snapshot-eps", "0.1,0.2", "--threads", "1", "--progress", "log",
                    "--out", out], check=True)
    cpu1 = os.times()
    with open(out + ".time", "w") as f:
        f.write("%.2f s wall, %.2f s user\n" % (time.time() - t0,
                                                cpu1.children_user - cpu0.children_user))


def cost(runs, ex, cells):
    """(wall, cpu) seconds from the .time file next to the bundle (GNU time's or ours)."""
    try:
        words = open(os.path.join(runs, "%s-%d.time" % (ex, cells))).read().replace(",", " ").split()
        return float(words[0]), float(words[3])
    except (OSError, ValueError, IndexError):
        return math.nan, math.nan


def measure(bin_dir, runs, ex, cells):
    d = os.path.join(runs, "%s-%d" % (ex, cells))
    if not os.path.exists(os.path.join(d, "summary.json")):
        return None
    with open(os.path.join(d, "summary.json")) as fh:
        if json.load(fh)["status"] == "cancelled":
            return None  # stopped before eps_end: not a level of the study
    c = json.loads(subprocess.run([os.path.join(bin_dir, "compaction-classify"), "--compact", d],
                                  capture_output=True, text=True, check=True).stdout)
    f = c.get("features", {})
    with open(os.path.join(d, "frames.csv")) as fh:
        rows = [r for r in csv.DictReader(fh)]
    top = [float(r["sigma_top_over_qy"]) for r in rows if EPS_END / 4 <= float(r["eps"]) <= EPS_END]
    s = json.load(open(os.path.join(d, "summary.json")))
    wall, cpu = cost(runs, ex, cells)
    nan = float("nan")
    g = lambda k: nan if f.get(k) is None else f[k]
    return {"cells": cells, "label": c.get("class") or "-", "confidence": c.get("confidence") or nan,
            "fit": g("band_speed_ratio"), "fit_err": g("band_speed_error"),
            "transit": g("band_speed_transit"), "transit_err": g("band_speed_transit_error"),
            "n_r": f.get("n_reflections"), "plateau": sum(top) / len(top) if top else nan,
            "particles": s.get("n_particles"), "steps": s.get("steps"), "wall": wall, "cpu": cpu,
            "strut_cells": cells * (1 - math.sqrt(1 - PHI))}


TABLE_HEADER = "| cells per unit cell | cells per strut | label (confidence) |"


LEVELS_MARK = "<!-- levels at full precision, read back on another machine: "


def earlier_levels(out):
    """{example: {cells: measure}} of an existing report, in measure()'s form: from the levels
    it keeps at full precision, else read back from its tables (4 significant digits)."""
    levels = {}
    if not os.path.exists(out):
        return levels
    text = open(out).read()
    if LEVELS_MARK in text:
        kept = json.loads(text.split(LEVELS_MARK, 1)[1].split(" -->", 1)[0])
        return {ex: {int(c): dict(m, kept=True) for c, m in by_cells.items()}
                for ex, by_cells in kept.items()}
    for ex in EXAMPLES:
        head = "## (%s): R = " % ex
        if head not in text:
            continue
        part = text[text.index(head):]
        tmp = out + ".part"
        with open(tmp, "w") as f:
            f.write(part)
        try:
            rows = kept_rows.table_rows(tmp, TABLE_HEADER)
        finally:
            os.remove(tmp)
        for r in rows:
            cells = int(r[0])
            label, confidence = kept_rows.label(r[2])
            fit, fit_err = kept_rows.plus_minus(r[3])
            transit, transit_err = kept_rows.plus_minus(r[4])
            cpu = kept_rows.number(r[9])
            levels.setdefault(ex, {})[cells] = {
                "cells": cells, "label": label, "confidence": confidence, "fit": fit,
                "fit_err": fit_err, "transit": transit, "transit_err": transit_err,
                "n_r": int(r[5]) if r[5].isdigit() else None, "plateau": kept_rows.number(r[6]),
                "particles": int(r[7]), "steps": int(r[8]), "wall": math.nan,
                "cpu": math.nan if cpu is None else cpu,
                "strut_cells": cells * (1 - math.sqrt(1 - PHI)), "kept": True}
    return levels


def levels_of(bin_dir, runs, ex, cells, earlier):
    """The measures of example ex at the levels `cells`, coarse to fine: from the bundles in
    runs, else from the earlier report's rows."""
    out = []
    for c in sorted(cells):
        m = measure(bin_dir, runs, ex, c) or earlier.get(ex, {}).get(c)
        if m:
            out.append(m)
    return out


def observed_order(c1, c2, c3, f1, f2, f3):
    """p with (f1 - f2) / (f2 - f3) = (h1^p - h2^p) / (h2^p - h3^p), h = 1 / cells; None if the
    differences do not shrink monotonically (no asymptotic range)."""
    d12, d23 = f1 - f2, f2 - f3
    if d12 == 0 or d23 == 0 or d12 * d23 < 0 or abs(d23) >= abs(d12):
        return None
    h1, h2, h3 = 1 / c1, 1 / c2, 1 / c3
    ratio = lambda p: (h1 ** p - h2 ** p) / (h2 ** p - h3 ** p) - d12 / d23
    lo, hi = 0.05, 8.0
    if ratio(lo) * ratio(hi) > 0:
        return None
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        if ratio(lo) * ratio(mid) <= 0:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


def converged(ms, key):
    """The converged value of one quantity from the levels ms (coarse to fine, at least three):
    {"value", "uncertainty" (relative), "extrapolated", "how" (a sentence)}. Where the last three
    levels are in the asymptotic range, the Richardson limit with Roache's grid convergence index;
    an observed order above the scheme's formal order is no evidence of faster convergence (the
    levels are not yet asymptotic), so the extrapolation uses at most the formal order, and the
    index (safety factor 1.25 for three levels) is the uncertainty; an index above REFERENCE_GCI
    makes the limit no reference. Otherwise the finest level, with its last change as the
    uncertainty (a lower bound: the levels have not settled)."""
    m1, m2, m3 = ms[-3:]
    p = observed_order(m1["cells"], m2["cells"], m3["cells"], m1[key], m2[key], m3[key])
    if p is None:
        return {"value": m3[key], "uncertainty": abs(m3[key] / m2[key] - 1), "extrapolated": False,
                "how": "the changes between the last three levels (%d, %d, %d cells: %s, %s, %s) "
                       "do not shrink monotonically: not in the asymptotic range, no observed "
                       "order, no extrapolation."
                       % (m1["cells"], m2["cells"], m3["cells"], fmt(m1[key], 4), fmt(m2[key], 4),
                          fmt(m3[key], 4))}
    r = m3["cells"] / m2["cells"]
    p_used = min(p, FORMAL_ORDER)
    limit = m3[key] + (m3[key] - m2[key]) / (r ** p_used - 1)
    gci = 1.25 * abs(m3[key] - m2[key]) / (r ** p_used - 1) / abs(m3[key])
    if gci > REFERENCE_GCI:
        return {"value": m3[key], "uncertainty": abs(m3[key] / m2[key] - 1), "extrapolated": False,
                "how": "observed order %.2f from %d, %d, %d cells, but a grid convergence index of "
                       "%.0f %% (Richardson limit %s at order %.1f): above the %.0f %% a reference "
                       "needs, so not converged; the finest level stands, %s."
                       % (p, m1["cells"], m2["cells"], m3["cells"], 100 * gci, fmt(limit, 4),
                          p_used, 100 * REFERENCE_GCI, fmt(m3[key], 4))}
    return {"value": limit, "uncertainty": gci, "extrapolated": True,
            "how": "observed order %.2f from %d, %d, %d cells%s; Richardson limit %s (order %.1f), "
                   "grid convergence index %.1f %% of the finest run."
                   % (p, m1["cells"], m2["cells"], m3["cells"],
                      " (above the formal order %d: not yet asymptotic)" % FORMAL_ORDER
                      if p > FORMAL_ORDER else "", fmt(limit, 4), p_used, 100 * gci)}


def reference(bin_dir, runs, ex, cells, out=None):
    """The converged reference of example ex from the study's bundles (and the rows of the
    report `out` for levels without one): {"fit", "transit", "plateau": converged() of each,
    "finest": the finest level's measure and bundle "dir"}; None with fewer than three levels."""
    ms = levels_of(bin_dir, runs, ex, cells, earlier_levels(out) if out else {})
    if len(ms) < 3:
        return None
    out = {key: converged(ms, key) for key in ("fit", "transit", "plateau")}
    out["finest"] = dict(ms[-1], dir=os.path.join(runs, "%s-%d" % (ex, ms[-1]["cells"])))
    return out


def fmt(v, digits=3):
    return "-" if v is None or (isinstance(v, float) and not math.isfinite(v)) else ("%.*g" % (digits, v))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cells", default="20,30,40,60,80")
    ap.add_argument("--runs", default=os.path.join(REPO, "out", "reference"))
    ap.add_argument("--bin", default=os.path.join(REPO, "build", "bin"))
    ap.add_argument("--examples", default=",".join(EXAMPLES))
    ap.add_argument("--summarise-only", action="store_true")
    ap.add_argument("--out", default=os.path.join(REPO, "studies", "reference", "README.md"))
    a = ap.parse_args()
    cells = sorted(int(c) for c in a.cells.split(","))
    os.makedirs(a.runs, exist_ok=True)
    examples = [e for e in a.examples.split(",") if e]
    for e in examples:
        if e not in EXAMPLES:
            ap.error("--examples: unknown example %r; choose from %s" % (e, ", ".join(EXAMPLES)))
    earlier = earlier_levels(a.out)
    if not a.summarise_only:
        for c in cells:
            for ex in examples:
                if c not in earlier.get(ex, {}):
                    run(a.bin, a.runs, ex, c)
    lines = ["# The converged reference: (a) and (b) at rising resolution", "",
             "Made by `python3 -m studies.reference.reference %s` (the runs' commands are in the script). "
             "phi = 0.4, S = 4e-3, pseudo-1D, to eps = 0.2, one thread per run; cost is CPU seconds "
             "(runs shared the machine with other work, so wall times are longer). c_b/V is read "
             "two ways (docs/classifier.md): the least-squares slope of the leading edge before "
             "its first turn (fit, with its standard error) and the first leg's mean speed "
             "(transit, with the map's resolution as uncertainty). Plateau: mean top plate stress "
             "over eps in [0.05, 0.2], / q_y. Struts are 1 - sqrt(1 - phi) = 0.225 of a unit cell "
             "thick." % " ".join(sys.argv[1:]), ""]
    kept, all_levels = 0, {}
    for ex, R in EXAMPLES.items():
        ms = levels_of(a.bin, a.runs, ex, cells, earlier)
        kept += sum(1 for m in ms if m.get("kept"))
        all_levels[ex] = {m["cells"]: {k: v for k, v in m.items() if k != "kept"} for m in ms}
        lines += ["## (%s): R = %g" % (ex, R), "",
                  "| cells per unit cell | cells per strut | label (confidence) | c_b/V fit | c_b/V transit | N_r by eps 0.2 | plateau sigma_top/q_y | particles | steps | CPU [s] |",
                  "|---|---|---|---|---|---|---|---|---|---|"]
        for m in ms:
            lines.append("| %d | %.1f | %s (%s) | %s +- %s | %s +- %s | %s | %s | %d | %d | %s |"
                         % (m["cells"], m["strut_cells"], m["label"], fmt(m["confidence"], 2),
                            fmt(m["fit"], 4), fmt(m["fit_err"], 2), fmt(m["transit"], 4),
                            fmt(m["transit_err"], 2), m["n_r"], fmt(m["plateau"], 4),
                            m["particles"], m["steps"], fmt(m["cpu"], 4)))
        lines.append("")
        if len(ms) >= 2:
            lines.append("Change from each level to the next: " + "; ".join(
                "%d -> %d cells: fit %+.1f %%, transit %+.1f %%, plateau %+.1f %%"
                % (p["cells"], q["cells"], 100 * (q["fit"] / p["fit"] - 1),
                   100 * (q["transit"] / p["transit"] - 1), 100 * (q["plateau"] / p["plateau"] - 1))
                for p, q in zip(ms, ms[1:])) + ".")
            lines.append("")
        for key in ("fit", "transit", "plateau"):
            if len(ms) >= 3:
                lines.append("- %s: %s" % (key, converged(ms, key)["how"]))
        lines.append("")
    if kept:
        lines += ["%d of the levels above are kept from the report as it was: their runs were made "
                  "on an earlier machine, whose bundles are not in --runs." % kept, ""]
    lines += [LEVELS_MARK + json.dumps(all_levels, allow_nan=True) + " -->", ""]
    kept_notes.write(a.out, "\n".join(lines))  # and the reading of the numbers, written by hand
    print("\n".join(lines))


if __name__ == "__main__":
    main()
