# A new Debian root made with debootstrap from Debian's packages only, set up to fetch and trust
# what the host does. Sourced by scripts/check-fresh-machine.sh (a clean machine to run the
# README's commands in) and scripts/container-images.sh (the base image of docker/Dockerfile).
# Each function runs on its own in a `bash -c` with errexit (check-fresh-machine.sh's steps), so
# none of them relies on another or on a variable of its caller. Needs root.

# debian_root_tools MIRROR SUITE: installs debootstrap with apt-get when it is missing and checks
# that MIRROR serves SUITE (with curl, when there is one), so that a missing mirror fails here with
# its address rather than somewhere inside debootstrap.
debian_root_tools() {
  local mirror="$1" suite="$2"
  if ! command -v debootstrap >/dev/null; then
    echo "apt-get install debootstrap"
    apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends debootstrap
  fi
  debootstrap --version
  if command -v curl >/dev/null; then
    curl -fsS -m 30 -o /dev/null "$mirror/dists/$suite/Release" ||
      { echo "cannot reach the Debian mirror: $mirror/dists/$suite/Release"; return 1; }
    echo "mirror $mirror answers"
  fi
}

# debian_root_make DIR MIRROR SUITE: the minimal Debian (minbase: essential packages and apt) in
# the existing folder DIR.
debian_root_make() {
  debootstrap --variant=minbase "$3" "$1" "$2"
}

# debian_root_host_apt DIR: the host's apt sources (/etc/apt/sources.list.d/debian.sources, which
# replaces debootstrap's sources.list, when the host has one: its mirror and the security and
# updates suites) and its certificate store (/etc/ssl/certs, /usr/local/share/ca-certificates,
# which update-ca-certificates keeps), so that apt, npm and git in DIR use and trust what the
# host does. Prints the sources DIR ends up with.
debian_root_host_apt() {
  local root="$1"
  if [ -f /etc/apt/sources.list.d/debian.sources ]; then
    cp /etc/apt/sources.list.d/debian.sources "$root/etc/apt/sources.list.d/"
    rm -f "$root/etc/apt/sources.list"
  fi
  cat "$root"/etc/apt/sources.list.d/*.sources "$root"/etc/apt/sources.list 2>/dev/null | grep -E '^(deb|URIs|Suites)' || true
  mkdir -p "$root/etc/ssl/certs" "$root/usr/local/share/ca-certificates"
  cp -a /etc/ssl/certs/. "$root/etc/ssl/certs/"
  if [ -d /usr/local/share/ca-certificates ]; then
    cp -a /usr/local/share/ca-certificates/. "$root/usr/local/share/ca-certificates/"
  fi
}
