#!/usr/bin/env python3
"""The full build's time with and without the precompiled headers that targets declare
(target_precompile_headers; bench/results/build_times.md names the ones measured), in one run:
for each variant, a clean build of a preset's configuration in a new folder (cmake -G Ninja, -j
of the cores), its wall time, and from ninja's log the CPU seconds of compiling (all files, and
the server's core and tests alone) and of linking. The ratio is without / with.

usage: bench/build/build_times.py [--preset release|asan] [--repeat N] [--out FILE]
  --preset   the configuration built (the flags of CMakePresets.json's preset; default release)
  --repeat   clean builds per variant, alternating; medians are printed (default 1: a build
             takes minutes)
  --out      also append the table, with the command and the load, to FILE (markdown)
Each variant is configured with -DCMAKE_DISABLE_PRECOMPILE_HEADERS=ON or OFF (CMake's own switch).
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def preset_cache(name):
    with open(os.path.join(ROOT, "CMakePresets.json")) as f:
        presets = {p["name"]: p for p in json.load(f)["configurePresets"]}
    if name not in presets:
        sys.exit("build_times.py: no configure preset '%s' (have: %s)" % (name, ", ".join(presets)))
    return presets[name].get("cacheVariables", {})


def ninja_seconds(build_dir):
    """CPU seconds from .ninja_log: compiling (all, the server's core and tests) and linking."""
    out = {"compile": 0.0, "server": 0.0, "link": 0.0}
    with open(os.path.join(build_dir, ".ninja_log")) as f:
        for line in f:
            if line.startswith("#"):
                continue
            start, end, _, target = line.split("\t")[:4]
            secs = (int(end) - int(start)) / 1000.0
            if target.endswith(".o") or target.endswith(".gch"):
                out["compile"] += secs
                if target.startswith("server/") or target.startswith("tests/server/"):
                    out["server"] += secs
            else:
                out["link"] += secs
    return out


def build(cache, pch, jobs):
    d = tempfile.mkdtemp(prefix="build-times-")
    try:
        args = ["cmake", "-S", ROOT, "-B", d, "-G", "Ninja",
                "-DCMAKE_DISABLE_PRECOMPILE_HEADERS=%s" % ("OFF" if pch else "ON")]
        args += ["-D%s=%s" % kv for kv in cache.items()]
        subprocess.run(args, check=True, stdout=subprocess.DEVNULL)
        t0 = time.monotonic()
        subprocess.run(["cmake", "--build", d, "-j", str(jobs)], check=True,
                       stdout=subprocess.DEVNULL)
        wall = time.monotonic() - t0
        r = ninja_seconds(d)
        r["wall"] = wall
        return r
    finally:
        shutil.rmtree(d, ignore_errors=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--preset", default="release")
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--out")
    a = ap.parse_args()
    if a.repeat < 1:
        ap.error("--repeat must be at least 1")
    cache = preset_cache(a.preset)
    jobs = os.cpu_count() or 1
    runs = {False: [], True: []}
    for i in range(a.repeat):
        for pch in (False, True):
            r = build(cache, pch, jobs)
            runs[pch].append(r)
            print("build %d, precompiled headers %s: wall %.0f s, compile %.0f CPU-s "
                  "(server %.0f), link %.0f CPU-s"
                  % (i + 1, "on" if pch else "off", r["wall"], r["compile"], r["server"],
                     r["link"]), flush=True)
    med = {pch: {k: statistics.median(r[k] for r in runs[pch]) for k in runs[pch][0]}
           for pch in runs}
    rows = [("wall time, s", "wall"), ("compile, CPU-s", "compile"),
            ("of which server core and its tests, CPU-s", "server"), ("link, CPU-s", "link")]
    lines = ["| preset %s, %d cores, median of %d | without | with | ratio |"
             % (a.preset, jobs, a.repeat), "|---|---|---|---|"]
    for label, k in rows:
        off, on = med[False][k], med[True][k]
        lines.append("| %s | %.0f | %.0f | %.2f |" % (label, off, on, off / on if on else 0))
    table = "\n".join(lines)
    print(table)
    if a.out:
        with open(a.out, "a") as f:
            f.write("\n`%s` (load average %.1f at the end, %s)\n\n%s\n"
                    % (" ".join(["bench/build/build_times.py"] + sys.argv[1:]),
                       os.getloadavg()[0], time.strftime("%Y-%m-%d"), table))


if __name__ == "__main__":
    main()
