#!/usr/bin/env bash
# Installs Debian's Slurm daemons and client tools and munge (idempotent; needs root or sudo):
# what the test labelled slurm (tests/slurm/slurm_workers_test.py) starts on loopback, and what
# a single machine needs to try scripts/slurm/submit-workers.sh (docs/cluster.md). Nothing is
# configured here; the test starts its own munged, slurmctld and slurmd with their own key,
# sockets, ports and state in a temporary folder, beside any services Debian may have started.
set -euo pipefail
packages=(slurmctld slurmd slurm-client munge)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  echo "installing: ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
