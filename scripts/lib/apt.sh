# apt_install_missing PACKAGE...: installs with apt-get (no recommends) those of the Debian
# packages that are not installed, and nothing when all are; as root, or through sudo.
# Sourced by the scripts/install-*.sh that install Debian packages.
apt_install_missing() {
  local p sudo="" missing=()
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  ((${#missing[@]})) || return 0
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  echo "installing: ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
}
