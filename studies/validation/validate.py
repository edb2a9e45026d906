"""Validation of engine + classifier against Blatny et al., PRL 128, 228002 (2022).

Runs (results cached under --work; a cached bundle is not computed again):
  examples    the paper's six examples at phi = 0.4, pseudo-1D, to full density
  fig3        a line of >= 5 points through class (b): c_b/V and N_r vs q_y/(rho V^2) = R/S^2
  full2d      examples (a) and (b) in full 2D (17 x 34 cells) against pseudo-1D, to eps = 0.2
  resolution  the six examples at several resolutions
and writes studies/validation/README.md with the space-time maps copied to studies/validation/results/; the report's
text below the notes marker (what the runs show, written by hand) is kept (studies/lib/kept_notes.py).

  python3 -m studies.validation.validate --jobs 2 --resolutions 8,12,20,30 --fig3-cells 20,30 --full2d-cells 12,20

Costs grow as cells^3 / S (class (d), S = 1.32e-3, is the slowest: 7 min at 20 cells per unit
cell, 26 min at 30); the command above is about 4 core-hours from scratch (2 h with --jobs 2).
--eps-scale shortens every run's final strain (1 = as in EXAMPLES).
"""
import argparse
import json
import math
import os
import shutil
import sys
import time

from studies.lib import examples, kept_notes, runs
from studies.lib.spread import spearman

ROOT = runs.ROOT
PHI = examples.PHI
# class: (S, R, eps_end at eps-scale 1): to full density, 1 - phi, as the service runs them.
EXAMPLES = {k: (S, R, 0.6) for k, (S, R) in examples.EXAMPLES.items()}
FIG3_S, FIG3_R = examples.FIG3_S, examples.FIG3_R
FIG3_EPS = 0.6     # to full density: reflections happen after the band first reaches the bottom
FULL2D_EPS = 0.2   # 17 times the particles of pseudo-1D: the prereflection band only


def fig3_name(R, cells, eps_end):
    """A point of the Fig. 3 line that is one of the examples shares its run."""
    for k, (S, R_k, _) in EXAMPLES.items():
        if S == FIG3_S and R_k == R:
            return f"{k}_p1d_{cells}_{eps_end:g}"
    return f"fig3_R{R:g}_{cells}_{eps_end:g}"


def scene(args, name, S, R, cells, eps_end, geometry="pseudo1d"):
    """A run's folder name and flags; runs with another pore contact than the engine's default
    (single_field) are named after it, so that both stay cached side by side."""
    flags = {"S": S, "R": R, "phi": PHI, "cells_per_unit": cells, "eps_end": eps_end,
             "geometry": geometry, "snapshot_eps": min(0.2, eps_end)}
    if args.pore_contact != "single_field":
        name, flags["pore_contact"] = f"{name}_{args.pore_contact}", args.pore_contact
    return name, flags


def full2d_cells(args):
    return [int(x) for x in args.full2d_cells.split(",")] if args.full2d_cells else [args.cells]


def fig3_cells(args):
    return [int(x) for x in args.fig3_cells.split(",")] if args.fig3_cells else [args.cells]


def plan(args, sections):
    """Every run the requested sections need, as {name: flags}."""
    out = {}
    add = lambda name_flags: out.__setitem__(*name_flags)
    if "examples" in sections:
        for k, (S, R, e) in EXAMPLES.items():
            add(scene(args, f"{k}_p1d_{args.cells}_{e * args.eps_scale:g}", S, R, args.cells, e * args.eps_scale))
    if "resolution" in sections:
        for c in [int(x) for x in args.resolutions.split(",")]:
            for k, (S, R, e) in EXAMPLES.items():
                add(scene(args, f"{k}_p1d_{c}_{e * args.eps_scale:g}", S, R, c, e * args.eps_scale))
    if "fig3" in sections:
        for c3 in fig3_cells(args):
            for R in FIG3_R:
                add(scene(args, fig3_name(R, c3, FIG3_EPS * args.eps_scale), FIG3_S, R, c3, FIG3_EPS * args.eps_scale))
    if "full2d" in sections:
        for c2 in full2d_cells(args):
            for k in ("a", "b"):
                S, R, _ = EXAMPLES[k]
                e = FULL2D_EPS * args.eps_scale
                add(scene(args, f"{k}_2d_{c2}_{e:g}", S, R, c2, e, "full2d"))
                add(scene(args, f"{k}_p1d_{c2}_{e:g}", S, R, c2, e))
    return out


def run(args, name, S, R, cells, eps_end, geometry="pseudo1d"):
    """The results of a run that plan() listed (run_all has computed it)."""
    out = runs.run_one(args.work, *scene(args, name, S, R, cells, eps_end, geometry), run=args.run)
    cls = runs.classify(out, args.classify)
    s = runs.summary(out)
    return {"name": name, "dir": out, "S": S, "R": R, "cells": cells, "eps_end": eps_end,
            "geometry": geometry, "wall": s["wall_seconds"], "phi_discrete": s["phi_discrete"],
            "cls": cls}


def fmt(v, p=3):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-"
    return f"{v:.{p}g}" if isinstance(v, float) else str(v)


def copy_map(args, r, tag):
    os.makedirs(args.images, exist_ok=True)
    dst = os.path.join(args.images, f"{tag}.png")
    shutil.copyfile(os.path.join(r["dir"], "spacetime.png"), dst)
    return os.path.relpath(dst, os.path.dirname(args.report))


def stress_plot(args, r, tag):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import numpy as np
    except ImportError:
        return None
    d = np.genfromtxt(os.path.join(r["dir"], "frames.csv"), delimiter=",", names=True)
    fig, ax = plt.subplots(figsize=(4, 2.4))
    ax.plot(d["eps"], d["sigma_top_over_qy"], label="top")
    ax.plot(d["eps"], d["sigma_bottom_over_qy"], label="bottom")
    ax.set_xlabel("eps"); ax.set_ylabel("sigma / q_y"); ax.legend(); ax.set_title(tag)
    lo = np.percentile(np.r_[d["sigma_top_over_qy"][2:], d["sigma_bottom_over_qy"][2:]], 1)
    hi = np.percentile(np.r_[d["sigma_top_over_qy"][2:], d["sigma_bottom_over_qy"][2:]], 99)
    ax.set_ylim(min(0, lo), hi * 1.2 if hi > 0 else 1)
    fig.tight_layout()
    dst = os.path.join(args.images, f"{tag}_stress.png")
    fig.savefig(dst, dpi=90); plt.close(fig)
    return os.path.relpath(dst, os.path.dirname(args.report))


def row(expected, r):
    c = r["cls"]
    ok = "yes" if c["class"] == expected else "**no**"
    return (f"| {expected} | {c['class']} | {ok} | {fmt(c['confidence'], 2)} | {c['runner_up'] or '-'} | "
            f"{c['n_reflections']} | {fmt(c['band_speed_ratio'])} | {fmt(1 / (1 - r['phi_discrete']))} | "
            f"{fmt(c['features']['stress_ratio'])} | {fmt(c['features']['coherence'], 2)} | "
            f"{fmt(c['features']['peak_jump'], 2)} | {fmt(c['features']['deflection_growth'], 2)} | "
            f"{r['wall']:.1f} | {r['geometry']} {r['cells']}/cell, eps {r['eps_end']:g} |")


def reading_gap(r2, r1, name):
    """One reading of c_b/V ("fit" or "transit", runs.band_speeds) in full 2D against pseudo-1D:
    both values with their uncertainty and the relative difference."""
    b2, b1 = runs.band_speeds(r2["cls"]["features"]), runs.band_speeds(r1["cls"]["features"])
    v2, v1 = b2[name], b1[name]
    if not v1 or not v2:
        return f"{name} -"
    return (f"{name} {fmt(v2)} +- {fmt(b2[name + '_err'], 2)} against {fmt(v1)} +- "
            f"{fmt(b1[name + '_err'], 2)}, {100 * (v2 / v1 - 1):+.1f} %")


HEADER = ("| expected | found | match | confidence | runner-up | N_r | c_b/V | 1/(1-phi) | "
          "top/bottom stress | coherence | peak jump [cells] | deflection growth [dec] | wall [s] | run |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cells", type=int, default=20, help="cells per unit cell of the examples")
    ap.add_argument("--resolutions", default="8,12,16", help="comma list for the resolution study")
    ap.add_argument("--fig3-cells", default=None,
                    help="comma list of resolutions of the Fig. 3 line (default: --cells)")
    ap.add_argument("--full2d-cells", default=None,
                    help="comma list of resolutions of the full-2D comparison (default: --cells)")
    ap.add_argument("--eps-scale", type=float, default=1.0)
    ap.add_argument("--sections", default="examples,fig3,full2d,resolution")
    ap.add_argument("--pore-contact", default="single_field",
                    choices=("single_field", "split_fields", "auto"),
                    help="pore_contact of every run (docs/engine.md, Pore contact) [single_field]")
    ap.add_argument("--work", default="/tmp/compaction-validation")
    ap.add_argument("--jobs", type=int, default=1, help="runs at a time (each on one thread)")
    ap.add_argument("--run", default=os.path.join(ROOT, "build", "bin", "compaction-run"))
    ap.add_argument("--classify", default=os.path.join(ROOT, "build", "bin", "compaction-classify"))
    ap.add_argument("--report", default=os.path.join(ROOT, "studies", "validation", "README.md"))
    ap.add_argument("--images", default=os.path.join(ROOT, "studies", "validation", "results"))
    args = ap.parse_args()
    sections = args.sections.split(",")
    t0 = time.time()
    runs.run_all(args.work, plan(args, sections), jobs=args.jobs, run=args.run)
    md = ["# Validation against the paper's examples",
          "",
          "Written by `python3 -m studies.validation.validate` "
          f"(`{' '.join(os.path.basename(a) if i == 0 else a for i, a in enumerate(sys.argv))}`). "
          f"phi = 0.4, pore_contact = {args.pore_contact}. Labels from `compaction-classify` "
          "(docs/classifier.md): it reads the run's space-time map, plate stresses and strut "
          "diagnostics, never S or R.", ""]

    if "examples" in sections:
        md += [f"## The six examples (pseudo-1D, {args.cells} cells per unit cell)", "", HEADER]
        pics, total = [], 0.0
        for k, (S, R, e) in EXAMPLES.items():
            r = run(args, f"{k}_p1d_{args.cells}_{e * args.eps_scale:g}", S, R, args.cells, e * args.eps_scale)
            md.append(row(k, r))
            tag = f"{k}_p1d_{args.cells}"
            pics.append((k, S, R, copy_map(args, r, tag), stress_plot(args, r, tag)))
            total += r["wall"]
        md += ["", f"Total wall time of the six: {total:.0f} s ({total / 60:.1f} min), one thread each, "
               f"{args.jobs} at a time.", "", "Space-time maps (height up, eps to the right) and plate stresses:", ""]
        for k, S, R, m, st in pics:
            md.append(f"**({k})** S = {S:g}, R = {R:g}: ![{k}]({m})" + (f" ![{k} stress]({st})" if st else ""))
            md.append("")

    if "resolution" in sections:
        res = [int(x) for x in args.resolutions.split(",")]
        md += ["## Resolution study (pseudo-1D)", "",
               "| class | " + " | ".join(f"{c} cells: label (conf), c_b/V, N_r, wall" for c in res) + " |",
               "|---|" + "---|" * len(res)]
        finest = {}
        for k, (S, R, e) in EXAMPLES.items():
            cells = []
            for c in res:
                r = run(args, f"{k}_p1d_{c}_{e * args.eps_scale:g}", S, R, c, e * args.eps_scale)
                cl = r["cls"]
                cells.append(f"{cl['class']} ({fmt(cl['confidence'], 2)}), {fmt(cl['band_speed_ratio'])}, "
                             f"{cl['n_reflections']}, {r['wall']:.0f} s")
                if c == max(res):
                    finest[k] = r
            md.append(f"| {k} | " + " | ".join(cells) + " |")
        md.append("")
        if max(res) != args.cells:  # the maps the study converges to, beside the examples' above
            md += [f"Space-time maps at {max(res)} cells per unit cell:", ""]
            for k, r in finest.items():
                md += [f"**({k})** ![{k} at {max(res)} cells]({copy_map(args, r, f'{k}_p1d_{max(res)}')})", ""]

    if "fig3" in sections:
        lines = []
        for c3 in fig3_cells(args):
            e = FIG3_EPS * args.eps_scale
            pts = [(R / FIG3_S ** 2, run(args, fig3_name(R, c3, e), FIG3_S, R, c3, e)) for R in FIG3_R]
            lines.append((c3, pts))
            md += [f"## Band speed vs q_y/(rho V^2) (Fig. 3 line, S = {FIG3_S:g}, pseudo-1D, {c3} cells per unit cell)", "",
                   "| q_y/(rho V^2) = R/S^2 | R | class | N_r | turns of the band | c_b/V | wall [s] |",
                   "|---|---|---|---|---|---|---|"]
            for x, r in pts:
                cl = r["cls"]
                md.append(f"| {x:.3g} | {r['R']:g} | {cl['class']} | {cl['n_reflections']} | "
                          f"{cl['features'].get('band_turns', '-')} | {fmt(cl['band_speed_ratio'])} | {r['wall']:.0f} |")
            # The Fig. 3 checks (c_b/V rises with q_y/(rho V^2), N_r does not fall), over the
            # points labelled (b), in order of q_y/(rho V^2)
            b_pts = [(x, r["cls"]) for x, r in pts if r["cls"]["class"] == "b" and r["cls"]["band_speed_ratio"]]
            xs = [math.log(x) for x, _ in b_pts]
            ys = [math.log(c["band_speed_ratio"]) for _, c in b_pts]
            if len(xs) >= 2:
                n = len(xs); mx = sum(xs) / n; my = sum(ys) / n
                slope = sum((a - mx) * (b - my) for a, b in zip(xs, ys)) / sum((a - mx) ** 2 for a in xs)
                md += ["", f"Fitted exponent over the class-(b) points: c_b/V ~ (q_y/(rho V^2))^{slope:.3f} ({n} points)."]
            speeds = [c["band_speed_ratio"] for _, c in b_pts]
            nrs = [c["n_reflections"] for _, c in b_pts]
            rising = all(b > a for a, b in zip(speeds, speeds[1:]))
            not_falling = all(b >= a for a, b in zip(nrs, nrs[1:]))
            md += ["", f"Checks over the {len(b_pts)} points labelled (b) (at least five asked for): "
                   f"c_b/V rises with q_y/(rho V^2) at every step: {'yes' if rising else '**no**'} "
                   f"(rank correlation {fmt(spearman(xs, speeds), 2)}); "
                   f"N_r does not fall: {'yes' if not_falling else '**no**'} (N_r {', '.join(map(str, nrs))}).", ""]
        try:
            import matplotlib
            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
            fig, ax = plt.subplots(1, 2, figsize=(8, 3))
            for c3, pts in lines:  # filled markers: labelled (b); hollow: another class
                X = [x for x, _ in pts]
                Y0 = [r["cls"]["band_speed_ratio"] or float("nan") for _, r in pts]
                Y1 = [r["cls"]["n_reflections"] for _, r in pts]
                other = [r["cls"]["class"] != "b" for _, r in pts]
                l0, = ax[0].loglog(X, Y0, "o-", label=f"{c3} cells")
                l1, = ax[1].semilogx(X, Y1, "s-", label=f"{c3} cells")
                for a, Y, ln, mk in ((ax[0], Y0, l0, "o"), (ax[1], Y1, l1, "s")):
                    a.plot([x for x, o in zip(X, other) if o], [y for y, o in zip(Y, other) if o], mk,
                           mfc="white", mec=ln.get_color())
            ax[0].axhline(1 / (1 - PHI), ls="--", c="gray"); ax[0].set_xlabel("q_y/(rho V^2)"); ax[0].set_ylabel("c_b/V")
            ax[1].set_xlabel("q_y/(rho V^2)"); ax[1].set_ylabel("N_r")
            ax[0].legend(fontsize=7); ax[1].legend(fontsize=7)
            fig.tight_layout(); os.makedirs(args.images, exist_ok=True)
            fig.savefig(os.path.join(args.images, "fig3_line.png"), dpi=90); plt.close(fig)
            md += ["![Fig. 3 line](%s)" % os.path.relpath(os.path.join(args.images, "fig3_line.png"),
                                                        os.path.dirname(os.path.abspath(args.report))), "",
                   "Filled markers: labelled (b); hollow: labelled another class."]
        except ImportError:
            pass
        md.append("")

    if "full2d" in sections:
        for c2 in full2d_cells(args):
            md += [f"## Full 2D (17 x 34 cells, {c2} cells per unit cell) against pseudo-1D", "", HEADER]
            gaps, maps = [], []
            suffix = "" if args.pore_contact == "single_field" else f"_{args.pore_contact}"
            for k in ("a", "b"):
                S, R, _ = EXAMPLES[k]
                e = FULL2D_EPS * args.eps_scale
                r2 = run(args, f"{k}_2d_{c2}_{e:g}", S, R, c2, e, "full2d")
                r1 = run(args, f"{k}_p1d_{c2}_{e:g}", S, R, c2, e)
                md += [row(k, r2), row(k, r1)]
                same = r2["cls"]["class"] == r1["cls"]["class"]
                gaps.append(f"({k}): full 2D labelled {r2['cls']['class']}, pseudo-1D {r1['cls']['class']} "
                            f"({'same' if same else '**different**'}); c_b/V full 2D against pseudo-1D: "
                            + "; ".join(reading_gap(r2, r1, name) for name in ("fit", "transit")))
                maps.append(f"**({k})** full 2D ![{k} full 2D]({copy_map(args, r2, f'{k}_2d_{c2}{suffix}')}) "
                            f"pseudo-1D ![{k} pseudo-1D]({copy_map(args, r1, f'{k}_p1d_{c2}{suffix}')})")
            md += [""] + [f"- {g}" for g in gaps] + ["", "Space-time maps (height up, eps to the right):", ""]
            md += [m + "\n" for m in maps]

    md += [f"Total wall time of this report's runs (new and cached): {time.time() - t0:.0f} s of this invocation.", ""]
    kept_notes.write(args.report, "\n".join(md))  # and what the runs show, written by hand
    print("wrote", args.report, file=sys.stderr)


if __name__ == "__main__":
    main()
