#!/usr/bin/env bash
# Sets everything up and runs the whole test suite: the optimised build with every test (unit,
# physics, end-to-end with real server and workers, browser tests in headless Chromium, the
# fresh-machine check), then the ASan+UBSan build with the tests not labelled "slow" or
# "resources" (the server's memory and latency bounds, which the sanitizer's own costs distort).
#   COMPACTION_TEST_QUICK=1: the optimised build with the tests not labelled "slow" (test preset
#   quick; the sanitizer pass's set is the same less "resources") and no sanitizer pass.
#   scripts/check-fresh-machine.sh sets it inside its clean Debian 12: what it proves there is the
#   install steps, a real build and the tests that use what was installed (the browser, promtool);
#   "slow" holds the fresh-machine check itself (no recursion), the container and slurm tests and
#   the long physics runs, which the host's pass runs.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/install-browser-deps.sh        # Debian's chromium, node, playwright-core from npm
export COMPACTION_REQUIRE_BROWSER=1    # a missing browser fails the browser tests, never skips
scripts/install-promtool.sh            # promtool (Debian's prometheus) for metrics_test
export COMPACTION_REQUIRE_PROMTOOL=1
scripts/build.sh release
if [ "${COMPACTION_TEST_QUICK:-0}" = 1 ]; then
  ctest --preset quick -j "$(nproc)"
  echo "test.sh: COMPACTION_TEST_QUICK=1: the tests not labelled slow, no sanitizer pass"
  exit 0
fi
ctest --preset release -j "$(nproc)"
scripts/build.sh asan
ctest --preset asan -j "$(nproc)"
