"""The first band of pseudo-1D runs read from the particles: where the material stops
compacting, how fast that edge runs, and how dense the zone behind it is, against the
classifier's two readings of c_b/V and the mass balance c_b/V = 1/(1 - phi/phi_f) (the paper,
the paragraph before its Fig. 3).

usage: python3 -m studies.validation.compacted_zone BUNDLE... [--bin build/bin] [--out FILE]

Each bundle needs its movie.bin (schema/movie-format.md; every run since engine 0.2.1 writes one
at eps steps of 0.02). In each movie frame the particles' heights give the count C(y) of
particles above y. On the reference lattice C is known at the mid-height of every unit-cell row,
(rows - j - 1/2) particles-per-row at y = (j + 1/2) L, and stays so where the material has not
moved (to the elastic precursor's 0.01-0.05 of a row). The deficit D = (C - C_ref) /
particles-per-row counts, in unit-cell rows, how far the material above y has come down, and
D_{j-2} - D_j how much the two rows below y_j have shortened. The band's edge is where that
shortening, read from the plate down, falls below a level (front_height: 1/4 of a row, a
shortening of the two rows by 1/8, and 1/2, by 1/4, as a second reading); rows collapsing
further down are compaction ahead of the band. Over the first leg (the edge 2 L below the
plate's start, until it is within 2 L of the bottom plate, is lost, or compaction begins ahead
of it) a straight line through the edge's heights gives c_b/V = -(dy_f / d eps) / h0, with its
standard error. The compacted zone is what lies between L above the edge and L below the plate;
its solid fraction phi_f is phi_discrete times its particles over those of the same height of
reference lattice, averaged over the leg's frames. Where a band compacts its zone to phi_f in
one step and the material ahead is at rest, mass conservation gives c_b/V = 1/(1 - phi/phi_f): a
band that leaves its zone denser runs slower, and both levels read the same edge speed.
"""
import argparse
import bisect
import math
import os
import statistics
import sys

from studies.lib import runs
from studies.lib.cells import fmt
from studies.lib.movie import Movie
from studies.lib.spread import line_fit

# A window of two rows is compacting from a quarter row of shortening on (1/8 of its length:
# the "1/8 level"); the band's edge is read at this level and at twice it (the "1/4 level"). A
# band that compacts the material in one step gives both the same speed; where rows yield ahead
# of the band and compact part-way before it arrives, the lower level reads the faster, earlier
# edge.
COMPACTING = (0.25, 0.5)
GAP = 2          # quiet windows a band may hold between compacting ones
EDGE_ROWS = 2    # the first leg: the edge 2 L from either plate's start
ZONE_MARGIN = 1  # the zone: 1 L clear of the edge and of the plate


def deficit(y_sorted, n, rows, h0):
    """The sample heights y_j = (j + 1/2) L, j = 0 .. rows - 1, and D_j there:
    (C(y_j) - C_ref(y_j)) / particles per row, from the particles' heights in rising order."""
    per_row, L = n / rows, h0 / rows
    yj = [(j + 0.5) * L for j in range(rows)]
    d = [(n - bisect.bisect_right(y_sorted, yj[j]) - per_row * (rows - j - 0.5)) / per_row
         for j in range(rows)]
    return yj, d


def front_height(yj, d, y_from, y_top, level=COMPACTING[0]):
    """The lower edge of the band whose previous edge was at y_from (the plate, y_top, at the
    first frame), and where compaction has begun ahead of it.

    A window of two unit cells [y_{j-2}, y_j] is compacting when the material at its top has
    come down by `level` rows or more relative to that at its bottom (D_{j-2} - D_j >= level;
    1/4: shortened by 1/8 of its length). Reading downwards from 2 L above y_from (at most
    the plate), the band is the first compacting window above y_from - 2 L and those that follow
    it with gaps of at most two quiet windows (a row that has not collapsed yet between two that
    have); quiet windows before it are material carried along with the plate. The edge is where
    the band's last compacting window meets the next quiet one (linear in D_{j-2} - D_j),
    reported at the window's centre; 0, the bottom plate, when the band reaches it. Compacting
    windows further down are compaction ahead of the band (rows collapsing on their own, or a
    band from the bottom plate). Returns (edge, ahead): ahead is the centre of the highest such
    window, None when there is none; or None when no band starts there."""
    L = yj[1] - yj[0]
    rise = [math.nan] * 2 + [d[j - 2] - d[j] for j in range(2, len(d))]  # across [y_{j-2}, y_j]
    start = min(y_from + 2 * L, y_top)
    scan = [j for j in range(len(yj) - 1, 1, -1) if yj[j] < start]
    compacting = [rise[j] >= level for j in scan]
    first = next((k for k, c in enumerate(compacting) if c), None)
    if first is None or yj[scan[first]] < y_from - 2 * L:
        return None
    last = first
    for k in range(first + 1, len(scan)):
        if compacting[k]:
            if k - last - 1 > GAP:
                return edge_at(yj, rise, scan, last, level), yj[scan[k]] - L
            last = k
    if last == len(scan) - 1:
        return 0.0, None
    return edge_at(yj, rise, scan, last, level), None


def edge_at(yj, rise, scan, last, level):
    """Where the compacting window scan[last] gives way to the quiet one below it."""
    j_in, j_out = scan[last], scan[last + 1]
    t = (rise[j_in] - level) / (rise[j_in] - rise[j_out])
    return yj[j_in] + t * (yj[j_out] - yj[j_in]) - (yj[1] - yj[0])


def zone_fraction(y_sorted, n, rows, h0, phi, lo, hi):
    """The solid fraction of the slab lo < y < hi: phi times its particles over a reference
    lattice's in the same height."""
    inside = bisect.bisect_left(y_sorted, hi) - bisect.bisect_right(y_sorted, lo)
    return phi * inside / (n / rows * (hi - lo) / (h0 / rows))


def leg_fit(points):
    """c_b/V of an edge moving down through (eps, height / h0) points, minus their least-squares
    slope, and its standard error; (None, None) with fewer than three points."""
    if len(points) < 3:
        return None, None
    slope, err = line_fit([e for e, _ in points], [y for _, y in points])
    return -slope, err


def first_leg(frames, n, rows, h0, phi, level=COMPACTING[0]):
    """The first leg over frames (eps, particle heights), in order of strain, with the edge read
    at `level`: c_b/V from the edge's heights with the fit's standard error, over the whole leg
    and over its frames in the column's upper half (the early stage, before a band that changes
    speed on its way has done so); the compacted zone's phi_f (mean and standard deviation over
    the leg's frames); the leg's strain range, frame count and what ended it (with the height
    of the compaction ahead of the band, where that ended it). None values where the movie has
    no leg of three frames."""
    L = h0 / rows
    eps_leg, y_leg, zones = [], [], []
    previous, end, ahead_at = None, "the movie's end", None
    for eps, y in frames:
        y = sorted(y)
        y_top = h0 * (1 - eps)
        yj, d = deficit(y, n, rows, h0)
        edge = front_height(yj, d, y_top if previous is None else previous, y_top, level)
        if edge is None:
            if eps_leg:
                end = "the band lost"
                break
            continue
        yf, ahead = edge
        previous = yf
        if yf > h0 - EDGE_ROWS * L:
            continue  # still forming
        if ahead is not None:
            end, ahead_at = "compaction ahead of the band, at %.2f h0" % (ahead / h0), ahead
            break
        if yf < EDGE_ROWS * L:
            end = "the bottom plate"
            break
        eps_leg.append(eps)
        y_leg.append(yf)
        lo, hi = yf + ZONE_MARGIN * L, y_top - ZONE_MARGIN * L
        if hi - lo >= L:
            zones.append(zone_fraction(y, n, rows, h0, phi, lo, hi))
    path = list(zip(eps_leg, y_leg))
    speed, speed_err = leg_fit([(e, yf / h0) for e, yf in path])
    upper, upper_err = leg_fit([(e, yf / h0) for e, yf in path if yf >= h0 / 2])
    return {"speed": speed, "speed_err": speed_err, "upper": upper, "upper_err": upper_err,
            "phi_f": statistics.fmean(zones) if zones else None,
            "phi_f_sd": statistics.stdev(zones) if len(zones) > 1 else None,
            "eps": (eps_leg[0], eps_leg[-1]) if eps_leg else None, "frames": len(eps_leg),
            "end": end, "ahead_at": ahead_at, "path": path}


def read_bundle(out, classify_bin):
    """A bundle's first leg from its movie, with the classifier's reading of it."""
    s = runs.summary(out)
    p = s["params"]
    if p.get("geometry") != "pseudo1d":
        raise ValueError("%s: %s geometry; the deficit counts unit-cell rows of a pseudo-1D column"
                         % (out, p.get("geometry")))
    m = Movie(out)
    frames = [m.heights(k) for k in range(m.n_frames)]
    legs = [first_leg(frames, m.n, p["n_rows"], m.y_hi - m.y_lo, s["phi_discrete"], level)
            for level in COMPACTING]
    return {"run": os.path.basename(os.path.normpath(out)), "params": p, "legs": legs,
            "phi": s["phi_discrete"], "grid": s["grid"],
            "classifier": runs.reading(out, classify_bin)}


def speed_cell(v, err):
    """A speed and its standard error as a table cell ("-": none)."""
    return "-" if v is None else "%s +- %s" % (fmt(v), fmt(err, 2))


def leg_cells(leg):
    """A leg's speed over the whole leg and over its upper half, and its strain range, frames
    and end, as three table cells."""
    span = ("-" if leg["eps"] is None else
            "%.2f-%.2f (%d), %s" % (leg["eps"] + (leg["frames"], leg["end"])))
    return [speed_cell(leg["speed"], leg["speed_err"]), speed_cell(leg["upper"], leg["upper_err"]),
            span]


def plot(results, png):
    """The edges' paths and the speeds against R/S^2 into `png`, a colour per resolution and
    perturbation; False without matplotlib."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import matplotlib.ticker
    except ImportError:
        return False
    os.makedirs(os.path.dirname(os.path.abspath(png)), exist_ok=True)
    groups = sorted({(round(r["grid"]["cells_per_strut"], 2), r["params"]["perturbation"])
                     for r in results})
    colour = {g: "C%d" % i for i, g in enumerate(groups)}
    fig, ax = plt.subplots(1, 2, figsize=(8, 3.2))
    for r in results:
        p = r["params"]
        g = (round(r["grid"]["cells_per_strut"], 2), p["perturbation"])
        x, c = p["R"] / p["S"] ** 2, colour[g]
        leg = r["legs"][1] if r["legs"][1]["upper"] is not None else r["legs"][0]
        if leg["path"]:
            ax[0].plot([e for e, _ in leg["path"]], [y for _, y in leg["path"]], "-", c=c, lw=0.8)
        if leg["upper"] is not None:
            ax[1].errorbar([x], [leg["upper"]], yerr=[leg["upper_err"]], c=c, ms=4,
                           fmt="o" if leg is r["legs"][1] else "^")
        if r["classifier"]["fit"] is not None:
            ax[1].plot([x], [r["classifier"]["fit"]], "o", mfc="white", mec=c, ms=4)
        if r["classifier"]["lead"] is not None:
            ax[1].errorbar([x], [r["classifier"]["lead"]], yerr=[r["classifier"]["lead_err"]],
                           fmt="D", mfc="white", mec=c, c=c, ms=4)
    for g in groups:
        ax[0].plot([], [], "-", c=colour[g], label="%g cells, perturbation %g" % g)
    ax[0].set_xlabel("eps"); ax[0].set_ylabel("edge height / h0")
    ax[0].legend(fontsize=6)
    ax[1].axhline(1 / (1 - results[0]["phi"]), ls="--", c="gray", lw=0.8)
    ax[1].set_xscale("log"); ax[1].set_yscale("log")
    ax[1].yaxis.set_major_formatter(matplotlib.ticker.ScalarFormatter())
    ax[1].yaxis.set_minor_formatter(matplotlib.ticker.ScalarFormatter())
    ax[1].set_xlabel("q_y/(rho V^2)"); ax[1].set_ylabel("c_b/V")
    fig.tight_layout()
    fig.savefig(png, dpi=90)
    plt.close(fig)
    return True


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("bundles", nargs="+",
                    help="run bundles (folders with summary.json and movie.bin)")
    ap.add_argument("--bin", default=os.path.join(runs.ROOT, "build", "bin"),
                    help="folder of the compaction-classify that reads the bands [build/bin]")
    ap.add_argument("--out", help="write the report here as well as to stdout, and its plot beside "
                                   "it (.png, where matplotlib is installed)")
    a = ap.parse_args()
    classify_bin = os.path.join(a.bin, "compaction-classify")
    if not os.access(classify_bin, os.X_OK):
        ap.error("--bin: %s is not an executable" % classify_bin)
    results = []
    for out in a.bundles:
        if not runs.finished(out) or not os.path.exists(os.path.join(out, "movie.bin")):
            ap.error("%s: not a finished bundle with a movie.bin" % out)
        try:
            results.append(read_bundle(out, classify_bin))
        except ValueError as e:
            ap.error(str(e))

    lines = [
        "# The first band read from the particles", "",
        "Made by `python3 -m studies.validation.compacted_zone %s`. The band's edge: where the material, "
        "read "
        "from the plate down, stops compacting, a window of two unit cells counting as compacting "
        "once it has shortened by 1/8 (and, second reading, by 1/4). c_b/V: a straight "
        "line through the edge's heights over the first leg (the movie's frames, every 0.02 of "
        "strain, from the edge 2 L below the plate's start until it is within 2 L of the bottom "
        "plate, the band is lost, or compaction begins ahead of it), +- the fit's standard error; "
        "upper half: the same over the leg's frames whose edge is in the column's upper half. "
        "phi_f: the solid fraction between L above the 1/8 edge and L below the plate, mean +- sd "
        "over that leg's frames; mass balance of a band that leaves its zone at phi_f: "
        "1/(1 - phi/phi_f). Classifier readings (fit, transit; and in the velocity map over the "
        "band's early stage, its first leg in the column's upper half: its middle, where the "
        "rows move at half the plate speed, and its leading edge, the 10 %% point of the step from "
        "the material ahead to the plate speed, each +- its fit's standard error) as in "
        "docs/classifier.md. Method: the script's docstring." % " ".join(sys.argv[1:]), "",
        "| run | R/S^2 | cells across a strut | perturbation | label | c_b/V fit | c_b/V transit | "
        "velocity map, early: middle | leading edge | "
        "c_b/V edge 1/8 | upper half | its leg: eps (frames), ended by | c_b/V edge 1/4 | "
        "upper half | its leg | phi_f | 1/(1 - phi/phi_f) |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        c, p, leg = r["classifier"], r["params"], r["legs"][0]
        mass = (1 / (1 - r["phi"] / leg["phi_f"]) if leg["phi_f"] and leg["phi_f"] > r["phi"]
                else None)
        lines.append("| " + " | ".join(
            [r["run"], "%.3g" % (p["R"] / p["S"] ** 2), "%.2f" % r["grid"]["cells_per_strut"],
             "%g" % p["perturbation"], "%s (%s)" % (c["label"], fmt(c["confidence"], 2)),
             fmt(c["fit"]), fmt(c["transit"]), speed_cell(c["early"], c["early_err"]),
             speed_cell(c["lead"], c["lead_err"])] + leg_cells(leg) + leg_cells(r["legs"][1]) +
            ["-" if leg["phi_f"] is None else
             "%.3f +- %s" % (leg["phi_f"], fmt(leg["phi_f_sd"], 2)),
             fmt(mass)]) + " |")
    lines.append("")
    if a.out and plot(results, os.path.splitext(a.out)[0] + ".png"):
        lines += ["![The first band's edge](%s)" % (os.path.splitext(os.path.basename(a.out))[0]
                                                   + ".png"), "",
                  "Left: the edge (1/4 level; 1/8 where a run has no 1/4 edge) over each run's "
                  "first leg; right: c_b/V against R/S^2, the edge's speed over the leg's upper "
                  "half (filled circles; triangles: the 1/8 edge), the classifier's fit "
                  "(hollow circles) and the leading edge in the velocity map over the early "
                  "stage (hollow diamonds). Colours: resolution (cells across a strut) and "
                  "perturbation. Dashed: 1/(1 - phi_discrete).", ""]
    if a.out:
        runs.write_report(a.out, lines)
    else:
        print("\n".join(lines))


if __name__ == "__main__":
    main()
