#!/usr/bin/env bash
# Runs the constitutive-update benchmark (5 repetitions, medians) on one core and writes
# bench/results/return_map_bench.json and bench/results/return_map_bench.md (ns per call and the
# ratios between variants, one run).
# usage: bench/run_return_map_bench.sh [build-dir]   (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build}"
cmake --build "$build" --target return_map_bench >/dev/null
mkdir -p bench/results
"$build/bin/return_map_bench" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
  --benchmark_out=bench/results/return_map_bench.json --benchmark_out_format=json
/usr/bin/env python3 bench/summarize_return_map_bench.py bench/results/return_map_bench.json \
  > bench/results/return_map_bench.md
cat bench/results/return_map_bench.md
