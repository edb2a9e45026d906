#!/usr/bin/env bash
# Sets everything up and runs the whole test suite: the optimised build with every test (unit,
# physics, end-to-end with real server and workers, browser tests in headless Chromium), then
# the ASan+UBSan build with the tests not labelled "slow".
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/install-browser-deps.sh        # Debian's chromium, node, playwright-core from npm
export COMPACTION_REQUIRE_BROWSER=1    # a missing browser fails the browser tests, never skips
scripts/build.sh release
ctest --preset release -j "$(nproc)"
scripts/build.sh asan
ctest --preset asan -j "$(nproc)"
