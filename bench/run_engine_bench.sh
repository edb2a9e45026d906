#!/usr/bin/env bash
# Runs the engine benchmark (5 repetitions, medians) and writes bench/results/engine_bench.json
# and bench/results/engine_bench.md (the medians and the ratios between variants, one run).
# usage: bench/run_engine_bench.sh [build-dir]   (default: build)
exec "$(dirname "$0")/lib/run_google_bench.sh" engine_bench "$@"
