"""Run-to-run scatter of an example's band speed at one resolution: the example unperturbed and
with its particles moved at random (--perturbation, a fraction of their spacing) for several
seeds, pseudo-1D, phi = 0.4, to --eps-end. A level of the converged reference (studies/reference/README.md)
is converged when its mean moves between levels by less than this scatter; one run per level
cannot tell (b)'s mechanism change from round-off.

usage: python3 -m studies.reference.scatter --example b [--cells-per-strut N]
       [--pore-contact auto] [--nu 0.3] [--perturbation 0.01] [--seeds 1,2,3,4]
       [--no-unperturbed] [--eps-end 0.2] [--jobs 2] [--work DIR] [--bin build/bin] [--out FILE]

Runs what is missing in --work (a bundle there is not made again), two at a time with --jobs 2,
each on one thread, then writes --out (default studies/reference/results/scatter-EXAMPLE-CELLS-epsEPS.md,
with -nuNU when --nu is given):
per run the label, N_r and both readings of c_b/V with their uncertainties (docs/classifier.md);
over the perturbed runs the mean, the sample standard deviation and the range of each reading,
and where the unperturbed run lies against them.
"""
import argparse
import os
import sys

from studies.lib import runs
from studies.lib.examples import EXAMPLES
from studies.lib.cells import fmt
from studies.lib.spread import seed_list, stats

PHI = 0.4  # the paper's examples


def positive(kind):
    def parse(text):
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError("%r is not a number" % text)
        if not value > 0:
            raise argparse.ArgumentTypeError("must be above 0, got %s" % text)
        return value
    return parse


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--example", required=True, choices=sorted(EXAMPLES))
    ap.add_argument("--cells-per-strut", type=float, default=runs.scene_key("cells_per_strut")["default"],
                    help="grid cells across the thinnest strut [%(default)g, the default preset]")
    ap.add_argument("--pore-contact", default="auto", choices=("auto", "single_field", "split_fields"),
                    help="contact across closing pores (the presets: auto)")
    ap.add_argument("--nu", type=float, default=None,
                    help="Poisson's ratio (the runner's range and default; at fixed S and R the "
                         "paper's patterns do not depend on it: studies/validation/README.md, Invariance)")
    ap.add_argument("--perturbation", type=positive(float), default=0.01,
                    help="random particle offset, a fraction of the particle spacing (the runner's range)")
    ap.add_argument("--seeds", type=seed_list, default="1,2,3,4", help="comma list of the perturbed runs' seeds")
    ap.add_argument("--unperturbed", action=argparse.BooleanOptionalAction, default=True,
                    help="also run the example unperturbed, on its exact lattice (the ensemble's "
                         "statistics are of the perturbed runs alone; --no-unperturbed saves its cost)")
    ap.add_argument("--eps-end", type=positive(float), default=0.2)
    ap.add_argument("--jobs", type=positive(int), default=1)
    ap.add_argument("--work", default=os.path.join(runs.ROOT, "out", "scatter"))
    ap.add_argument("--bin", default=os.path.join(runs.ROOT, "build", "bin"))
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    runs.check_cells_per_strut(ap, a.cells_per_strut)
    if a.eps_end > 1 - PHI + 1e-12:
        ap.error("--eps-end: at most full density (1 - phi = %g), got %g" % (1 - PHI, a.eps_end))
    seeds = a.seeds
    if a.out is None:
        a.out = os.path.join(runs.ROOT, "studies", "reference", "results",
                             "scatter-%s-%g-eps%g%s.md" % (a.example, a.cells_per_strut, a.eps_end,
                                                           "" if a.nu is None else "-nu%g" % a.nu))

    S, R = EXAMPLES[a.example]
    base = {"S": S, "R": R, "phi": PHI, "cells_per_strut": a.cells_per_strut,
            "pore_contact": a.pore_contact, "eps_end": a.eps_end, "snapshot_eps": ""}
    if a.nu is not None:
        base["nu"] = a.nu
    # A run's folder names everything that sets its scene, so --work can hold several studies.
    prefix = "%s-c%g-%s-e%g%s" % (a.example, a.cells_per_strut, a.pore_contact, a.eps_end,
                                  "" if a.nu is None else "-nu%g" % a.nu)
    runs_wanted = ([(0.0, 1)] if a.unperturbed else []) + [(a.perturbation, s) for s in seeds]
    scenes = {"%s-p%g-s%d" % (prefix, p, s): dict(base, perturbation=p, seed=s)
              for p, s in runs_wanted}
    runs.check_all(scenes, run=os.path.join(a.bin, "compaction-run"))
    dirs = runs.run_all(a.work, scenes, jobs=a.jobs, run=os.path.join(a.bin, "compaction-run"))
    classify_bin = os.path.join(a.bin, "compaction-classify")

    rows, perturbed, unperturbed = [], [], None
    for (p, s), name in zip(runs_wanted, scenes):
        r = runs.reading(dirs[name], classify_bin)
        if r is None:
            sys.exit("scatter.py: %s did not finish (no summary.json in %s)" % (name, dirs[name]))
        grid, nu = r["summary"]["grid"], r["summary"]["params"]["nu"]
        rows.append("| %g | %s | %s (%s) | %s | %s +- %s | %s +- %s | %s | %.0f |" % (
            p, s, r["label"], fmt(r["confidence"], 2), r["n_r"],
            fmt(r["fit"]), fmt(r["fit_err"], 2), fmt(r["transit"]), fmt(r["transit_err"], 2),
            r["status"], r["wall"]))
        if p > 0:
            perturbed.append(r)
        else:
            unperturbed = r

    lines = ["# Run-to-run scatter of (%s) at %g cells across a strut (%s)" % (
                 a.example, a.cells_per_strut, a.pore_contact), "",
             "Made by `python3 -m studies.reference.scatter %s`. S = %g, R = %g, phi = %g, nu = %g, pseudo-1D, "
             "%d cells per unit cell (%.2f across the thinnest strut), to eps = %g, one thread "
             "a run. The perturbed runs move every particle at random by up to %g of the "
             "particle spacing (`--perturbation`, seeded). c_b/V in both readings (fit: slope of "
             "the leading edge before its first turn; transit: mean speed of the first leg; "
             "docs/classifier.md), with the classifier's uncertainty of each run." % (
                 " ".join(sys.argv[1:]), S, R, PHI, nu, grid["cells_per_unit"],
                 grid["cells_per_strut"], a.eps_end, a.perturbation), "",
             "| perturbation | seed | label (confidence) | N_r | c_b/V fit | c_b/V transit | status | wall [s] |",
             "|---|---|---|---|---|---|---|---|"] + rows + [""]
    labels = sorted({r["label"] for r in perturbed})
    lines.append("Over the %d perturbed runs: label%s %s." % (
        len(perturbed), "" if len(labels) == 1 else "s", ", ".join(labels)))
    lines.append("")
    lines.append("| reading | mean | standard deviation | range | sd / mean | unperturbed | unperturbed against the mean |")
    lines.append("|---|---|---|---|---|---|---|")
    for key, title in (("fit", "c_b/V fit"), ("transit", "c_b/V transit")):
        st = stats([r[key] for r in perturbed])
        u = unperturbed[key] if unperturbed else None
        if st is None:
            lines.append("| %s | - | - | - | - | %s | - |" % (title, fmt(u)))
            continue
        lines.append("| %s | %s | %s | %s to %s | %s | %s | %s |" % (
            title, fmt(st["mean"]), fmt(st["sd"], 2), fmt(st["min"]), fmt(st["max"]),
            "-" if st["sd"] is None else "%.1f %%" % (100 * st["sd"] / st["mean"]), fmt(u),
            "-" if u is None else "%+.1f %%" % (100 * (u / st["mean"] - 1))))
    runs.write_report(a.out, lines)


if __name__ == "__main__":
    main()
