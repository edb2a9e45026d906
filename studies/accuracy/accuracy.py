"""Run time against error: the paper's examples (a) and (b), a fast and a slow point, over a
grid of numerics; each run's error against the converged reference of its point.

  python3 -m studies.accuracy.accuracy --jobs 2 --reference-runs DIR  # all runs (about 75 core-minutes)
  python3 -m studies.accuracy.accuracy --points e --jobs 2            # one point only (the fast one)

Numerics varied (one at a time from the base, 16 cells per unit cell, 2 x 2 particles per cell,
APIC, MLS gradient, CFL 0.5): cells per unit cell 8, 12, 16, 20 and the reference 30; particles
per cell 1 and 3; PIC/FLIP; CFL 0.25 and 1.0; the exact B-spline gradient at 16 and 20 cells.
The engine keeps F and the transfers in double (small strain increments at low S need it); there is
no float variant to measure.

The reference of (a) and (b) is the converged one of studies/reference/reference.py (its bundles
in --reference-runs, levels 20-80 cells per unit cell): its Richardson limit where the levels
converge, else its finest level, and the finest level's space-time map. The fast and slow points
(e), (d) have no convergence study: their reference is their 30-cell run, and their errors are
against that (marked so in the report).
Errors against the reference:
  c_b/V        relative difference of the classifier's prereflection band speed, both readings
               (fit and transit, docs/classifier.md; where the reference is a band, (a) or (b));
  plateau      relative difference of the mean top plate stress over eps in [eps_end/4, eps_end];
  map          relative L1 norm of the difference of the space-time maps, both averaged over
               each row of unit cells (the frames share the same strains);
  label        whether the classifier gives the reference's label.
Cost is modelled as particle-steps (deterministic) times the ns per particle-step of the transfer
and gradient on a quiet core (NS_QUIET, from bench/results/engine_bench.md); the measured wall
time is listed too. A run is on the Pareto front when no other run of its point is
both cheaper and has a smaller largest error. Writes studies/accuracy/README.md (tables, the commands; its
text below the notes marker, the reading written by hand, is kept: studies/lib/kept_notes.py) and
studies/accuracy/results/pareto.png (error against cost per point).
"""
import argparse
import math
import os
import sys

import numpy as np

from studies.lib import kept_notes, runs

from studies.reference import reference as convergence

PHI = 0.4
# name: (S, R, eps_end, paper's class or None, what it stands for)
POINTS = {
    "a": (4e-3, 1e-5, 0.2, "a", "paper's example (a), non-reflecting band"),
    "b": (4e-3, 4e-4, 0.2, "b", "paper's example (b), reflecting band"),
    "e": (1e-1, 1e-5, 0.2, "e", "fast point: example (e), S = 0.1, few steps per strain"),
    "d": (1.32e-3, 4e-3, 0.1, "d", "slow point: example (d), S = 1.32e-3, most steps per strain"),
}
BASE = {"cells_per_unit": 16, "particles_per_cell": 2, "transfer": "apic", "cfl": 0.5,
        "gradient": "mls"}
REFERENCE_CELLS = 30
# variant name: overrides of BASE
VARIANTS = {
    "cells 8": {"cells_per_unit": 8},
    "cells 12": {"cells_per_unit": 12},
    "cells 16": {},
    "cells 20": {"cells_per_unit": 20},
    "cells 30": {"cells_per_unit": REFERENCE_CELLS},
    "cells 16, ppc 1": {"particles_per_cell": 1},
    "cells 16, ppc 3": {"particles_per_cell": 3},
    "cells 16, pic_flip": {"transfer": "pic_flip"},
    "cells 16, cfl 0.25": {"cfl": 0.25},
    "cells 16, cfl 1.0": {"cfl": 1.0},
    "cells 16, bspline": {"gradient": "bspline"},
    "cells 20, bspline": {"cells_per_unit": 20, "gradient": "bspline"},
}
# ns per particle-step of each transfer / gradient pair on one quiet core, from the engine
# benchmark (bench/results/engine_bench.md): the cost model of the Pareto front, since the wall
# times of runs sharing the machine vary by +-30 %.
NS_QUIET = {("apic", "mls"): 57.4, ("pic_flip", "mls"): 68.4, ("apic", "bspline"): 74.7}
# The slow point costs three times per strain: only the resolution levels there.
SLOW_ONLY = ("cells 8", "cells 12", "cells 16", "cells 20", "cells 30")
# The levels of the convergence study (studies/reference/reference.py) that the reference uses.
STUDY_CELLS = (20, 30, 40, 60, 80)


def scene_name(point, flags):
    keys = ("cells_per_unit", "particles_per_cell", "transfer", "cfl", "gradient")
    return point + "_" + "_".join(str(flags[k]) for k in keys) + f"_e{flags['eps_end']:g}"


def plan(points):
    scenes = {}
    for p in points:
        S, R, eps_end, _, _ = POINTS[p]
        for v, over in VARIANTS.items():
            if p == "d" and v not in SLOW_ONLY:
                continue
            flags = dict(BASE, **over, S=S, R=R, phi=PHI, eps_end=eps_end, snapshot_eps=min(0.2, eps_end))
            scenes[(p, v)] = (scene_name(p, flags), flags)
    return scenes


def height_profile(out, s):
    """The space-time map (frames x rows) averaged over each row of unit cells: the resolution of
    the structure, so that maps of different grids compare (and a band one grid cell off is
    not counted as a miss)."""
    m = np.load(os.path.join(out, s["spacetime"]["file"])).astype(np.float64)
    cells = s["params"]["n_rows"]
    per = m.shape[1] // cells
    return m[:, :per * cells].reshape(m.shape[0], cells, per).mean(axis=2)


def measure(out, eps_end, classify_bin):
    s = runs.summary(out)
    fr = runs.frames(out)
    cls = runs.classify(out, classify_bin)
    lo = eps_end / 4
    top = [t for e, t in zip(fr["eps"], fr["sigma_top_over_qy"]) if lo <= e <= eps_end + 1e-12]
    return {"summary": s, "cls": cls, "plateau": sum(top) / len(top) if top else float("nan"),
            "map": height_profile(out, s), "wall": s["wall_seconds"],
            "work": s["n_particles"] * s["steps"] / 1e6,
            "cost": s["n_particles"] * s["steps"] * 1e-9 * NS_QUIET[(s["params"]["transfer"], s["params"]["gradient"])],
            "ns": s["ns_per_particle_step"], "status": s["status"]}


def reference_of(p, results, args, classify_bin):
    """The reference of point p: {"what", "cls", "fit", "transit", "plateau", "map", "run"
    (the variant that is the reference, or None)}; None when it cannot be made."""
    eps_end = POINTS[p][2]
    if p in ("a", "b"):
        ref = convergence.reference(args.bin, args.reference_runs, p, STUDY_CELLS)
        if ref is None:
            print(f"({p}): fewer than three levels of the convergence study in "
                  f"{args.reference_runs}: left out", file=sys.stderr)
            return None
        finest = ref["finest"]
        m = measure(finest["dir"], eps_end, classify_bin)

        def described(key):
            c = ref[key]
            return ("Richardson limit +- %.1f %%" if c["extrapolated"] else
                    "finest level, not converged: last change %.1f %%") % (100 * c["uncertainty"])
        what = (f"converged reference, studies/reference/README.md: c_b/V fit {described('fit')}, transit "
                f"{described('transit')}, plateau {described('plateau')}; label and map of its "
                f"finest level, {finest['cells']} cells")
        return {"what": what, "cls": m["cls"], "fit": ref["fit"]["value"],
                "transit": ref["transit"]["value"], "plateau": ref["plateau"]["value"],
                "map": m["map"], "run": None}
    r = results.get((p, "cells 30"))
    if r is None:
        return None
    f = r["cls"].get("features") or {}
    return {"what": f"its {REFERENCE_CELLS}-cell run; no convergence study", "cls": r["cls"],
            "fit": f.get("band_speed_ratio"), "transit": f.get("band_speed_transit"),
            "plateau": r["plateau"], "map": r["map"], "run": "cells 30"}


def rel(a, b):
    if a is None or b is None or not b:
        return float("nan")
    return abs(a - b) / abs(b)


def largest(*errors):
    """The largest finite error (NaN when none is finite)."""
    finite = [e for e in errors if math.isfinite(e)]
    return max(finite) if finite else float("nan")


def fmt(v, pct=False):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-"
    return f"{100 * v:.1f} %" if pct else f"{v:.3g}"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--points", default="a,b,e,d", help="comma list of " + ", ".join(POINTS))
    ap.add_argument("--jobs", type=int, default=1, help="runs at a time (each on one thread)")
    ap.add_argument("--work", default="/tmp/compaction-accuracy", help="bundles (cached)")
    ap.add_argument("--bin", default=os.path.join(runs.ROOT, "build", "bin"),
                    help="where compaction-run and compaction-classify are")
    ap.add_argument("--reference-runs", default=os.path.join(runs.ROOT, "out", "reference"),
                    help="the bundles of studies/reference/reference.py (its --runs)")
    ap.add_argument("--no-run", action="store_true", help="report on the bundles present only")
    ap.add_argument("--report", default=os.path.join(runs.ROOT, "studies", "accuracy", "README.md"))
    ap.add_argument("--images", default=os.path.join(runs.ROOT, "studies", "accuracy", "results"))
    args = ap.parse_args()
    points = [p for p in args.points.split(",") if p]
    for p in points:
        if p not in POINTS:
            ap.error(f"--points: unknown point {p!r}; choose from {', '.join(POINTS)}")

    scenes = plan(points)
    if args.no_run:
        dirs = {n: os.path.join(args.work, n) for n, _ in scenes.values()
                if runs.finished(os.path.join(args.work, n))}
    else:
        dirs = runs.run_all(args.work, {n: f for n, f in scenes.values()}, jobs=args.jobs,
                            run=os.path.join(args.bin, "compaction-run"))
    classify_bin = os.path.join(args.bin, "compaction-classify")
    results = {key: measure(dirs[name], POINTS[key[0]][2], classify_bin)
               for key, (name, _) in scenes.items() if name in dirs}
    refs = {p: reference_of(p, results, args, classify_bin) for p in points}
    points = [p for p in points if refs[p]]

    md = ["# Run time against error", "",
          "Written by `studies/accuracy/accuracy.py "
          + " ".join(sys.argv[1:]) + "` (see its header for the method). Every run is pseudo-1D, "
          "phi = 0.4, one thread. The error of each run of (a) and (b) is measured against the "
          "converged reference of studies/reference/README.md (Richardson limit where the levels converge, "
          "else the finest level; the space-time map of the finest level); (e) and (d) have no "
          f"convergence study, and their errors are against their {REFERENCE_CELLS}-cell run. "
          "Cells per unit cell n are n (1 - sqrt(1 - phi)) = 0.225 n across a strut "
          "(16 cells: 3.6).", ""]
    pareto = {}
    for p in points:
        S, R, eps_end, paper, what = POINTS[p]
        ref = refs[p]
        md += [f"## ({p}) S = {S:g}, R = {R:g}, to eps = {eps_end:g}: {what}", "",
               f"Reference ({ref['what']}): label **{ref['cls']['class']}** (paper: {paper}), "
               f"c_b/V = {fmt(ref['fit'])} (fit) and {fmt(ref['transit'])} (transit), "
               f"plateau sigma_top/q_y = {fmt(ref['plateau'])}.", "",
               "| numerics | status | label | c_b/V fit | c_b/V transit | error fit | error transit | "
               "error plateau | error map | particle-steps [1e6] | one-core time [s], model | "
               "wall [s] | ns/particle-step | Pareto |",
               "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        pts, rows = [], []
        for v in VARIANTS:
            r = results.get((p, v))
            if r is None:
                continue
            features = r["cls"].get("features") or {}
            fit, transit = features.get("band_speed_ratio"), features.get("band_speed_transit")
            # c_b/V is a band's speed: compared only where the reference is a band, (a) or (b).
            band = ref["cls"]["class"] in ("a", "b")
            e_fit = rel(fit, ref["fit"]) if band else float("nan")
            e_transit = rel(transit, ref["transit"]) if band else float("nan")
            e_pl = rel(r["plateau"], ref["plateau"])
            e_map = float(np.abs(r["map"] - ref["map"]).sum() / max(np.abs(ref["map"]).sum(), 1e-300)) \
                if r["map"].shape == ref["map"].shape else float("nan")
            same = r["cls"]["class"] == ref["cls"]["class"]
            err = largest(e_fit, e_transit, e_pl, e_map)
            is_ref = ref["run"] == v
            rows.append((v, r, fit, transit, same, e_fit, e_transit, e_pl, e_map, err, is_ref))
            if not is_ref:
                pts.append((v, r["cost"], err, same))
        # On the Pareto front: no other run is both cheaper and more accurate (largest error).
        front = {row[0] for row in rows if not row[10] and not any(
            o[1]["cost"] < row[1]["cost"] and o[9] < row[9] for o in rows if not o[10])}
        for v, r, fit, transit, same, e_fit, e_transit, e_pl, e_map, err, is_ref in rows:
            md.append(f"| {v}{' (reference)' if is_ref else ''} | {r['status']} | "
                      f"{r['cls']['class']}{'' if same else ' (differs)'} | {fmt(fit)} | {fmt(transit)} | "
                      f"{fmt(e_fit, True)} | {fmt(e_transit, True)} | {fmt(e_pl, True)} | {fmt(e_map, True)} | "
                      f"{r['work']:.0f} | {r['cost']:.0f} | "
                      f"{r['wall']:.1f} | {r['ns']:.1f} | {'yes' if v in front else ''} |")
        md.append("")
        pareto[p] = pts

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, axes = plt.subplots(1, len(points), figsize=(4.2 * len(points), 3.6), squeeze=False)
        for ax, p in zip(axes[0], points):
            for v, work, err, same in pareto[p]:
                ax.loglog(work, err, "o" if same else "x", color="C0" if v.startswith("cells") and "," not in v else "C1")
                ax.annotate(v.replace("cells ", ""), (work, err), fontsize=6, xytext=(3, 2), textcoords="offset points")
            ax.set_title(f"({p})")
            ax.set_xlabel("one-core time [s] (particle-steps x quiet ns/particle-step)")
            ax.set_ylabel("largest relative error")
        fig.tight_layout()
        os.makedirs(args.images, exist_ok=True)
        fig.savefig(os.path.join(args.images, "pareto.png"), dpi=90)
        plt.close(fig)
        md += ["![error against cost](%s)" % os.path.relpath(os.path.join(args.images, "pareto.png"),
                                                    os.path.dirname(os.path.abspath(args.report))), "",
               "Largest of the four relative errors against the modelled one-core time (particle-steps "
               "times the quiet-machine ns per particle-step of the transfer and gradient; the measured "
               "wall times above include the load of the other run sharing the machine); blue: resolution levels, "
               "orange: other numerics at 16 or 20 cells; a cross marks a label that differs from "
               "the reference's. The errors of (a) and (b) are against the converged reference.", ""]
    except ImportError:
        pass

    os.makedirs(os.path.dirname(args.report), exist_ok=True)
    kept_notes.write(args.report, "\n".join(md))  # and the reading of the tables, written by hand
    print("wrote", args.report, file=sys.stderr)


if __name__ == "__main__":
    main()
