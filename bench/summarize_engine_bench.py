#!/usr/bin/env python3
"""Turns Google Benchmark's JSON of engine_bench into a Markdown table of medians and ratios."""
import json
import sys

data = json.load(open(sys.argv[1]))
ctx = data["context"]
rows = {}
for b in data["benchmarks"]:
    if b.get("aggregate_name") != "median":
        continue
    rows[b["run_name"].replace("BM_", "").replace("/iterations:1", "")] = b

print("# Engine benchmark: reference scene, large scene, 3D column\n")
print("Reference scene: pseudo-1D, phi = 0.4, 20 cells per unit cell, 2 x 2 particles per cell, "
      "S = 4e-3, R = 1e-5, eps 0 -> 0.008 (about 3200 steps). Large scene: the same column at 40 "
      "cells per unit cell (86 904 particles), eps 0 -> 0.002 (about 1600 steps). 3D column: "
      "geometry pseudo1d_3d at 8 cells per unit cell, 2 x 2 x 2 particles per cell (64 566 "
      "particles), eps 0 -> 0.002 (317 steps). Medians of 5 repetitions.\n")
print(f"Machine: {ctx.get('num_cpus')} CPUs at {ctx.get('mhz_per_cpu')} MHz, date {ctx.get('date')}. "
      f"Engine built Release (-O3, x86-64 baseline, with an AVX2 and an AVX-512 copy of the "
      f"particle loops, the widest that the processor has chosen at run time; all copies give "
      f"the same bits, engine/src/simd_dispatch.hpp); the Google Benchmark library itself is "
      f"Debian's "
      f"({ctx.get('library_build_type')} build), which only drives the timing loop.\n")
print("Command: `bench/run_engine_bench.sh`\n")
print("| variant | copy of the loops | ns / particle-step | P2G | grid update | G2P + plasticity | "
      "diagnostics | wall (ms) |")
print("|---|---|---|---|---|---|---|---|")
for name, b in rows.items():
    print(f"| {name} | {b.get('label', '-')} | {b['ns_per_particle_step']:.1f} | {b['p2g_ns']:.1f} | "
          f"{b['grid_ns']:.1f} | {b['g2p_ns']:.1f} | {b['diag_ns']:.1f} | {b['real_time']:.0f} |")
base = rows.get("ReferenceScene_Apic_1Thread")
if base:
    print("\nRatios to ReferenceScene_Apic_1Thread (ns / particle-step):\n")
    for name, b in rows.items():
        print(f"- {name}: {b['ns_per_particle_step'] / base['ns_per_particle_step']:.2f}")
pairs = [(n, n.replace("_1Thread", "_2Threads")) for n in rows if n.endswith("_1Thread")]
pairs = [(a, b) for a, b in pairs if b in rows]
if pairs:
    print("\nTwo threads against one, same run (ns / particle-step, one thread over two):\n")
    for a, b in pairs:
        ra, rb = rows[a], rows[b]
        speedup = ra["ns_per_particle_step"] / rb["ns_per_particle_step"]
        print(f"- {a.replace('_1Thread', '')}: {speedup:.2f} "
              f"(particles {ra['particles']:.0f}; P2G {ra['p2g_ns'] / rb['p2g_ns']:.2f}, "
              f"G2P {ra['g2p_ns'] / rb['g2p_ns']:.2f})")
