#!/usr/bin/env bash
# Runs one browser test file with node's test runner. Without chromium or playwright-core it
# skips (exit 77, ctest's SKIP_RETURN_CODE) and says how to install them, unless
# COMPACTION_REQUIRE_BROWSER=1, where a missing dependency fails the test.
#   NEEDS_BROWSER=0: the test drives no browser (chromium and playwright-core are not needed);
#   NEEDS_MODULES="a b": packages of tests/browser/node_modules the test needs besides.
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"
missing=""
if [ "${NEEDS_BROWSER:-1}" = 1 ]; then
  [ -x "${CHROMIUM:-/usr/bin/chromium}" ] || missing="chromium (${CHROMIUM:-/usr/bin/chromium})"
  [ -f node_modules/playwright-core/package.json ] || missing="${missing:+$missing, }tests/browser/node_modules/playwright-core"
fi
for module in ${NEEDS_MODULES:-}; do
  [ -f "node_modules/$module/package.json" ] || missing="${missing:+$missing, }tests/browser/node_modules/$module"
done
if [ -n "$missing" ]; then
  echo "missing: $missing; run scripts/install-browser-deps.sh"
  [ "${COMPACTION_REQUIRE_BROWSER:-0}" = 1 ] && exit 1
  exit 77
fi
exec node --test --test-reporter=spec "$@"
