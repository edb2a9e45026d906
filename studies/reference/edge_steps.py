"""Why a band's two speed readings differ: the leading edge of a band through the structure moves
in steps (it stands while a row of pores closes, then moves on by about a unit cell), and the
transit reading, a two-point estimate, takes on wherever its two ends fall on a step.

For each result bundle given, reads the primary front's leading-edge points, the ones both
readings use (`compaction-classify --fronts`), and reports:
- both readings as the classifier gives them (fit: least-squares slope; transit: travel between
  the first and the last point over the strain it took; docs/classifier.md);
- the first and the last point's offsets from the fit's line, in unit cells, positive behind
  the line: transit / fit - 1 = (first - last) x cell / (fit x strain) exactly;
- the edge's steps: frames in which it stands (moves less than 0.1 cell), and the mean height of
  a step (consecutive moving frames) in cells;
- both readings again over the points from --from-eps on, after the onset transient (for (b) the
  fast front from the top plate has died by eps = 0.06 in every run of studies/reference/README.md).
Then per level (bundle names up to their -p<perturbation>-s<seed> tail) the mean and sample
standard deviation of each reading.

usage: python3 -m studies.reference.edge_steps [--bin build/bin] [--from-eps 0.06] [--out FILE]
       DIR [DIR ...]
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys

from studies.lib import runs

STAND = 0.1  # a frame-to-frame move below this share of a cell counts as standing


def fronts(out, classify_bin):
    res = subprocess.run([classify_bin, "--fronts", "--compact", out], check=True,
                         capture_output=True, text=True)
    return json.loads(res.stdout)


def line(points):
    """Least-squares slope and intercept of height against strain."""
    n = len(points)
    me = sum(e for e, _ in points) / n
    my = sum(y for _, y in points) / n
    sxx = sum((e - me) ** 2 for e, _ in points)
    slope = sum((e - me) * (y - my) for e, y in points) / sxx
    return slope, my - slope * me


def readings(points):
    """fit and transit (both positive in the direction of travel) of a leg's edge points."""
    if len(points) < 3:
        return None, None
    slope, _ = line(points)
    (e0, y0), (e1, y1) = points[0], points[-1]
    return abs(slope), abs(y1 - y0) / (e1 - e0)


def edge_numbers(pts, cell, from_eps):
    """The numbers of one leg from its leading-edge points [(eps, height / h0)] and the unit cell
    (h0): both readings, the ends' offsets, the steps, both readings from from_eps on."""
    fit, transit = readings(pts)
    down = pts[-1][1] < pts[0][1]
    behind = 1.0 if down else -1.0  # a point above a falling edge's line lags behind it
    slope, icpt = line(pts)
    offset = lambda p: behind * (p[1] - (icpt + slope * p[0])) / cell  # noqa: E731
    moves = [abs(b[1] - a[1]) / cell for a, b in zip(pts, pts[1:])]
    steps, run = [], 0.0
    for m in moves:
        if m >= STAND:
            run += m
        elif run:
            steps.append(run)
            run = 0.0
    if run:
        steps.append(run)
    late_fit, late_transit = readings([p for p in pts if p[0] >= from_eps])
    return {"fit": fit, "transit": transit, "window": (pts[0][0], pts[-1][0]), "n": len(pts),
            "first": offset(pts[0]), "last": offset(pts[-1]),
            "standing": sum(m < STAND for m in moves) / len(moves),
            "step": statistics.mean(steps) if steps else float("nan"), "n_steps": len(steps),
            "late_fit": late_fit, "late_transit": late_transit}


def analyse(out, classify_bin, from_eps):
    d = fronts(out, classify_bin)
    prim = [f for f in d["fronts"] if f["primary"]]
    if not prim or len(prim[0]["leg_edge"]) < 3:
        return None
    f = prim[0]
    r = edge_numbers([tuple(p) for p in f["leg_edge"]], d["unit_cell_h0"], from_eps)
    # the classifier's own readings (the same numbers as edge_numbers' to round-off)
    r.update(name=os.path.basename(os.path.normpath(out)), label=d.get("class") or "none",
             fit=f["speed_over_V"], transit=f["transit_speed_over_V"], transit_err=f["transit_error"])
    return r


def level_of(name):
    return re.sub(r"-p[^-]*-s\d+$", "", name)


def num(v, digits=3):
    return "-" if v is None or v != v else f"{v:.{digits}g}"


def report(rows, args):
    lines = ["# The leading edge of the band in steps: both speed readings, run by run", "",
             "Made by `python3 -m studies.reference.edge_steps --from-eps %s %s` (bundles outside the repository; "
             "classifier of `--bin`). Offsets of the leg's first and last points from the fit's line in "
             "unit cells, positive behind the line; transit / fit - 1 = (first - last) x cell / "
             "(fit x strain). A frame stands when the edge moves less than %s cell." % (
                 args.from_eps, " ".join(os.path.basename(os.path.normpath(d)) for d in args.dirs), STAND),
             "",
             "| run | label | leg (eps) | points | fit | transit (+- its error) | transit / fit | "
             "first, last offset [cell] | frames standing | steps, mean step [cell] | "
             f"fit from eps {args.from_eps} | transit from eps {args.from_eps} |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(
            f"| {r['name']} | {r['label']} | {r['window'][0]:.3f}-{r['window'][1]:.3f} | {r['n']} | "
            f"{num(r['fit'])} | {num(r['transit'])} +- {num(r['transit_err'], 2)} | "
            f"{num(r['transit'] / r['fit'])} | {r['first']:+.2f}, {r['last']:+.2f} | "
            f"{r['standing']:.0%} | {r['n_steps']}, {num(r['step'], 2)} | "
            f"{num(r['late_fit'])} | {num(r['late_transit'])} |")
    lines += ["", "| level | runs | fit | transit | fit from eps %s | transit from eps %s |" % (
        args.from_eps, args.from_eps), "|---|---|---|---|---|---|"]
    levels = {}
    for r in rows:
        levels.setdefault(level_of(r["name"]), []).append(r)
    for lv, rs in levels.items():
        def ms(key):
            v = [r[key] for r in rs if r[key] is not None]
            if len(v) < 2:
                return num(v[0]) if v else "-"
            return f"{statistics.mean(v):.3g} +- {statistics.stdev(v):.2g}"
        lines.append(f"| {lv} | {len(rs)} | {ms('fit')} | {ms('transit')} | {ms('late_fit')} | "
                     f"{ms('late_transit')} |")
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dirs", nargs="+", help="result bundles (compaction-run --out)")
    ap.add_argument("--bin", default=os.path.join(runs.ROOT, "build", "bin"),
                    help="where compaction-classify is (default: build/bin of this checkout)")
    ap.add_argument("--from-eps", type=float, default=0.06,
                    help="strain after which the onset transient is over (default 0.06)")
    ap.add_argument("--out", help="write the Markdown report here (default: standard output)")
    args = ap.parse_args()
    if not 0 <= args.from_eps < 1:
        ap.error("--from-eps must be in [0, 1), got %s" % args.from_eps)
    classify_bin = os.path.join(args.bin, "compaction-classify")
    rows = []
    for d in args.dirs:
        if not runs.finished(d):
            ap.error("%s is not a finished result bundle" % d)
        r = analyse(d, classify_bin, args.from_eps)
        if r is None:
            print("edge_steps: %s has no primary front with a leg to read; left out" % d, file=sys.stderr)
            continue
        rows.append(r)
    text = report(rows, args)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text)
    else:
        sys.stdout.write(text)


if __name__ == "__main__":
    main()
