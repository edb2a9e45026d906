"""Contact across closing pores: one grid velocity field against two (pore_contact).

The non-reflecting band of example (a) (S = 4e-3, R = 1e-5, phi = 0.4, pseudo-1D) to eps = 0.2
with a snapshot at 0.18, at each resolution and pore_contact setting. For each run: the band
speed c_b/V (the front, the lowest row at 20 % of the frame's peak rate, fitted over
eps >= 0.05; and the classifier's two readings), its excess over 1/(1 - phi_discrete) (full
compaction of the discretised structure), the solid fraction phi_f of the compacted zone at the
snapshot (the particles' areas J V0 from one unit cell behind the front to one below the plate,
over the zone's area: 1 when its pores are closed, above 1 when particles overlap), the range
of J there, and the cost (wall time, ns per particle-step, one thread). A setting that
validate() refuses at a resolution is listed with its reason.

  python3 -m studies.pore_contact.pore_contact --cells 12,16,20 --jobs 1 --bin build/bin
"""
import argparse
import os
import shutil

import numpy as np

from studies.lib import runs

SETTINGS = ("single_field", "split_fields")
SCENE = {"S": 4e-3, "R": 1e-5, "phi": 0.4, "eps_end": 0.2, "snapshot_eps": 0.18,
         "movie_d_eps": 0}
FIT_FROM = 0.05  # the band's start (first unit cells) is left out of the fit, as in docs/engine.md


def front_speed(out, s):
    """c_b/V from spacetime.npy: -(d front / h0) / d eps over eps >= FIT_FROM; front per frame."""
    m = np.load(os.path.join(out, "spacetime.npy"))
    eps = np.array(runs.frames(out)["eps"])
    fronts = []
    for row in m:
        peak = row.max()
        lowest = np.argmax(row >= 0.2 * peak) if peak > 0 else len(row) - 1
        fronts.append((lowest + 0.5) / m.shape[1])
    fronts = np.array(fronts)
    keep = eps >= FIT_FROM
    return -np.polyfit(eps[keep], fronts[keep], 1)[0], eps, fronts


def compacted_zone(out, s, eps, fronts):
    """phi_f and the J range of the zone between the front and the plate at the snapshot."""
    snap = s["snapshots"][0]
    t = np.load(os.path.join(out, snap["file"]))
    x, y, jac = t[:, 0], t[:, 1], t[:, 4]
    p = s["params"]
    h0, L = p["h0"], s["derived"]["unit_cell"]
    width = L  # pseudo-1D: one unit cell
    frame = int(np.argmin(np.abs(eps - snap["eps"])))
    lo, hi = fronts[frame] * h0 + L, h0 * (1 - snap["eps"]) - L
    if hi - lo < 2 * L:
        return None, None, None
    v0 = (s["grid"]["dx"] / p["particles_per_cell"]) ** 2
    zone = (y >= lo) & (y < hi)
    return float(jac[zone].sum() * v0 / ((hi - lo) * width)), float(jac[zone].min()), float(jac[zone].max())


def fmt(v, digits=3):
    return "-" if v is None else "%.*g" % (digits, v)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cells", default="12,16,20", help="cells per unit cell, comma list")
    ap.add_argument("--settings", default=",".join(SETTINGS))
    ap.add_argument("--work", default=os.path.join(runs.ROOT, "out", "pore-contact"))
    ap.add_argument("--bin", default=os.path.join(runs.ROOT, "build", "bin"))
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--out", default=os.path.join(runs.ROOT, "studies", "pore_contact", "results", "pore-contact.md"))
    a = ap.parse_args()
    run_bin = os.path.join(a.bin, "compaction-run")
    cells = [int(c) for c in a.cells.split(",")]
    settings = [x for x in a.settings.split(",") if x]
    for x in settings:
        if x not in SETTINGS:
            ap.error("--settings: unknown %r; choose from %s" % (x, ", ".join(SETTINGS)))
    scenes, reasons = {}, {}
    for c in cells:
        for x in settings:
            flags = dict(SCENE, cells_per_unit=c, pore_contact=x)
            why = runs.refused(flags, run_bin)
            if why:
                reasons[(c, x)] = why
            else:
                scenes["a-c%d-%s" % (c, x)] = flags
    dirs = runs.run_all(a.work, scenes, jobs=a.jobs, run=run_bin)
    classify_bin = os.path.join(a.bin, "compaction-classify")

    lines = ["# Contact across closing pores: one velocity field against two", "",
             "Made by `python3 -m studies.pore_contact.pore_contact --cells %s --settings %s --jobs %d`, engine %s."
             % (a.cells, ",".join(settings), a.jobs, "?"), "",
             "Example (a), S = 4e-3, R = 1e-5, phi = 0.4, pseudo-1D, to eps = 0.2, one thread each "
             "(%d runs at a time). " % a.jobs +
             "c_b/V: the front fitted over eps >= %g, and the classifier's fit and transit "
             "readings; excess against 1/(1 - phi_discrete); phi_f: the particles' areas J V0 "
             "over the compacted zone's area at eps = 0.18, from a unit cell behind the front to one "
             "below the plate (1: pores closed; above 1: particles overlap)."
             % FIT_FROM, "",
             "| cells per unit | cells across the strut | pore_contact | c_b/V (front fit) | excess "
             "| classifier fit, transit | label | phi_f | J min, max | particles | wall s "
             "| ns / particle-step |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    version = None
    for c in cells:
        for x in settings:
            if (c, x) in reasons:
                lines.append("| %d | - | %s | refused: %s |  |  |  |  |  |  |  |  |" % (c, x, reasons[(c, x)]))
                continue
            out = dirs["a-c%d-%s" % (c, x)]
            s = runs.summary(out)
            version = s["engine_version"]
            cb, eps, fronts = front_speed(out, s)
            bound = 1 / (1 - s["phi_discrete"])
            phi_f, jmin, jmax = compacted_zone(out, s, eps, fronts)
            cl = runs.classify(out, classify_bin)
            f = cl.get("features", {})
            lines.append("| %d | %.2f | %s | %.3f | %+.1f %% | %s, %s | %s | %s | %s, %s | %d | %.0f | %.1f |" % (
                c, s["grid"]["cells_per_strut"], x, cb, 100 * (cb / bound - 1),
                fmt(f.get("band_speed_ratio")), fmt(f.get("band_speed_transit")),
                cl.get("class") or "-", fmt(phi_f), fmt(jmin, 5), fmt(jmax, 5), s["n_particles"],
                s["wall_seconds"], s["ns_per_particle_step"]))
            print(lines[-1], flush=True)
    lines[2] = lines[2].replace("engine ?", "engine %s" % (version or "?"))
    lines += ["", "Wall times and ns per particle-step are those of the runs, %d at a time, and of "
              "whatever else the machine ran then: read the cost of each setting in "
              "bench/results/engine_bench.md, measured in one run." % a.jobs]
    # The snapshots beside the table: the compacted zone's remaining pores, as a reader sees them.
    images = os.path.splitext(a.out)[0]
    os.makedirs(images, exist_ok=True)
    for name, out in sorted(dirs.items()):
        snap = runs.summary(out)["snapshots"][0]["image"]
        shutil.copyfile(os.path.join(out, snap), os.path.join(images, name + ".png"))
    lines += ["", "Snapshots at eps = 0.18 (plastic strain rate, the compacted zone above the "
              "front): %s/<run>.png, e.g. `a-c20-single_field.png` and `a-c20-split_fields.png`."
              % os.path.relpath(images, os.path.dirname(os.path.abspath(a.out)))]
    runs.write_report(a.out, lines, echo=False)
    print("wrote", a.out)


if __name__ == "__main__":
    main()
