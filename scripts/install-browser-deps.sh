#!/usr/bin/env bash
# Installs what the browser tests and the dashboard benchmark need, and nothing else:
#   - Debian's chromium (/usr/bin/chromium) and node/npm, via apt-get, only when missing;
#   - tests/browser/node_modules from the committed package-lock.json: playwright-core (it drives
#     the system chromium and never downloads a browser of its own), and for openapi_test.mjs
#     Redocly's linter (@redocly/cli), ajv and js-yaml.
# Idempotent: a second run changes nothing. Needs root (or sudo) for apt-get.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"; elif command -v sudo >/dev/null; then sudo "$@"; else
    echo "install-browser-deps: need root for: $*" >&2; return 1; fi
}

missing=()
[ -x /usr/bin/chromium ] || missing+=(chromium)
command -v node >/dev/null || missing+=(nodejs)
command -v npm >/dev/null || missing+=(npm)
if [ ${#missing[@]} -gt 0 ]; then
  echo "install-browser-deps: apt-get install ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  as_root apt-get update -q
  as_root apt-get install -y -q --no-install-recommends "${missing[@]}" fonts-dejavu-core
fi

# playwright-core must not try to fetch browsers (it does not on install, but be explicit).
export PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1
cd "$repo/tests/browser"
# The version package-lock.json pins for a package, and the one installed ('' when none).
want() { node -p "require('./package-lock.json').packages['node_modules/$1'].version"; }
have() { node -p "try { require('./node_modules/$1/package.json').version } catch (e) { '' }"; }
stale=""
for package in playwright-core @redocly/cli ajv js-yaml; do
  [ "$(want "$package")" = "$(have "$package")" ] || stale="${stale:+$stale, }$package $(want "$package")"
done
if [ -n "$stale" ]; then
  echo "install-browser-deps: npm ci in tests/browser ($stale)"
  npm ci --no-audit --no-fund --loglevel=error
fi
echo "install-browser-deps: chromium $(/usr/bin/chromium --version 2>/dev/null | awk '{print $2}'), node $(node --version), playwright-core $(have playwright-core), @redocly/cli $(have @redocly/cli)"
