"""The paper's generality claim for random structures: label and band speed do not deviate
significantly from the regular structure of the same porosity.

The six examples (studies/lib/examples.py, phi = 0.4, pseudo-1D, to full density eps = 0.6, the
`default` preset's grid of 4.5 cells across the regular strut or that of --cells-per-strut, one
velocity field) on the regular structure and on random
structures of --seeds (structure = random: void areas and centres drawn from the seed,
random_structure in engine/include/compaction/params.hpp, docs/engine.md). It writes, per
example, the label with its confidence, N_r and both readings of c_b/V (docs/classifier.md) of
the regular run and of each seed, the realised phi of each random structure (phi_discrete of
summary.json) and each c_b/V against the regular one.

  python3 -m studies.validation.random_structures --seeds 1,2,3 --jobs 1 --bin build/bin

Runs go one example at a time, the cheapest first (e, c, then a, b, f, then d), each on the
regular structure and its seeds, cached in --work; the report is rewritten after each example,
so an interrupted study keeps whole comparisons of the examples it finished and a second call
goes on from there. Runs not made yet are listed as such.
"""
import argparse
import os
import sys

from studies.lib import runs
from studies.lib.examples import EXAMPLES, PHI
from studies.lib.cells import fmt

CELLS_PER_STRUT = runs.scene_key("cells_per_strut")["default"]  # the default preset's grid
SAME_SPEED = 0.10      # |c_b/V / regular - 1| the summary counts as the same band speed


def scene(example, seed=None, cells_per_strut=CELLS_PER_STRUT):
    S, R = EXAMPLES[example]
    flags = {"S": S, "R": R, "phi": PHI, "cells_per_strut": cells_per_strut, "eps_end": 1 - PHI,
             "snapshot_eps": ""}
    if seed is not None:
        flags.update(structure="random", seed=seed)
    return flags


def name(example, seed=None, cells_per_strut=CELLS_PER_STRUT):
    """The bundle's folder; runs on another grid than the default carry it in the name."""
    base = "%s-regular" % example if seed is None else "%s-random-seed%d" % (example, seed)
    return base if cells_per_strut == CELLS_PER_STRUT else "%s-cps%g" % (base, cells_per_strut)


def reading(bundle, classify_bin):
    """What the report shows of one run, or None when it is not made yet."""
    r = runs.reading(bundle, classify_bin)
    if r is not None:
        r.update(phi=r["summary"]["phi_discrete"],
                 origin=r["features"].get("primary_origin") or "-")
    return r


def against(v, ref):
    if v is None or ref is None or ref == 0:
        return "-"
    return "%+.0f %%" % (100 * (v / ref - 1))


def report(a, examples, seeds, classify_bin):
    def work(ex, seed=None):
        return os.path.join(a.work, name(ex, seed, a.cells_per_strut))
    cells_per_unit = a.cells_per_strut / (1 - (1 - PHI) ** 0.5)
    lines = ["# Random structures against the regular one (phi = 0.4, %g cells across the strut)"
             % a.cells_per_strut, "",
             "Made by `python3 -m studies.validation.random_structures %s`. The paper's examples %s, "
             "pseudo-1D (34 voids), to full density (eps = 0.6), %g cells across the regular "
             "strut (%.0f cells per unit cell) and one velocity field (the runner's default "
             "contact; the service's `default` and `reference` presets run two fields on the "
             "regular structure: docs/service.md, GET /presets), one thread per run. Random "
             "structures: each void's area uniform in (1 -+ 0.3) x L^2 (1 - phi) "
             "in antithetic pairs, its centre moved uniformly within the room that keeps half the "
             "thinnest strut (half the regular strut) to its cell's edges (docs/engine.md, "
             "\"Random structures\"). phi realised: the particles' solid fraction "
             "(phi_discrete of summary.json). c_b/V in both readings (fit: slope of the leading "
             "edge before its first turn; transit: mean speed of the first leg; "
             "docs/classifier.md) with their uncertainty; \"against regular\" is the transit "
             "reading over the regular structure's; primary front from: where the primary front "
             "starts (the strongest propagating front from the top plate, else the strongest; "
             "top, bottom or interior: primary_origin of the features, docs/classifier.md)."
             % (" ".join(sys.argv[1:]), ", ".join("(%s)" % e for e in examples), a.cells_per_strut,
                cells_per_unit), "",
             "| example | structure | phi realised | label (confidence) | N_r | primary front from | c_b/V fit | c_b/V transit | transit against regular | wall [s] |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    same_label = same_speed = compared = speeds = 0
    missing = []
    for ex in examples:
        ref = reading(work(ex), classify_bin)
        for seed in [None] + seeds:
            r = ref if seed is None else reading(work(ex, seed), classify_bin)
            structure = "regular" if seed is None else "random, seed %d" % seed
            if r is None:
                missing.append("(%s) %s" % (ex, structure))
                lines.append("| (%s) | %s | not run yet | | | | | | | |" % (ex, structure))
                continue
            if seed is not None and ref is not None:
                compared += 1
                same_label += r["label"] == ref["label"]
                if r["transit"] is not None and ref["transit"]:
                    speeds += 1
                    same_speed += abs(r["transit"] / ref["transit"] - 1) <= SAME_SPEED
            lines.append("| (%s) | %s | %.4f | %s (%s) | %s | %s | %s +- %s | %s +- %s | %s | %.0f |" % (
                ex, structure, r["phi"], r["label"], fmt(r["confidence"], 2), fmt(r["n_r"]), r["origin"],
                fmt(r["fit"]), fmt(r["fit_err"], 2), fmt(r["transit"]), fmt(r["transit_err"], 2),
                "-" if seed is None or ref is None else against(r["transit"], ref["transit"]),
                r["wall"]))
    lines += ["", "Random runs with the regular structure's label: %d of %d; with a transit c_b/V "
              "within %d %% of the regular one: %d of %d that have both readings."
              % (same_label, compared, round(100 * SAME_SPEED), same_speed, speeds)]
    if missing:
        lines += ["", "Not run yet: %s." % ", ".join(missing)]
    runs.write_report(a.out, lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", default="1,2,3")
    ap.add_argument("--examples", default=",".join(EXAMPLES))
    ap.add_argument("--work", default=os.path.join(runs.ROOT, "out", "random-structures"))
    ap.add_argument("--bin", default=os.path.join(runs.ROOT, "build", "bin"))
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--cells-per-strut", type=float, default=CELLS_PER_STRUT,
                    help="grid cells across the regular strut (default %g, the default preset's "
                         "grid; 9: the reference preset's)" % CELLS_PER_STRUT)
    ap.add_argument("--out", default=os.path.join(runs.ROOT, "studies", "validation", "results", "random-structures.md"))
    a = ap.parse_args()
    try:
        seeds = [int(s) for s in a.seeds.split(",") if s]
    except ValueError:
        ap.error("--seeds: a comma list of non-negative integers, got %r" % a.seeds)
    if not seeds or min(seeds) < 0:
        ap.error("--seeds: a comma list of non-negative integers, got %r" % a.seeds)
    runs.check_cells_per_strut(ap, a.cells_per_strut)
    examples = [e for e in a.examples.split(",") if e]
    for e in examples:
        if e not in EXAMPLES:
            ap.error("--examples: unknown example %r; choose from %s" % (e, ", ".join(EXAMPLES)))
    run = os.path.join(a.bin, "compaction-run")
    classify_bin = os.path.join(a.bin, "compaction-classify")
    # The cheapest example first (steps ~ 1 / S at one grid), each on the regular structure and
    # then seed by seed, so that a study stopped early has whole comparisons of the examples it
    # reached.
    for e in sorted(examples, key=lambda e: 1 / EXAMPLES[e][0]):
        group = {name(e, seed, a.cells_per_strut): scene(e, seed, a.cells_per_strut)
                 for seed in [None] + seeds}
        runs.run_all(a.work, group, jobs=a.jobs, run=run)
        report(a, examples, seeds, classify_bin)


if __name__ == "__main__":
    main()
