#!/usr/bin/env bash
# Installs Debian's Slurm daemons and client tools and munge (idempotent; needs root or sudo):
# what the test labelled slurm (tests/slurm/slurm_workers_test.py) starts on loopback, and what
# a single machine needs to try scripts/slurm/submit-workers.sh (docs/cluster.md). Nothing is
# configured here; the test starts its own munged, slurmctld and slurmd with their own key,
# sockets, ports and state in a temporary folder, beside any services Debian may have started.
set -euo pipefail
packages=(slurmctld slurmd slurm-client munge)
# shellcheck source=lib/apt.sh
. "$(dirname "${BASH_SOURCE[0]}")/lib/apt.sh"
apt_install_missing "${packages[@]}"
