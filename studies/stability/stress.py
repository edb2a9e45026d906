"""Numerical stability stress test of the engine.

Runs compaction-run over the corners and edges of the box S in [1e-4, 0.3], R in [1e-6, 0.3],
phi in [0.2, 0.8] at coarse resolution, plus pathological numerics (CFL near and past the
limit for each transfer scheme and gradient, one particle per cell, the thinnest struts the
grid allows), and the same for two velocity fields across closing pores (pore_contact =
split_fields) on the coarsest grid that takes them, and checks that every run ends "ok" or
"unstable" with a reason, within a time bound, with no NaN or Inf in any stored output. Every
scene gets --pore-contact (default auto, what the default preset asks for: two fields where 3
grid cells span the thinnest strut). Writes studies/stability/README.md.

usage: python3 -m studies.stability.stress [--run build/bin/compaction-run]
       [--work /tmp/stability] [--timeout 300] [--pore-contact auto]
       [--out studies/stability/README.md]
"""
import argparse
import itertools
import json
import math
import os
import pathlib
import shutil
import subprocess
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]


def box_points():
    """48 points on the corners and edges of the (S, R, phi) box, 10 cells per unit cell
    (the coarsest grid that resolves the struts at phi = 0.2), to a strain that keeps the
    slowest runs (S = 1e-4) to seconds."""
    points = []
    for S, R, phi in itertools.product([1e-4, 1e-3, 3e-2, 0.3], [1e-6, 1e-4, 1e-2, 0.3],
                                       [0.2, 0.5, 0.8]):
        eps_end = 0.01 if S < 1e-3 else 0.05
        points.append(dict(S=S, R=R, phi=phi, cells_per_unit=10, eps_end=eps_end))
    return points


def numerics_points():
    """Pathological numerics at a point that yields and moves fast (S = 0.03, R = 1e-4)."""
    base = dict(S=0.03, R=1e-4, phi=0.4, cells_per_unit=8, eps_end=0.05)
    points = []
    for transfer, gradient in [("apic", "mls"), ("pic_flip", "mls"), ("apic", "bspline")]:
        for cfl in [0.5, 0.8, 1.0, 1.2, 1.5, 1.9]:
            points.append(dict(base, cfl=cfl, transfer=transfer, gradient=gradient))
    points.append(dict(base, particles_per_cell=1))
    points.append(dict(base, particles_per_cell=1, cfl=1.0))
    points.append(dict(base, phi=0.2, cells_per_unit=10))  # struts of 1.06 cells
    points.append(dict(base, phi=0.8, cells_per_unit=3))   # holes of 1.3 cells
    points.append(dict(base, S=0.3, R=1e-6, perturbation=0.5))
    points.append(dict(base, contact="unilateral", S=0.3, R=1e-6))
    return points


SPLIT_CELLS = 14  # 3.1 cells across the strut at phi = 0.4: the coarsest grid two fields take


def split_points():
    """Two velocity fields under the pathological numerics of numerics_points: the CFL sweep
    of APIC with MLS (the only transfer they run with), perturbed particles (their face normals
    no longer on the lattice), unilateral plates, and a slow point that compacts."""
    base = dict(S=0.03, R=1e-4, phi=0.4, cells_per_unit=SPLIT_CELLS, eps_end=0.05,
                pore_contact="split_fields")
    points = [dict(base, cfl=cfl, transfer="apic", gradient="mls")
              for cfl in [0.5, 0.8, 1.0, 1.2, 1.5, 1.9]]
    points.append(dict(base, particles_per_cell=1))
    points.append(dict(base, phi=0.8, cells_per_unit=6))  # 3.3 cells across the strut
    points.append(dict(base, S=0.3, R=1e-6, perturbation=0.5))
    points.append(dict(base, contact="unilateral", S=0.3, R=1e-6))
    points.append(dict(base, S=1e-3, R=1e-6, eps_end=0.1))  # pores close at the band
    return points


def numbers(value):
    """Every number in a parsed JSON value (json.loads reads NaN and Infinity as floats)."""
    if isinstance(value, dict):
        for v in value.values():
            yield from numbers(v)
    elif isinstance(value, list):
        for v in value:
            yield from numbers(v)
    elif isinstance(value, (int, float)) and not isinstance(value, bool):
        yield value


def finite_outputs(out):
    """True when no stored number is NaN or Inf: frames.csv, the .npy arrays, summary.json."""
    rows = (out / "frames.csv").read_text().splitlines()[1:]  # a run may stop before frame 1
    if rows and not np.isfinite(np.array([[float(v) for v in r.split(",")] for r in rows])).all():
        return False
    for npy in out.glob("*.npy"):
        if not np.isfinite(np.load(npy)).all():
            return False
    summary = json.loads((out / "summary.json").read_text())
    return all(math.isfinite(v) for v in numbers(summary))


def run_point(run, work, index, scene, timeout):
    out = work / f"p{index:03d}"
    shutil.rmtree(out, ignore_errors=True)
    scene_file = work / f"p{index:03d}.json"
    scene_file.write_text(json.dumps(dict(scene, snapshot_eps=[])))
    t0 = time.monotonic()
    try:
        proc = subprocess.run([run, "--scene", str(scene_file), "--out", str(out),
                               "--progress", "none"], capture_output=True, text=True,
                              timeout=timeout)
        rc = proc.returncode
        err = proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else ""
    except subprocess.TimeoutExpired:
        rc, err = "timeout", f"no end within {timeout} s"
    wall = time.monotonic() - t0
    row = dict(scene=scene, rc=rc, wall=wall, status="", reason="", eps=float("nan"),
               finite=None, error="", contact="")
    if rc == 0:
        summary = json.loads((out / "summary.json").read_text())
        row.update(status=summary["status"], reason=summary["reason"],
                   eps=summary["eps_reached"], finite=finite_outputs(out),
                   contact=summary["grid"]["pore_contact"])
    elif rc == 2:
        row.update(status="rejected", error=err)  # invalid input: a clear error, nothing run
    else:
        row.update(status="FAILED", error=err)
    return row


def verdict(row):
    if row["status"] == "rejected":
        return "rejected (invalid input)"
    good = row["status"] in ("ok", "unstable") and row["finite"] and \
        (row["status"] == "ok" or row["reason"])
    return "pass" if good else "**FAIL**"


def fmt_scene(s, keys):
    return ", ".join(f"{k} {s[k]:g}" if isinstance(s[k], float) else f"{k} {s[k]}"
                     for k in keys if k in s)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--run", default=str(ROOT / "build/bin/compaction-run"))
    ap.add_argument("--work", default="/tmp/stability")
    ap.add_argument("--timeout", type=float, default=300)
    ap.add_argument("--pore-contact", default="auto", choices=("single_field", "split_fields", "auto"),
                    help="pore_contact of every scene that does not set its own [auto]")
    ap.add_argument("--out", default=str(ROOT / "studies/stability/README.md"))
    args = ap.parse_args()
    work = pathlib.Path(args.work)
    work.mkdir(parents=True, exist_ok=True)

    groups = [("Corners and edges of the (S, R, phi) box", box_points(),
               ["S", "R", "phi", "eps_end"]),
              ("Pathological numerics (S = 0.03, R = 1e-4, phi = 0.4, 8 cells per unit)",
               numerics_points(),
               ["transfer", "gradient", "cfl", "particles_per_cell", "phi", "cells_per_unit",
                "S", "R", "perturbation", "contact"]),
              (f"Two velocity fields (pore_contact = split_fields; S = 0.03, R = 1e-4, phi = 0.4, "
               f"{SPLIT_CELLS} cells per unit)", split_points(),
               ["cfl", "particles_per_cell", "phi", "cells_per_unit", "S", "R", "eps_end",
                "perturbation", "contact"])]
    rows_by_group, index, failures = [], 0, 0
    for title, points, keys in groups:
        rows = []
        for scene in points:
            scene = dict({"pore_contact": args.pore_contact}, **scene)
            row = run_point(args.run, work, index, scene, args.timeout)
            index += 1
            failures += verdict(row) == "**FAIL**"
            print(f"[{index}] {fmt_scene(scene, keys)}: {row['status']} {row['reason'] or row['error']}"
                  f" ({row['wall']:.1f} s)", flush=True)
            rows.append(row)
        rows_by_group.append((title, rows, keys))

    total = sum(len(r) for _, r, _ in rows_by_group)
    lines = ["# Numerical stability stress test", "",
             f"Made by `python3 -m studies.stability.stress --pore-contact {args.pore_contact}` ({total} runs, "
             f"{failures} failures). Every run "
             "must end `ok` or `unstable` with a reason (or be rejected as invalid input with a "
             f"clear error), within {args.timeout:g} s, with no NaN or Inf in frames.csv, the .npy "
             "arrays or summary.json. Pseudo-1D, bonded plates, APIC and MLS unless stated; "
             f"`pore_contact = {args.pore_contact}` unless stated (`auto`: two velocity fields where "
             "3 grid cells span the thinnest strut, what the default preset asks for; the run's "
             "summary.json says which it used, in the column `contact`).", ""]
    for title, rows, keys in rows_by_group:
        lines += [f"## {title}", "",
                  "| run | contact | status | reason | eps reached | wall [s] | verdict |",
                  "|---|---|---|---|---|---|---|"]
        for row in rows:
            eps = "" if math.isnan(row["eps"]) else f"{row['eps']:.4g}"
            reason = (row["reason"] or row["error"]).replace("|", "/")
            lines.append(f"| {fmt_scene(row['scene'], keys)} | {row['contact']} | {row['status']} | "
                         f"{reason} | {eps} | {row['wall']:.1f} | {verdict(row)} |")
        lines.append("")
    # Stable CFL per transfer scheme and gradient: the largest CFL that ended ok.
    lines += ["## Largest stable CFL (S = 0.03, R = 1e-4, phi = 0.4, 8 cells per unit, to eps = 0.05)", "",
              "| transfer | gradient | ok up to CFL | first unstable CFL |", "|---|---|---|---|"]
    numerics, split = rows_by_group[1][1], rows_by_group[2][1]
    for transfer, gradient, rows in [("apic", "mls", numerics), ("pic_flip", "mls", numerics),
                                     ("apic", "bspline", numerics),
                                     ("apic", f"mls, two fields at {SPLIT_CELLS} cells", split)]:
        cfls = [(r["scene"]["cfl"], r["status"]) for r in rows if "cfl" in r["scene"] and
                r["scene"].get("transfer") == transfer and gradient.startswith(r["scene"].get("gradient"))]
        ok = [c for c, st in cfls if st == "ok"]
        bad = [c for c, st in cfls if st == "unstable"]
        lines.append(f"| {transfer} | {gradient} | {max(ok) if ok else '-'} | "
                     f"{min(bad) if bad else 'none up to 1.9'} |")
    pathlib.Path(args.out).write_text("\n".join(lines) + "\n")
    print(f"{total} runs, {failures} failures; wrote {args.out}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
