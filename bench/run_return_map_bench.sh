#!/usr/bin/env bash
# Runs the constitutive-update benchmark (5 repetitions, medians) on one core and writes
# bench/results/return_map_bench.json and bench/results/return_map_bench.md (ns per call and the
# ratios between variants, one run).
# usage: bench/run_return_map_bench.sh [build-dir]   (default: build)
exec "$(dirname "$0")/lib/run_google_bench.sh" return_map_bench "$@"
