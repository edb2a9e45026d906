#!/usr/bin/env bash
# Installs promtool, which tests/e2e/metrics_test.py checks /metrics with, and nothing else the
# server needs: Debian's prometheus package (about 100 MB; its daemon is not started by this
# script, and without systemd the package starts none). Idempotent; needs root or sudo.
set -euo pipefail
if command -v promtool >/dev/null; then
  exit 0
fi
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
echo "install-promtool: apt-get install prometheus (for promtool)"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends prometheus
promtool --version | head -1
