#!/usr/bin/env python3
"""Turns Google Benchmark's JSON of return_map_bench into a Markdown table of ns per call."""
import json
import sys

data = json.load(open(sys.argv[1]))
ctx = data["context"]
rows = {}
for b in data["benchmarks"]:
    if b.get("aggregate_name") == "median":
        rows[b["run_name"].replace("BM_", "")] = b

print("# Constitutive update per call: 2D closed form, 3D return mapping, 3D eigen-solvers\n")
print("4 096 deformation gradients of a column compressed along y (strain 0-0.02 along y, shears "
      "up to 1e-3, rotations up to 0.1 rad; about half past yield), each update from the same "
      "trial state (bench/return_map_bench.cpp). Medians of 5 repetitions.\n")
print(f"Machine: {ctx.get('num_cpus')} CPUs at {ctx.get('mhz_per_cpu')} MHz, load "
      f"{', '.join('%.1f' % x for x in ctx.get('load_avg', []))}, date {ctx.get('date')}. Built "
      f"Release with the project's flags (x86-64 baseline, not the engine's AVX2 copy).\n")
print("Command: `bench/run_return_map_bench.sh`\n")
print("| variant | ns / call | yielded |")
print("|---|---|---|")
for name, b in rows.items():
    y = b.get("yielded_fraction")
    print(f"| {name} | {b['s_per_call'] * 1e9:.1f} | {'-' if y is None else '%.2f' % y} |")
ratios = [("ReturnMap3D", "ReturnMap2D"), ("ReturnMap3D_Principal", "ReturnMap3D"),
          ("ReturnMap3D_Principal", "ReturnMap2D"),
          ("EigenSolver3D_Compute", "EigenSolver3D_Jacobi"),
          ("EigenSolver3D_Jacobi", "EigenSolver3D_ComputeDirect")]
print("\nRatios (ns per call, same run):\n")
for a, b in ratios:
    if a in rows and b in rows:
        print(f"- {a} / {b}: {rows[a]['s_per_call'] / rows[b]['s_per_call']:.2f}")
