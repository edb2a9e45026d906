"""The paper's dimension claim, measured: a 3D column gives the band speed of the pseudo-1D 2D
one (Blatny et al. 2022, supplemental material).

For the examples (a) and (b) (phi = 0.4, to eps = 0.2, 34 unit cells tall, one thread, one
velocity field: the 3D engine has no second one) it runs the 3D column (geometry =
pseudo1d_3d: one unit cell across in x and z, cubic holes) and the pseudo-1D 2D column at the
same cells per unit cell, for each of --cells-per-unit, and writes a table of label, N_r, both
readings of c_b/V (docs/classifier.md) with their uncertainty, the plateau stress, cells across
the strut and the cost (wall time, ns per particle-step). "3D against 2D" is the transit reading
of the 3D run over the 2D run's at the same grid.

The 3D column resolves its strut more coarsely at the same grid: L (1 - (1 - phi)^(1/3)) is
0.157 L at phi = 0.4 against 0.225 L for the square holes of 2D, so "cells per unit cell" is
the grid and "cells across the strut" says what it resolves; both are in the table.

usage: python3 -m studies.validation.column_3d [--cells-per-unit 8] [--examples a,b]
       [--work DIR] [--bin DIR] [--jobs N] [--out FILE]

Runs are cached in --work (a second call goes on from the runs it has); the report is
rewritten after each pair, and runs not made yet are listed as such.
"""
import argparse
import os
import sys

from studies.lib import runs
from studies.lib.examples import EXAMPLES, PHI
from studies.lib.cells import fmt

BASE = {"phi": PHI, "eps_end": 0.2, "snapshot_eps": "", "movie_d_eps": 0,
        "pore_contact": "single_field"}
STRUT_2D = 1 - (1 - PHI) ** 0.5        # strut / L between square holes
STRUT_3D = 1 - (1 - PHI) ** (1 / 3)    # strut / L between cubic holes
# Each grid of --cells-per-unit runs three ways: label -> (geometry, the grid it runs at). The
# third is the 2D column at the grid that resolves its strut as the 3D grid resolves the 3D
# strut (the nearest whole number of cells per unit cell).
GEOMETRIES = {
    "2D pseudo-1D": ("pseudo1d", lambda cells: cells),
    "2D pseudo-1D, the 3D strut's resolution": (
        "pseudo1d", lambda cells: max(2, round(cells * STRUT_3D / STRUT_2D))),
    "3D": ("pseudo1d_3d", lambda cells: cells),
}
SAME_SPEED = 0.05  # |c_b/V 3D / 2D - 1| the summary counts as the same band speed


def scene(example, geometry, cells):
    S, R = EXAMPLES[example]
    return {**BASE, "S": S, "R": R, "geometry": geometry, "cells_per_unit": cells}


def name(example, geometry, cells):
    return "%s-%s-%d" % (example, geometry, cells)


def plateau(bundle):
    """Median top-plate stress over q_y in the second half of the run (the band's plateau)."""
    f = runs.frames(bundle)
    eps, top = f.get("eps", []), f.get("sigma_top_over_qy", [])
    half = sorted(t for e, t in zip(eps, top) if e >= 0.5 * eps[-1]) if eps else []
    return half[len(half) // 2] if half else None


def reading(bundle, classify_bin):
    """What the report shows of one run, or None when it is not made yet."""
    r = runs.reading(bundle, classify_bin)
    if r is not None:
        s = r["summary"]
        r.update(plateau=plateau(bundle), strut=s.get("grid", {}).get("cells_per_strut"),
                 ns=s["ns_per_particle_step"], particles=s["n_particles"], steps=s["steps"],
                 revision=s.get("source_revision"))
    return r


def runs_of(examples, cells_list):
    """{(example, cells, label): (bundle name, flags)} of every run the study makes."""
    return {(ex, cells, g): (name(ex, geo, grid(cells)), scene(ex, geo, grid(cells)))
            for ex in examples for cells in cells_list for g, (geo, grid) in GEOMETRIES.items()}


def report(a, examples, cells_list, classify_bin):
    got = {key: reading(os.path.join(a.work, bundle), classify_bin)
           for key, (bundle, _) in runs_of(examples, cells_list).items()}
    revision = ", ".join(sorted({r["revision"] or "unknown" for r in got.values() if r})) or "-"
    lines = ["# The 3D column against the pseudo-1D 2D one (phi = 0.4)", "",
             "Made by `python3 -m studies.validation.column_3d %s` (engine %s). Examples (a) and (b) of the "
             "paper, 34 unit cells tall, to eps = 0.2, one velocity field, one thread per run. "
             "c_b/V in both readings (fit: slope of the leading edge before its first turn; "
             "transit: mean speed of the first leg; docs/classifier.md) with their uncertainty; "
             "plateau: the median top-plate stress over q_y in the second half of the run; "
             "\"3D against 2D\" is the 3D transit reading over the 2D one at the same grid; the "
             "third row of each pair runs 2D at the grid that resolves the square holes' strut "
             "as the 3D grid resolves the cubic holes' (L (1 - sqrt(1 - phi)) against "
             "L (1 - (1 - phi)^(1/3))). "
             "Wall times are of runs that shared the 2 cores with other work."
             % (" ".join(sys.argv[1:]), revision), "",
             "| example | grid [cells / unit] | geometry | cells across the strut | label (confidence) "
             "| N_r | c_b/V fit | c_b/V transit | 3D against 2D | plateau / q_y | particles | steps "
             "| ns / particle-step | wall [s] |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    missing, compared, same = [], 0, 0
    for ex in examples:
        for cells in cells_list:
            ref = got[(ex, cells, "2D pseudo-1D")]  # the same grid
            for g, (_, grid) in GEOMETRIES.items():
                r = got[(ex, cells, g)]
                if r is None:
                    missing.append("(%s) %s at %d cells" % (ex, g, grid(cells)))
                    lines.append("| (%s) | %d | %s | not run yet | | | | | | | | | | |"
                                 % (ex, grid(cells), g))
                    continue
                vs = "-"
                if g == "3D" and ref is not None and r["transit"] and ref["transit"]:
                    ratio = r["transit"] / ref["transit"] - 1
                    vs = "%+.1f %%" % (100 * ratio)
                    compared += 1
                    same += abs(ratio) <= SAME_SPEED and r["label"] == ref["label"]
                lines.append("| (%s) | %d | %s | %s | %s (%s) | %s | %s +- %s | %s +- %s | %s | %s "
                             "| %d | %d | %.0f | %.0f |" % (
                                 ex, grid(cells), g, fmt(r["strut"]), r["label"], fmt(r["confidence"], 2),
                                 fmt(r["n_r"]), fmt(r["fit"]), fmt(r["fit_err"], 2),
                                 fmt(r["transit"]), fmt(r["transit_err"], 2), vs,
                                 fmt(r["plateau"]), r["particles"], r["steps"], r["ns"], r["wall"]))
    lines += ["", "3D runs with the 2D run's label and a transit c_b/V within %d %% of it: %d of %d."
              % (round(100 * SAME_SPEED), same, compared)]
    if missing:
        lines += ["", "Not run yet: %s." % ", ".join(missing)]
    runs.write_report(a.out, lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cells-per-unit", default="8", help="comma list of grids (default 8)")
    ap.add_argument("--examples", default="a,b")
    ap.add_argument("--work", default=os.path.join(runs.ROOT, "out", "column-3d"))
    ap.add_argument("--bin", default=os.path.join(runs.ROOT, "build", "bin"))
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--out", default=os.path.join(runs.ROOT, "studies", "validation", "results", "column-3d.md"))
    a = ap.parse_args()
    try:
        cells_list = [int(c) for c in a.cells_per_unit.split(",") if c]
    except ValueError:
        ap.error("--cells-per-unit: a comma list of whole numbers, got %r" % a.cells_per_unit)
    if not cells_list or min(cells_list) < 2:
        ap.error("--cells-per-unit: grids of at least 2 cells per unit cell, got %r" % a.cells_per_unit)
    examples = [e for e in a.examples.split(",") if e]
    for e in examples:
        if e not in EXAMPLES:
            ap.error("--examples: unknown example %r; choose from %s" % (e, ", ".join(EXAMPLES)))
    if a.jobs < 1:
        ap.error("--jobs must be at least 1")
    run = os.path.join(a.bin, "compaction-run")
    classify_bin = os.path.join(a.bin, "compaction-classify")
    for ex in examples:
        for cells in cells_list:
            group = dict(v for k, v in runs_of([ex], [cells]).items())
            runs.run_all(a.work, group, jobs=a.jobs, run=run)
            report(a, examples, cells_list, classify_bin)


if __name__ == "__main__":
    main()
