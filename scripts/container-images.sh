#!/usr/bin/env bash
# Builds the images of docker/Dockerfile with podman: localhost/compaction-server and
# localhost/compaction-worker, from a base image made here with debootstrap from Debian's
# packages (localhost/debian:bookworm: Debian 12 minbase with the host's apt sources and
# certificate store, so that apt in the build fetches from where the host does). Nothing comes
# from a container registry.
#   - The base image is made when podman's storage does not have it: from a saved root in
#     --base-cache when that is younger than --base-max-age days and was made with the same apt
#     sources, else with a new debootstrap (which is then saved there). The saved root holds only
#     Debian's packages, and the build runs apt-get update on it, so an old one costs package
#     updates, never stale build tools.
#   - The images record the source revision (the context leaves .git out): --revision, or the
#     commit of --src's git checkout (with "-dirty" for uncommitted changes, as the CMake build
#     says it); a --src without .git needs --revision.
#   - Prints each step's time and the images' sizes.
# podman's configuration is the caller's: the machine's, or the one that
# `eval "$(scripts/podman-conf.sh DIR)"` sets up (what tests/container/container_test.py does).
#
# usage: scripts/container-images.sh [--src DIR] [--revision REV] [--base-cache DIR]
#                                    [--base-max-age DAYS] [--base-only]
#   --src DIR            the source tree to build (default: this checkout)
#   --revision REV       the source revision the binaries report (default: from --src's git)
#   --base-cache DIR     where the base root is saved between runs (default
#                        /var/tmp/compaction-container-base; about 60 MB)
#   --base-max-age DAYS  a saved root older than this is made again (default 7)
#   --base-only          make the base image, build nothing
#   COMPACTION_DEBIAN_MIRROR  the mirror debootstrap fetches from (default
#                        http://deb.debian.org/debian; the image then uses the host's sources)
# Needs root (debootstrap; rootful podman), and installs podman and the rest with
# scripts/install-podman.sh when missing. Fails, never skips, when something is missing.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# shellcheck source=lib/debian-root.sh
. "$repo/scripts/lib/debian-root.sh"   # debian_root_tools, debian_root_make, debian_root_host_apt
src="$repo"
revision=""
cache=/var/tmp/compaction-container-base
max_age=7
base_only=0
mirror="${COMPACTION_DEBIAN_MIRROR:-http://deb.debian.org/debian}"
suite=bookworm
base=localhost/debian:bookworm

die() { echo "container-images: FAILED: $*" >&2; exit 1; }
say() { echo "container-images: $*"; }
while [ $# -gt 0 ]; do
  case "$1" in
    --src) src="${2:?--src needs a folder}"; shift 2 ;;
    --revision) revision="${2:?--revision needs a revision}"; shift 2 ;;
    --base-cache) cache="${2:?--base-cache needs a folder}"; shift 2 ;;
    --base-max-age) max_age="${2:?--base-max-age needs days}"; shift 2 ;;
    --base-only) base_only=1; shift ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "container-images.sh: unknown option '$1' (--help)" >&2; exit 2 ;;
  esac
done
[ "$(id -u)" -eq 0 ] || die "needs root (debootstrap, rootful podman)"
[ -f "$src/docker/Dockerfile" ] || die "$src/docker/Dockerfile does not exist (--src)"
src="$(cd "$src" && pwd)"
command -v podman >/dev/null && command -v debootstrap >/dev/null || "$repo/scripts/install-podman.sh"

fmt() { printf '%dm%02ds' $(($1 / 60)) $(($1 % 60)); }
mb() { podman image inspect --format '{{.Size}}' "$1" | awk '{ printf "%.0f MB", $1 / 1e6 }'; }

# --- the base image ------------------------------------------------------------------------------
# The saved root is valid for the apt sources it was made with (the host's, and the mirror).
sources_key() {
  { echo "$mirror $suite"; cat /etc/apt/sources.list.d/debian.sources 2>/dev/null || true; } | sha256sum | cut -c1-16
}
make_base() {
  local t0 key tarball root
  t0=$(date +%s)
  key="$(sources_key)"
  tarball="$cache/debian-$suite-$key.tar"
  mkdir -p "$cache"
  if [ -f "$tarball" ] && [ -z "$(find "$tarball" -mtime +"$max_age")" ]; then
    say "base: importing the saved root $tarball (made $(date -r "$tarball" -u '+%F %H:%M UTC'))"
  else
    rm -f "$cache"/debian-"$suite"-*.tar
    root="$(mktemp -d "$cache/root.XXXXXX")"
    # shellcheck disable=SC2064
    trap "umount_under '$root'; rm -rf --one-file-system '$root'" EXIT
    say "base: debootstrap --variant=minbase $suite from $mirror"
    debian_root_tools "$mirror" "$suite"
    debian_root_make "$root" "$mirror" "$suite" >"$cache/debootstrap.log" 2>&1 ||
      { tail -n 30 "$cache/debootstrap.log" >&2; die "debootstrap failed (log $cache/debootstrap.log)"; }
    debian_root_host_apt "$root"
    # What an image does not need: downloaded packages, package lists (the build fetches them).
    rm -rf "$root"/var/cache/apt/archives/*.deb "$root"/var/lib/apt/lists/* "$root"/var/log/*.log
    tar -C "$root" --numeric-owner -cf "$tarball.part" .
    mv "$tarball.part" "$tarball"
    umount_under "$root"
    rm -rf --one-file-system "$root"
    trap - EXIT
  fi
  podman import --quiet --change 'CMD ["/bin/bash"]' \
    --message "debootstrap --variant=minbase $suite, the host's apt sources" "$tarball" "$base" >/dev/null
  say "base: $base ($(mb "$base")) in $(fmt $(($(date +%s) - t0)))"
}
umount_under() {  # what debootstrap left mounted (it mounts /proc and /sys of the new root)
  awk -v d="$1/" 'index($5 "/", d) == 1 { print $5 }' /proc/self/mountinfo | sort -r |
    while read -r m; do umount "$m" 2>/dev/null || umount -l "$m"; done
}
if podman image exists "$base"; then
  say "base: $base is in podman's storage ($(mb "$base"))"
else
  make_base
fi
[ "$base_only" = 0 ] || exit 0

# --- the images ----------------------------------------------------------------------------------
if [ -z "$revision" ]; then
  git -C "$src" rev-parse --git-dir >/dev/null 2>&1 ||
    die "$src is not a git checkout: give the source revision with --revision"
  revision="$(git -c safe.directory="$src" -C "$src" rev-parse --short=12 HEAD)"
  [ -z "$(git -c safe.directory="$src" -C "$src" status --porcelain --untracked-files=no)" ] ||
    revision="$revision-dirty"
fi
say "building from $src at source revision $revision"
for target in server worker; do
  t0=$(date +%s)
  log="$(mktemp /tmp/compaction-image-$target.XXXXXX.log)"
  # --pull=never: the base is the local image; nothing is fetched from a registry.
  podman build --pull=never -f "$src/docker/Dockerfile" --target "$target" \
    --build-arg BASE_IMAGE="$base" --build-arg SOURCE_REVISION="$revision" \
    -t "localhost/compaction-$target:latest" "$src" >"$log" 2>&1 ||
    { tail -n 40 "$log" >&2; die "podman build --target $target failed (log $log)"; }
  rm -f "$log"
  say "image: localhost/compaction-$target ($(mb "localhost/compaction-$target")) in $(fmt $(($(date +%s) - t0)))"
done
