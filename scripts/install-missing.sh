# scripts/install-missing.sh — sourced by scripts/setup.sh and scripts/fuzz.sh:
#   install_missing TAG PACKAGE...
# installs those of the Debian packages that are not installed yet (apt-get, as root or through sudo),
# saying which under TAG on stderr; installs nothing when all are there.
install_missing() {
  local tag=$1
  shift
  local missing=() p sudo=""
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  ((${#missing[@]})) || return 0
  echo "$tag: installing ${missing[*]}" >&2
  [ "$(id -u)" -eq 0 ] || sudo=sudo
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}
