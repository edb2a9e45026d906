#!/usr/bin/env bash
# Installs the Debian packages compaction-sweep builds and runs with (idempotent; needs root or sudo).
# usage: scripts/install-deps.sh [--bench]
#   --bench  also matplotlib, which the study scripts under studies/ (validation, accuracy,
#            stability) use with numpy for their plots
set -euo pipefail
packages=(
  cmake ninja-build g++ git pkg-config
  libsqlite3-dev sqlite3 nlohmann-json3-dev libcpp-httplib-dev libspdlog-dev
  libgtest-dev libgmock-dev libbenchmark-dev zlib1g-dev libcli11-dev
  libcairo2-dev fonts-dejavu-core  # spacetime.png's axes and text
  libvalijson-dev  # header-only: the server checks uploaded summaries against schema/summary.schema.json
  libeigen3-dev  # header-only: the 3D column's linear algebra, and the tests' independent oracles
  python3 curl
  # the Python client (docs/python.md), installed without the Python package index: a venv that
  # sees Debian's packages (python3-venv brings pip and setuptools), the `wheel` module it builds
  # the package with (python3-wheel; python3-wheel-whl for a venv that does not see them), and
  # Debian's pandas and numpy, which its DataFrames and arrays need
  python3-venv python3-wheel python3-wheel-whl python3-pandas python3-numpy
)
for arg in "$@"; do
  case "$arg" in
    --bench) packages+=(python3-matplotlib) ;;
    *) echo "install-deps.sh: unknown option '$arg' (usage: scripts/install-deps.sh [--bench])" >&2; exit 2 ;;
  esac
done
# shellcheck source=lib/apt.sh
. "$(dirname "${BASH_SOURCE[0]}")/lib/apt.sh"
apt_install_missing "${packages[@]}"
