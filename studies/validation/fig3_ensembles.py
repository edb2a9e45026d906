"""The Fig. 3 line (S = 4e-3, R/S^2 = 0.625 to 62.5, phi = 0.4, pseudo-1D) as ensembles of
perturbed runs at one resolution: per point the label, N_r and both readings of c_b/V over the
seeds, and the paper's two checks over the points labelled (b): c_b/V rises with
q_y/(rho V^2) = R/S^2, and N_r does not fall.

usage: python3 -m studies.validation.fig3_ensembles [--cells-per-strut 8] [--seeds 1]
       [--perturbation 0.01] [--eps-end 0.6] [--points 2e-5,4e-4] [--jobs 2] [--work DIR]
       [--bin build/bin] [--table-only] [--out FILE]

Why perturbed, and why 8 cells across a strut by default: on the exact lattice the (b) point runs
a symmetric band at about 5.6 V at 4.5 cells and 2.6 V at 8 cells, while a 1 % perturbation of
the particles gives the row-by-row band of the converged reference (1.94 +- 0.04 V before any
reflection at 13.5 cells), which every perturbed seed takes from 8 cells on (studies/reference/README.md,
"The coarsest level that takes the converged mechanism of (b)"). One 8-cell run's fit scatters
about 8 % between seeds; the mean of an ensemble is the measurement.

Runs what is missing in --work (a bundle there is not made again), --jobs at a time, each on
one thread, then writes --out (default studies/validation/results/fig3-line-<N>-cells-per-strut.md) and
its plot beside it (.png), with the points' spread as error bars. --table-only runs nothing
and tabulates the points whose runs are all in --work.
"""
import argparse
import math
import os
import sys

from studies.lib import runs
from studies.lib.examples import FIG3_R, FIG3_S, PHI
from studies.lib.cells import fmt
from studies.lib.spread import line_fit, seed_list, spearman, stats


def r_list(text):
    """argparse type of --points: a comma list of R values of the Fig. 3 line."""
    try:
        values = [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError("a comma list of numbers, got %r" % text)
    unknown = [v for v in values if not any(math.isclose(v, r) for r in FIG3_R)]
    if not values or unknown:
        raise argparse.ArgumentTypeError("R values of the Fig. 3 line (%s), got %r"
                                         % (",".join("%g" % r for r in FIG3_R), text))
    return sorted({r for r in FIG3_R for v in values if math.isclose(v, r)})


def majority(labels):
    """The label more than half the runs of a point have, else "mixed"."""
    top = max(sorted(set(labels)), key=labels.count)
    return top if 2 * labels.count(top) > len(labels) else "mixed"


def reading_cell(st, single_err):
    """mean +- sd of an ensemble; a single run's value with its own uncertainty in brackets."""
    if st is None:
        return "-"
    if st["n"] == 1:
        return "%s (+- %s)" % (fmt(st["mean"]), fmt(single_err, 2))
    return "%s +- %s" % (fmt(st["mean"]), fmt(st["sd"], 2))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cells-per-strut", type=float, default=8.0,
                    help="grid cells across the thinnest strut [%(default)g: the coarsest level "
                         "that takes the converged mechanism of (b), studies/reference/README.md]")
    ap.add_argument("--seeds", type=seed_list, default=[1], help="comma list of the runs' seeds [1]")
    ap.add_argument("--perturbation", type=float, default=0.01,
                    help="random particle offset, a fraction of the particle spacing [%(default)g]")
    ap.add_argument("--eps-end", type=float, default=1 - PHI,
                    help="final strain [%(default)g: full density, which N_r needs]")
    ap.add_argument("--points", type=r_list, default=FIG3_R,
                    help="comma list of the line's R values to run [all eleven]")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--work", default=os.path.join(runs.ROOT, "out", "fig3-ensembles"))
    ap.add_argument("--bin", default=os.path.join(runs.ROOT, "build", "bin"))
    ap.add_argument("--table-only", action="store_true",
                    help="run nothing: tabulate the points whose runs are all in --work")
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    runs.check_cells_per_strut(ap, a.cells_per_strut)
    max_perturbation = runs.scene_key("perturbation")["maximum"]
    if not 0 < a.perturbation <= max_perturbation:
        ap.error("--perturbation: in (0, %g], got %g: the unperturbed lattice runs (b)'s symmetric "
                 "band (studies/reference/README.md)" % (max_perturbation, a.perturbation))
    if not 0 < a.eps_end <= 1 - PHI + 1e-12:
        ap.error("--eps-end: in (0, %g] (full density), got %g" % (1 - PHI, a.eps_end))
    if a.jobs < 1:
        ap.error("--jobs: at least 1, got %d" % a.jobs)
    if a.out is None:
        a.out = os.path.join(runs.ROOT, "studies", "validation", "results",
                             "fig3-line-%g-cells-per-strut.md" % a.cells_per_strut)
    run_bin = os.path.join(a.bin, "compaction-run")
    classify_bin = os.path.join(a.bin, "compaction-classify")

    def name(R, seed):
        return "fig3-R%g-c%g-p%g-s%d-e%g" % (R, a.cells_per_strut, a.perturbation, seed, a.eps_end)

    scenes = {name(R, s): {"S": FIG3_S, "R": R, "phi": PHI, "cells_per_strut": a.cells_per_strut,
                           "pore_contact": "auto", "perturbation": a.perturbation, "seed": s,
                           "eps_end": a.eps_end, "snapshot_eps": ""}
              for R in a.points for s in a.seeds}
    runs.check_all(scenes, run=run_bin)
    if not a.table_only:
        runs.run_all(a.work, scenes, jobs=a.jobs, run=run_bin)

    points, missing = [], []
    for R in a.points:
        readings = [runs.reading(os.path.join(a.work, name(R, s)), classify_bin) for s in a.seeds]
        if any(r is None for r in readings):
            missing.append(R)
            continue
        points.append({"R": R, "x": R / FIG3_S ** 2, "runs": readings,
                       "label": majority([r["label"] for r in readings]),
                       "fit": stats([r["fit"] for r in readings]),
                       "transit": stats([r["transit"] for r in readings]),
                       "n_r": sorted(r["n_r"] for r in readings)})
    if not points:
        sys.exit("fig3_ensembles.py: no point has all its runs in %s" % a.work)

    s0 = points[0]["runs"][0]["summary"]
    grid = s0["grid"]
    ideal = 1 / (1 - s0["phi_discrete"])
    lines = [
        "# The Fig. 3 line at %g cells across a strut, perturbed runs" % a.cells_per_strut, "",
        "Made by `python3 -m studies.validation.fig3_ensembles %s`. S = %g, phi = %g, pseudo-1D, %d cells per "
        "unit cell (%.2f across the thinnest strut), pore contact auto (two velocity fields "
        "across closing pores where 3 cells span the strut, as the presets), every particle moved at random by up to %g of the particle "
        "spacing (seeds %s), to eps = %g, one thread a run. c_b/V in both readings (fit: slope of "
        "the leading edge before its first turn; transit: mean speed of the first leg; "
        "docs/classifier.md): over two or more seeds the mean and the sample standard deviation, "
        "for one seed the run's value with the classifier's uncertainty in brackets, which "
        "understates the run-to-run scatter (8 %% between 8-cell seeds of (b), studies/reference/README.md). "
        "Non-reflecting speed of the particles' structure: 1/(1 - phi_discrete) = %.3f." % (
            " ".join(sys.argv[1:]), FIG3_S, PHI, grid["cells_per_unit"], grid["cells_per_strut"],
            a.perturbation, ",".join(map(str, a.seeds)), a.eps_end, ideal), "",
        "| q_y/(rho V^2) = R/S^2 | R | labels (confidence) | N_r | c_b/V fit | c_b/V transit | wall [s] |",
        "|---|---|---|---|---|---|---|"]
    for p in points:
        rs = p["runs"]
        lines.append("| %.3g | %g | %s | %s | %s | %s | %s |" % (
            p["x"], p["R"], ", ".join("%s (%s)" % (r["label"], fmt(r["confidence"], 2)) for r in rs),
            ", ".join(str(n) for n in p["n_r"]),
            reading_cell(p["fit"], rs[0]["fit_err"]), reading_cell(p["transit"], rs[0]["transit_err"]),
            ", ".join("%.0f" % r["wall"] for r in rs)))
    lines.append("")
    if missing:
        lines += ["Not run yet (or not all seeds): R = %s." % ", ".join("%g" % r for r in missing), ""]

    # The paper's checks, over the points most of whose runs are labelled (b), in order of R/S^2.
    b_pts = [p for p in points if p["label"] == "b" and p["fit"] is not None]
    if len(b_pts) >= 2:
        xs = [math.log(p["x"]) for p in b_pts]
        speeds = [p["fit"]["mean"] for p in b_pts]
        ys = [math.log(v) for v in speeds]
        slope = line_fit(xs, ys)[0]
        n_r = [sorted(p["n_r"])[len(p["n_r"]) // 2] for p in b_pts]  # the median (upper on a tie)
        rising = all(v > u for u, v in zip(speeds, speeds[1:]))
        not_falling = all(v >= u for u, v in zip(n_r, n_r[1:]))
        lines += [
            "Checks over the %d points labelled (b) by more than half their runs (at least five asked "
            "for), in order of R/S^2:" % len(b_pts), "",
            "- c_b/V (fit, mean over the seeds) rises at every step: %s (%s; rank correlation "
            "%s; log-log slope %.3f)." % ("yes" if rising else "**no**",
                                          ", ".join(fmt(v) for v in speeds),
                                          fmt(spearman(xs, speeds), 2), slope),
            "- N_r does not fall: %s (median over the seeds: %s)." % (
                "yes" if not_falling else "**no**", ", ".join(map(str, n_r))), ""]
    else:
        lines += ["Fewer than two points labelled (b): no check.", ""]

    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)  # the table's and plot's
    png = os.path.splitext(a.out)[0] + ".png"
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        png = None
    if png:
        fig, ax = plt.subplots(1, 2, figsize=(8, 3))
        X = [p["x"] for p in points]
        for key, mk, label in (("fit", "o", "fit"), ("transit", "^", "transit")):
            Y = [p[key]["mean"] if p[key] else float("nan") for p in points]
            E = [(p[key]["sd"] if p[key] and p[key]["sd"] is not None else
                  p["runs"][0][key + "_err"] or 0.0) for p in points]
            ln = ax[0].errorbar(X, Y, yerr=E, fmt="-", capsize=2, label=label)
            c = ln[0].get_color()
            for is_b in (True, False):  # filled: the point is (b); hollow: another label
                sel = [(x, y) for x, y, p in zip(X, Y, points) if (p["label"] == "b") == is_b]
                ax[0].plot([x for x, _ in sel], [y for _, y in sel], mk, ms=5, mec=c,
                           mfc=c if is_b else "white")
        ax[0].axhline(ideal, ls="--", c="gray", lw=0.8)
        ax[0].set_xscale("log"); ax[0].set_yscale("log")
        ax[0].set_xlabel("q_y/(rho V^2)"); ax[0].set_ylabel("c_b/V"); ax[0].legend(fontsize=7)
        for p in points:  # every run's N_r
            ax[1].plot([p["x"]] * len(p["n_r"]), p["n_r"], "s", c="C2",
                       mfc="C2" if p["label"] == "b" else "white")
        ax[1].set_xscale("log"); ax[1].set_xlabel("q_y/(rho V^2)"); ax[1].set_ylabel("N_r")
        fig.tight_layout()
        fig.savefig(png, dpi=90)
        plt.close(fig)
        lines += ["![Fig. 3 line at %g cells across a strut](%s)" % (a.cells_per_strut, os.path.basename(png)),
                  "", "Error bars: the standard deviation over the seeds (one seed: the run's own "
                  "uncertainty). Hollow markers: the point's label is not (b). Dashed: "
                  "1/(1 - phi_discrete).", ""]
    runs.write_report(a.out, lines)


if __name__ == "__main__":
    main()
