"""The paper's invariance claim, measured: at fixed S and R the pattern does not depend on q_y,
rho or nu.

For the examples (a) and (b) (phi = 0.4, pseudo-1D, to eps = 0.2, at each resolution of
--cells-per-strut: 4.5 is the default preset, 9 the reference preset) it runs the reference material (q_y = 250 N/m, rho = 1000 kg/m^2,
nu = 0.3), the same S and R with q_y and rho scaled (q_y x 40, rho x 0.1: E, V and time change,
the dimensionless problem does not), and nu = 0.2 and 0.35. It writes a table of label, both
readings of c_b/V (docs/classifier.md) and N_r, and checks each against the reference material:
same label and N_r, c_b/V within 5 %; scaled q_y and rho agree to round-off (1e-9).

The pore contact is the presets' (--pore-contact auto: two velocity fields across closing pores
where the grid resolves them); --pore-contact single_field measures the one-field engine.

With --seeds, each of the reference material, nu = 0.2 and nu = 0.35 is an ensemble: the run
above plus one run per seed with the particles moved at random by --perturbation of their
spacing (as studies/reference/scatter.py does). Near a change of mechanism one run of (b) is one
draw from a wide spread (studies/reference/README.md), so a single pair of runs cannot say whether nu
moves the pattern; the ensembles compare the most common label, the N_r seen and the means of
both readings of c_b/V (within 5 %, and against the standard error of the difference of the
means). The scaled material is left out there: it is the same dimensionless problem, equal to
round-off run by run (the table without --seeds, and classify_invariance_gtest).

usage: python3 -m studies.validation.invariance [--cells-per-strut 4.5,9] [--examples a,b]
       [--work DIR] [--bin DIR] [--jobs N] [--pore-contact MODE]
       [--seeds 1,2,3,4 [--perturbation 0.01]] [--out FILE]
Exit code 1 when a variant differs at the finest resolution asked for.
"""
import argparse
import collections
import math
import os
import sys

from studies.lib import examples, runs
from studies.lib.cells import fmt
from studies.lib.spread import seed_list, stats

EXAMPLES = {k: dict(zip(("S", "R"), examples.EXAMPLES[k])) for k in "ab"}
BASE = {"phi": 0.4, "eps_end": 0.2, "snapshot_eps": ""}
VARIANTS = {  # name: (changed material constants, what the check allows)
    "reference material": ({}, None),
    "q_y x 40, rho x 0.1": ({"q_y": 1e4, "rho": 100.0}, "round-off"),
    "nu = 0.2": ({"nu": 0.2}, "5 %"),
    "nu = 0.35": ({"nu": 0.35}, "5 %"),
}
TOLERANCE = {"round-off": 1e-9, "5 %": 0.05}
ENSEMBLE_VARIANTS = ("reference material", "nu = 0.2", "nu = 0.35")  # with --seeds


def maps_figure(a, resolutions, examples, dirs, name):
    """The space-time maps of every run, beside the report; None without numpy or matplotlib."""
    try:
        import numpy as np
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return None
    rows = [(cps, ex) for cps in resolutions for ex in examples]
    fig, axes = plt.subplots(len(rows), len(VARIANTS), figsize=(3.2 * len(VARIANTS), 2.6 * len(rows)),
                             squeeze=False)
    for (cps, ex), axrow in zip(rows, axes):
        for i, (variant, ax) in enumerate(zip(VARIANTS, axrow)):
            m = np.load(os.path.join(dirs[name(ex, cps, i)], "spacetime.npy"))
            ax.imshow(np.log10(m.T + 1e-3), aspect="auto", origin="lower", cmap="magma", vmin=-1, vmax=2)
            ax.set_title("(%s) %g cells/strut, %s" % (ex, cps, variant), fontsize=8)
            ax.set_xlabel("frame", fontsize=7)
            ax.set_ylabel("grid row", fontsize=7)
            ax.tick_params(labelsize=6)
    fig.tight_layout()
    path = os.path.splitext(a.out)[0] + "_maps.png"
    fig.savefig(path, dpi=60)
    plt.close(fig)
    return path


def ensemble_report(resolutions, examples, readings):
    """The tables of the ensembles (--seeds): readings[(ex, cps, variant)] is the list of the
    runs' readings, the unperturbed run first. Returns the report's lines and, per resolution,
    the variants that differ from the reference material."""
    lines, failures = [], {cps: [] for cps in resolutions}
    for cps, ex in ((c, e) for c in resolutions for e in examples):
        sr = EXAMPLES[ex]
        lines += ["## (%s): R = %g, %g cells across a strut, %d runs a material" % (
                      ex, sr["R"], cps, len(readings[(ex, cps, ENSEMBLE_VARIANTS[0])])), "",
                  "| material | labels | N_r | c_b/V fit: mean +- sd | c_b/V transit: mean +- sd | "
                  "against the reference material: most common label, means (difference / its "
                  "standard error) | wall [s] |",
                  "|---|---|---|---|---|---|---|"]
        base = None
        for variant in ENSEMBLE_VARIANTS:
            rs = readings[(ex, cps, variant)]
            labels = collections.Counter(r["label"] for r in rs)
            top = labels.most_common(1)[0][0]
            nrs = sorted({r["n_r"] for r in rs})
            st = {k: stats([r[k] for r in rs]) for k in ("fit", "transit")}
            verdict = "-"
            if base is None:
                base = (top, nrs, st)
            else:
                parts, ok = [], top == base[0] and nrs == base[1]
                for k in ("fit", "transit"):
                    m, b = st[k], base[2][k]
                    if m is None or b is None:
                        parts.append("%s -" % k)
                        ok = False
                        continue
                    dev = m["mean"] / b["mean"] - 1
                    se = math.sqrt((m["sd"] or 0) ** 2 / m["n"] + (b["sd"] or 0) ** 2 / b["n"])
                    ok = ok and abs(dev) <= TOLERANCE["5 %"]
                    parts.append("%s %+.1f %% (%s)" % (
                        k, 100 * dev, "%.1f" % (abs(m["mean"] - b["mean"]) / se) if se > 0 else "-"))
                verdict = "%s: %s%s" % ("same" if ok else "DIFFERENT", "; ".join(parts),
                                         "" if top == base[0] else ", label " + top)
                if not ok:
                    failures[cps].append("(%s) %s" % (ex, variant))
            cell = lambda m: "-" if m is None else "%s +- %s" % (fmt(m["mean"], 4), fmt(m["sd"], 2))
            lines.append("| %s | %s | %s | %s | %s | %s | %.0f-%.0f |" % (
                variant, ", ".join("%s %d" % kv for kv in sorted(labels.items())),
                ", ".join(map(str, nrs)), cell(st["fit"]), cell(st["transit"]), verdict,
                min(r["wall"] for r in rs), max(r["wall"] for r in rs)))
        lines.append("")
    return lines, failures


def write_report(path, lines, resolutions, failures, what):
    """Ends the report with the result at each resolution, writes and prints it; the exit code
    is 1 when something differs at the finest resolution."""
    for cps in resolutions:
        lines.append("Result at %g cells across a strut: %s" % (cps, (
            "%s gives the reference material's pattern." % what if not failures[cps] else
            "differs from the reference material: " + "; ".join(failures[cps]) + ".")))
    lines.append("")
    runs.write_report(path, lines)
    return 1 if failures[max(resolutions)] else 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cells-per-strut", default="4.5")
    ap.add_argument("--examples", default=",".join(EXAMPLES))
    ap.add_argument("--work", default=os.path.join(runs.ROOT, "out", "invariance"))
    ap.add_argument("--bin", default=os.path.join(runs.ROOT, "build", "bin"))
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--pore-contact", default="auto", choices=("auto", "single_field", "split_fields"),
                    help="the scenes' pore contact [auto, as the default and reference presets]")
    ap.add_argument("--seeds", type=seed_list, default=None,
                    help="comma list of seeds: compare ensembles of perturbed runs (see above)")
    ap.add_argument("--perturbation", type=float, default=0.01,
                    help="with --seeds: random particle offset, a fraction of the particle spacing "
                         "(the runner's range)")
    ap.add_argument("--out", default=None, help="default studies/validation/results/invariance.md, "
                    "invariance-single-field.md with --pore-contact single_field, "
                    "invariance-ensembles.md with --seeds")
    a = ap.parse_args()
    seeds = a.seeds or []
    if seeds and not a.perturbation > 0:
        ap.error("--perturbation: above 0 with --seeds (the unperturbed run is in every ensemble), "
                 "got %g" % a.perturbation)
    if a.out is None:
        a.out = os.path.join(runs.ROOT, "studies", "validation", "results",
                             "invariance-ensembles.md" if seeds else
                             "invariance.md" if a.pore_contact != "single_field" else
                             "invariance-single-field.md")
    run_bin, classify_bin = (os.path.join(a.bin, b) for b in ("compaction-run", "compaction-classify"))
    resolutions = [float(c) for c in a.cells_per_strut.split(",")]
    examples = [e for e in a.examples.split(",") if e]
    for e in examples:
        if e not in EXAMPLES:
            ap.error("--examples: unknown example %r; choose from %s" % (e, ", ".join(EXAMPLES)))
    suffix = "" if a.pore_contact == "single_field" else "-" + a.pore_contact  # a run's folder in --work
    name = lambda ex, cps, i: "%s-cps%g-%d%s" % (ex, cps, i, suffix)
    perturbed = lambda ex, cps, i, seed: "%s-p%g-s%d" % (name(ex, cps, i), a.perturbation, seed)
    scenes, members = {}, {}  # members[(ex, cps, variant)]: the ensemble's runs, unperturbed first
    for cps in resolutions:
        for ex in examples:
            for i, (variant, (material, _)) in enumerate(VARIANTS.items()):
                if seeds and variant not in ENSEMBLE_VARIANTS:
                    continue
                scene = dict(BASE, **EXAMPLES[ex], **material, cells_per_strut=cps,
                             pore_contact=a.pore_contact)
                scenes[name(ex, cps, i)] = scene
                members[(ex, cps, variant)] = [name(ex, cps, i)]
                for seed in seeds:
                    scenes[perturbed(ex, cps, i, seed)] = dict(scene, perturbation=a.perturbation, seed=seed)
                    members[(ex, cps, variant)].append(perturbed(ex, cps, i, seed))
    runs.check_all(scenes, run=run_bin)
    dirs = runs.run_all(a.work, scenes, jobs=a.jobs, run=run_bin)
    if seeds:
        lines = ["# Invariance at fixed S and R: nu, over ensembles of perturbed runs", "",
                 "Made by `python3 -m studies.validation.invariance %s`. phi = 0.4, pseudo-1D, to eps = 0.2, "
                 "S = 4e-3, pore contact %s. Each material is %d runs: unperturbed, and with every "
                 "particle moved at random by up to %g of the particle spacing for the seeds %s. "
                 "Checked against the reference material (nu = 0.3) of the same example and "
                 "resolution: the same most common label and set of N_r, and the means of both "
                 "readings of c_b/V within 5 %%; in brackets the difference of the means over its "
                 "standard error (sd^2/n of both ensembles), so that a reader sees whether a "
                 "difference stands out of the scatter." % (
                     " ".join(sys.argv[1:]), a.pore_contact, 1 + len(seeds), a.perturbation,
                     ", ".join(map(str, seeds))), ""]
        readings = {key: [runs.reading(dirs[n], classify_bin) for n in names]
                    for key, names in members.items()}
        body, failures = ensemble_report(resolutions, examples, readings)
        return write_report(a.out, lines + body, resolutions, failures, "every ensemble")

    lines = ["# Invariance at fixed S and R: q_y, rho and nu", "",
             "Made by `python3 -m studies.validation.invariance %s`. phi = 0.4, pseudo-1D, to eps = 0.2, "
             "S = 4e-3, pore contact %s; 4.5 cells across a strut is the default preset's "
             "resolution (20 per unit cell), 9 the reference preset's (40). Checked against the reference material of the same example "
             "and resolution: the same label and N_r, and c_b/V (both readings) within the "
             "tolerance of its row." % (" ".join(sys.argv[1:]), {
                 "auto": "auto (the presets': two velocity fields across closing pores)",
                 "split_fields": "split_fields (two velocity fields across closing pores)",
                 "single_field": "single_field (one velocity field)"}[a.pore_contact]), ""]
    failures = {cps: [] for cps in resolutions}
    for cps, ex in ((c, e) for c in resolutions for e in examples):
        sr = EXAMPLES[ex]
        lines += ["## (%s): R = %g, %g cells across a strut" % (ex, sr["R"], cps), "",
                  "| material | label (confidence) | c_b/V fit | c_b/V transit | N_r | against the reference material | wall [s] |",
                  "|---|---|---|---|---|---|---|"]
        base = None
        for i, (variant, (_, tolerance)) in enumerate(VARIANTS.items()):
            d = dirs[name(ex, cps, i)]
            m = runs.reading(d, classify_bin)
            verdict = "-"
            if base is None:
                base = m
            else:
                tol = TOLERANCE[tolerance]
                dev = max(abs(m[k] / base[k] - 1) for k in ("fit", "transit"))
                ok = m["label"] == base["label"] and m["n_r"] == base["n_r"] and dev <= tol
                verdict = "%s: c_b/V off by %.2g %% (allowed %s)%s" % (
                    "same" if ok else "DIFFERENT", 100 * dev, tolerance,
                    "" if m["label"] == base["label"] else ", label " + str(m["label"]))
                if not ok:
                    failures[cps].append("(%s) %s" % (ex, variant))
            lines.append("| %s | %s (%s) | %s +- %s | %s +- %s | %s | %s | %.0f |" % (
                variant, m["label"], fmt(m["confidence"], 2), fmt(m["fit"], 4), fmt(m["fit_err"], 2),
                fmt(m["transit"], 4), fmt(m["transit_err"], 2), m["n_r"], verdict, m["wall"]))
        lines.append("")
    figure = maps_figure(a, resolutions, examples, dirs, name)
    if figure:
        lines += ["![space-time maps of every run](%s)" % os.path.relpath(figure, os.path.dirname(a.out)), "",
                  "Space-time maps (log10 of the row-averaged plastic strain rate / (V/h0), rows "
                  "against frames of d_eps = 0.002) of every run above, one row per example and "
                  "resolution, the variants in the tables' order.", ""]
    return write_report(a.out, lines, resolutions, failures, "every variant")


if __name__ == "__main__":
    sys.exit(main())
