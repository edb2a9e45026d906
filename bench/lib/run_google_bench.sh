#!/usr/bin/env bash
# Runs one Google Benchmark program of bench/ (5 repetitions, medians) and writes
# bench/results/TARGET.json and bench/results/TARGET.md, the table bench/summarize_TARGET.py
# makes of it (medians and the ratios between variants, one run).
# usage: bench/lib/run_google_bench.sh TARGET [build-dir]   (default: build)
set -euo pipefail
cd "$(dirname "$0")/../.."
target="$1"
build="${2:-build}"
cmake --build "$build" --target "$target" >/dev/null
mkdir -p bench/results
"$build/bin/$target" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
  --benchmark_out="bench/results/$target.json" --benchmark_out_format=json
/usr/bin/env python3 "bench/summarize_$target.py" "bench/results/$target.json" \
  > "bench/results/$target.md"
cat "bench/results/$target.md"
