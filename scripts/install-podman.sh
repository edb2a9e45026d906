#!/usr/bin/env bash
# Installs what the container test (tests/container/container_test.py, label container) and
# scripts/container-images.sh build and run the images of docker/ with, all Debian packages
# (idempotent; needs root or sudo):
#   podman, podman-compose  the engine and the compose file's runner (Debian 12: 4.3.1, 1.0.3)
#   runc                    the OCI runtime: Debian's default, crun 1.8, refuses a host whose
#                           cgroups are in hybrid mode (v1 controllers beside a v2 mount)
#   netavark, aardvark-dns  the network backend whose DNS lets the workers reach the server by
#                           its service name (Debian's default CNI backend needs the dnsname
#                           plugin for that)
#   iptables                what netavark 1.4 sets a network's firewall rules with: without it a
#                           build's RUN step fails with "netavark: No such file or directory"
#                           (the package declares no dependency on it)
#   debootstrap             the base image, a minimal Debian 12 from Debian's packages
# Nothing is configured here: scripts/podman-conf.sh writes the settings into a folder of its own.
set -euo pipefail
# shellcheck source=lib/apt.sh
. "$(dirname "${BASH_SOURCE[0]}")/lib/apt.sh"
apt_install_missing podman podman-compose runc netavark aardvark-dns iptables debootstrap
