#!/usr/bin/env bash
# Runs the engine benchmark (5 repetitions, medians) and writes bench/results/engine_bench.json
# and bench/results/engine_bench.md (the medians and the ratios between variants, one run).
# usage: bench/run_engine_bench.sh [build-dir]   (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build}"
cmake --build "$build" --target engine_bench >/dev/null
mkdir -p bench/results
"$build/bin/engine_bench" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
  --benchmark_out=bench/results/engine_bench.json --benchmark_out_format=json
/usr/bin/env python3 bench/summarize_engine_bench.py bench/results/engine_bench.json \
  > bench/results/engine_bench.md
cat bench/results/engine_bench.md
