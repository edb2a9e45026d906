#!/usr/bin/env bash
# Sets everything up and runs the whole test suite: the optimised build with every test, then
# the ASan+UBSan build with the tests not labelled "slow".
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh release
ctest --preset release -j "$(nproc)"
scripts/build.sh asan
ctest --preset asan -j "$(nproc)"
