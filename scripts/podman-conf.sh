#!/usr/bin/env bash
# Writes a podman configuration of its own into DIR (created when missing) and prints the two
# variables that make podman, podman-compose and buildah use it, for `eval`:
#   eval "$(scripts/podman-conf.sh /var/tmp/compaction-podman)"
# What it sets, and why (each found on a root VM whose limits and cgroups are not podman's
# defaults; they are right on an ordinary Debian 12 too):
#   storage       DIR/storage (images, layers, volumes), DIR/run; the overlay driver when the
#                 kernel has overlayfs (vfs otherwise: a full copy per layer)
#   runtime       runc with cgroupfs: crun 1.8 (Debian's default) refuses a host with cgroups in
#                 hybrid mode, and there may be no systemd to manage cgroups
#   ulimits       the containers' open files and processes at what this process may give them:
#                 podman asks for 1048576 open files and the host's process limit, and without
#                 CAP_SYS_RESOURCE the runtime cannot raise a hard limit (podman itself lowers
#                 its process limit to 32768 before it starts the runtime)
#   events        written to a file (no journald)
#   network       netavark, whose aardvark-dns lets containers find each other by name, with its
#                 networks' files in DIR/networks (the machine's /etc/containers is not touched)
# Everything podman keeps lives under DIR; remove it with scripts/podman-conf.sh --remove DIR,
# which removes DIR's containers and images first (rm -rf alone would leave overlay mounts).
# usage: scripts/podman-conf.sh DIR
#        scripts/podman-conf.sh --remove DIR
set -euo pipefail

die() { echo "podman-conf: $*" >&2; exit 1; }
remove=0
if [ "${1:-}" = --remove ]; then remove=1; shift; fi
[ $# -eq 1 ] || die "usage: scripts/podman-conf.sh [--remove] DIR"
[ "$remove" = 1 ] || mkdir -p "$1"
dir="$(cd "$1" 2>/dev/null && pwd -P)" || die "no folder $1"

if [ "$remove" = 1 ]; then
  [ -f "$dir/containers.conf" ] && [ -f "$dir/storage.conf" ] ||
    die "$dir holds no configuration of scripts/podman-conf.sh: not removed"
  export CONTAINERS_CONF="$dir/containers.conf" CONTAINERS_STORAGE_CONF="$dir/storage.conf"
  podman rm --all --force --time 10 >/dev/null || true
  podman pod rm --all --force >/dev/null 2>&1 || true
  podman rmi --all --force >/dev/null || true
  podman volume rm --all --force >/dev/null || true
  podman network prune --force >/dev/null || true   # their bridges and firewall rules on the host
  # What podman still holds mounted under DIR (a store it could not clean): unmount, deepest first.
  awk -v d="$dir/" 'index($5 "/", d) == 1 { print $5 }' /proc/self/mountinfo | sort -r |
    while read -r m; do umount "$m" 2>/dev/null || umount -l "$m"; done
  left="$(awk -v d="$dir/" 'index($5 "/", d) == 1 { print $5 }' /proc/self/mountinfo)"
  [ -z "$left" ] || die "still mounted, $dir not removed: $left"
  rm -rf --one-file-system "$dir"
  exit 0
fi

mkdir -p "$dir/storage" "$dir/run" "$dir/tmp" "$dir/networks"
driver=vfs
grep -qw overlay /proc/filesystems && driver=overlay
nofile="$(ulimit -Hn)"
nproc="$(ulimit -Hu)"
[ "$nproc" = unlimited ] || [ "$nproc" -gt 32768 ] && nproc=32768
[ "$nofile" = unlimited ] && nofile=1048576
cat >"$dir/storage.conf" <<CONF
# written by scripts/podman-conf.sh
[storage]
driver = "$driver"
graphroot = "$dir/storage"
runroot = "$dir/run"
CONF
cat >"$dir/containers.conf" <<CONF
# written by scripts/podman-conf.sh (its header says why)
[containers]
default_ulimits = ["nofile=$nofile:$nofile", "nproc=$nproc:$nproc"]

[engine]
runtime = "runc"
cgroup_manager = "cgroupfs"
events_logger = "file"
tmp_dir = "$dir/tmp"

[network]
network_backend = "netavark"
network_config_dir = "$dir/networks"
CONF
echo "export CONTAINERS_CONF='$dir/containers.conf' CONTAINERS_STORAGE_CONF='$dir/storage.conf'"
