"""The paper's six examples at several solid fractions, at the default resolution or a finer one.

Each example's S and R (studies/validation/README.md) at phi = 0.3, 0.4, 0.5 and 0.6, pseudo-1D, to full
density (eps = 1 - phi, as the service runs them), 4.5 cells across a strut (the `default`
preset: 28, 20, 16 and 13 cells per unit cell). It writes the label with its confidence, both
readings of c_b/V (docs/classifier.md) against the non-reflecting speed 1/(1 - phi), N_r and the
wall time of each run; (a) is the non-reflecting band, whose c_b/V should be 1/(1 - phi).

  python3 -m studies.validation.solid_fractions --phi 0.3,0.4,0.5,0.6 --jobs 2 --bin build/bin

A run that is neither in --work nor made now keeps its row of the existing table (made on an
earlier machine: studies/lib/kept_rows.py), or is listed as not run yet; the runs are cached in
--work, so the study can be made in parts. --pore-contact split_fields runs the engine's
two-field contact across closing pores (docs/engine.md, "Pore contact") and writes its own
table. --cells-per-strut runs another resolution (the coarsest level at which (b) takes its
converged mechanism is 8: studies/reference/README.md) and writes its own table too.
"""
import argparse
import os
import sys

from studies.lib import kept_rows, runs
from studies.lib.examples import EXAMPLES
from studies.lib.cells import fmt

CELLS_PER_STRUT = runs.scene_key("cells_per_strut")["default"]  # the engine's, the default preset's


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--phi", default="0.3,0.4,0.5,0.6")
    ap.add_argument("--examples", default=",".join(EXAMPLES))
    ap.add_argument("--work", default=os.path.join(runs.ROOT, "out", "solid-fractions"))
    ap.add_argument("--bin", default=os.path.join(runs.ROOT, "build", "bin"))
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--table-only", action="store_true",
                    help="run nothing: tabulate the requested runs found in --work, list the rest")
    ap.add_argument("--pore-contact", default="single_field", choices=("single_field", "split_fields"))
    ap.add_argument("--cells-per-strut", type=float, default=CELLS_PER_STRUT,
                    help="cells across the thinnest strut [%(default)g, the default preset]")
    ap.add_argument("--out", default=None,
                    help="default studies/validation/results/solid-fractions.md, or solid-fractions-split-fields.md, "
                         "with -<N>-cells-per-strut before .md at another --cells-per-strut")
    a = ap.parse_args()
    runs.check_cells_per_strut(ap, a.cells_per_strut)
    split = a.pore_contact == "split_fields"
    default_cells = a.cells_per_strut == CELLS_PER_STRUT
    suffix = ("-split_fields" if split else "") + ("" if default_cells else "-cps%g" % a.cells_per_strut)
    if a.out is None:
        a.out = os.path.join(runs.ROOT, "studies", "validation", "results", "solid-fractions%s%s.md" % (
            "-split-fields" if split else "",
            "" if default_cells else "-%g-cells-per-strut" % a.cells_per_strut))

    def name(e, phi):  # a run's folder in --work
        return "%s-phi%g%s" % (e, phi, suffix)
    phis = [float(p) for p in a.phi.split(",")]
    examples = [e for e in a.examples.split(",") if e]
    for e in examples:
        if e not in EXAMPLES:
            ap.error("--examples: unknown example %r; choose from %s" % (e, ", ".join(EXAMPLES)))
    scenes = {name(e, phi): dict(
                  {"S": EXAMPLES[e][0], "R": EXAMPLES[e][1], "phi": phi,
                   "cells_per_strut": a.cells_per_strut, "eps_end": 1 - phi, "snapshot_eps": ""},
                  **({"pore_contact": "split_fields"} if split else {}))
              for phi in phis for e in examples}
    if a.table_only:  # the runs made so far, in --work; the others listed as not run
        dirs = {n: os.path.join(a.work, n) for n in scenes if runs.finished(os.path.join(a.work, n))}
    else:
        dirs = runs.run_all(a.work, scenes, jobs=a.jobs, run=os.path.join(a.bin, "compaction-run"))
    classify_bin = os.path.join(a.bin, "compaction-classify")

    header = "| example | phi | cells per unit cell (per strut) | label (confidence) |"
    earlier = {(r[0], r[1]): "| " + " | ".join(r) + " |" for r in kept_rows.table_rows(a.out, header)}
    kept = 0
    lines = ["# The six examples at phi = 0.3 to 0.6 (%s%s)"
             % ("default resolution" if default_cells else "%g cells across a strut" % a.cells_per_strut,
                ", two velocity fields across closing pores" if split else ""), "",
             "Made by `python3 -m studies.validation.solid_fractions %s`. Pseudo-1D, to full density "
             "(eps = 1 - phi), %g cells across a strut%s, one thread per run. "
             "c_b/V in both readings (fit: slope of the leading edge before its first turn; transit: "
             "mean speed of the first leg; docs/classifier.md), with their uncertainty, against "
             "the non-reflecting speed 1/(1 - phi_discrete) of the particles' structure."
             % (" ".join(sys.argv[1:]), a.cells_per_strut, " (the `default` preset)" if default_cells else "")
             + (" The runs were made by earlier calls with the same flags but --table-only, each for "
                "the examples and solid fractions it names." if a.table_only else ""), "",
             "| example | phi | cells per unit cell (per strut) | label (confidence) | c_b/V fit | c_b/V transit | 1/(1 - phi) | transit against it | N_r | wall [s] |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for e in examples:
        for phi in phis:
            if name(e, phi) not in dirs:
                row = earlier.get(("(%s)" % e, "%g" % phi))
                if row:
                    lines.append(row)
                    kept += 1
                continue
            d = dirs[name(e, phi)]
            s = runs.summary(d)
            c = runs.classify(d, classify_bin)
            f = c.get("features") or {}
            ideal = 1 / (1 - s["phi_discrete"])
            transit = f.get("band_speed_transit")
            lines.append("| (%s) | %g | %d (%.2f) | %s (%s) | %s +- %s | %s +- %s | %.3f | %s | %s | %.0f |" % (
                e, phi, s["grid"]["cells_per_unit"], s["grid"]["cells_per_strut"],
                c.get("class") or "none", fmt(c.get("confidence"), 2),
                fmt(f.get("band_speed_ratio")), fmt(f.get("band_speed_error"), 2),
                fmt(transit), fmt(f.get("band_speed_transit_error"), 2), ideal,
                "-" if transit is None else "%+.1f %%" % (100 * (transit / ideal - 1)),
                c.get("n_reflections"), s["wall_seconds"]))
    missing = ["(%s) at phi = %g" % (e, phi) for e in examples for phi in phis
               if name(e, phi) not in dirs and ("(%s)" % e, "%g" % phi) not in earlier]
    if kept:
        lines += ["", "%d of these rows were kept from the table as it was: their runs were made on "
                  "an earlier machine, whose bundles are not in --work." % kept]
    if missing:
        lines += ["", "Not run yet: " + ", ".join(missing) + "."]
    runs.write_report(a.out, lines)


if __name__ == "__main__":
    main()
