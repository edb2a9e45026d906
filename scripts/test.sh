#!/usr/bin/env bash
# Sets everything up and runs the whole test suite: the optimised build with every test (unit,
# physics, end-to-end with real server and workers, browser tests in headless Chromium, the
# fresh-machine check), then the ASan+UBSan build with the tests not labelled "slow".
#   COMPACTION_TEST_ORDINARY=1: the ordinary suite only: the optimised build with every test but
#   those labelled fresh (scripts/check-fresh-machine.sh, which sets this inside its clean Debian
#   12, so that it does not start itself again), container and slurm, and no sanitizer pass.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/install-browser-deps.sh        # Debian's chromium, node, playwright-core from npm
export COMPACTION_REQUIRE_BROWSER=1    # a missing browser fails the browser tests, never skips
scripts/install-promtool.sh            # promtool (Debian's prometheus) for metrics_test
export COMPACTION_REQUIRE_PROMTOOL=1
scripts/build.sh release
if [ "${COMPACTION_TEST_ORDINARY:-0}" = 1 ]; then
  ctest --preset release -j "$(nproc)" --label-exclude '^(fresh|container|slurm)$'
  echo "test.sh: COMPACTION_TEST_ORDINARY=1: no tests labelled fresh, container or slurm, no sanitizer pass"
  exit 0
fi
ctest --preset release -j "$(nproc)"
scripts/build.sh asan
ctest --preset asan -j "$(nproc)"
