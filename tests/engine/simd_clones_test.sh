#!/usr/bin/env bash
# The engine's hot loops exist twice (engine/src/simd_clones.hpp): for the x86-64 baseline and
# for AVX2, picked at load time. Both must give the same result bits, so that a result does not
# depend on the processor a worker happens to run on. Runs the probe linked against the engine
# with the AVX2 copies and against the engine without them, and compares their hashes.
# usage: simd_clones_test.sh PROBE_WITH_CLONES PROBE_BASELINE_ONLY
set -euo pipefail
with=$("$1")
without=$("$2")
echo "$with"
if [[ "$with" != "$without" ]]; then
  echo "FAIL: the AVX2 and baseline copies of the hot loops give different bits" >&2
  diff <(echo "$without") <(echo "$with") >&2 || true
  exit 1
fi
if grep -q "avx2: no" <<<"$with"; then
  echo "this processor has no AVX2: both probes ran the baseline copy" >&2
  exit 77
fi
echo "same bits with and without the AVX2 copies"
