#!/usr/bin/env bash
# Installs every Debian package acoustic_firmness needs to build, test and run,
# on Debian 12 (a minimal one included: scripts/fresh_check.sh proves it).
#
# One dependency list: package.xml names the keys, and rosdep's rules map each
# key to its Debian packages, read here as rosdep reads them (for each key, the
# first file with a Debian rule wins; the rule for this release, else '*'):
# rosdep/acoustic_firmness.yaml (what upstream lacks), rosdep/debian_ros.yaml
# (the ROS packages, as Debian ships them) and test/data/rosdep_upstream.yaml
# (upstream's rules for the other keys). The ctest rosdep_keys checks that
# rosdep itself resolves every key to the same packages. Beside them, TOOLS:
# what a minbase system lacks to check out, build and lint (no package.xml
# key: they are not dependencies of the package itself).
# --rviz: also the rviz and xvfb keys for scripts/rviz_shot.sh.
# --list: print `key: packages` for every key, install nothing.
# Idempotent: packages already present are left alone. Needs root (or sudo).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
rules=("$root/rosdep/acoustic_firmness.yaml" "$root/rosdep/debian_ros.yaml"
  "$root/test/data/rosdep_upstream.yaml")
release=$(. /etc/os-release 2>/dev/null && echo "${VERSION_CODENAME:-}")
release=${release:-bookworm}

TOOLS=(
  # check-out, certificates, the system python the ROS tools run on
  git ca-certificates python3 procps
  # static checks (scripts/lint.sh)
  clang-format clang-tidy cppcheck catkin-lint
  # the sanitizer stage and the fuzzers (scripts/sanitize.sh, fuzz.sh: clang-14 with
  # ASan, UBSan, libFuzzer), valgrind memcheck (scripts/valgrind.sh)
  clang-14 libclang-rt-14-dev valgrind
  # the fresh-machine stage (scripts/fresh_check.sh)
  mmdebstrap
  # rosdep itself, for the ctest rosdep_keys (Debian names it python3-rosdep2)
  python3-rosdep2
)

# Every key of package.xml: <depend>, <build_depend>, <exec_depend>, ... but
# the package's own name.
keys() {
  sed -n 's/.*<\([a-z_]*\)depend>[[:space:]]*\([^<[:space:]]*\)[[:space:]]*<\/\1depend>.*/\2/p' \
    "$root/package.xml"
}

# The Debian packages of one key, from the first rule file with a Debian rule
# for it (`debian: [..]`, or per release `bookworm: [..]` / `'*': [..]`); fails
# naming the key when no file has one for this release.
packages_of() {
  local pkgs
  pkgs=$(awk -v key="$1" -v rel="$release" -v q="'" '
    function list(s) {
      sub(/^[^[]*\[/, "", s); sub(/\].*$/, "", s); gsub(/,/, " ", s)
      gsub(/[[:space:]]+/, " ", s); sub(/^ /, "", s); sub(/ $/, "", s)
      return s
    }
    function out(s) { print s; done = 1; exit }
    function decide() { if (deb) out(star) }
    FNR == 1 { decide(); inkey = 0 }
    /^[^[:space:]#]/ { decide(); k = $0; sub(/:.*/, "", k); inkey = (k == key); next }
    !inkey { next }
    /^  [^[:space:]#]/ {
      decide()
      if ($1 == "debian:") { if ($0 ~ /\[/) out(list($0)); deb = 1; star = "" }
      next
    }
    deb && /^    [^[:space:]#]/ {
      v = $1; sub(/:$/, "", v); gsub(q, "", v)
      if (v == rel) out(list($0))
      if (v == "*") star = list($0)
    }
    END { if (!done) decide() }' "${rules[@]}")
  if [ -z "$pkgs" ]; then
    echo "setup: package.xml names '$1', which no rosdep rule (rosdep/*.yaml," \
      "test/data/rosdep_upstream.yaml) maps to Debian $release packages" >&2
    return 1
  fi
  echo "$pkgs"
}

want=$(keys)
[ "${1:-}" = "--rviz" ] && want="$want rviz xvfb"
PACKAGES=("${TOOLS[@]}")
for k in $want; do
  pkgs=$(packages_of "$k") || exit 1
  if [ "${1:-}" = "--list" ]; then
    echo "$k: $pkgs"
    continue
  fi
  read -r -a more <<<"$pkgs"
  PACKAGES+=("${more[@]}")
done
[ "${1:-}" = "--list" ] && exit 0

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -eq 0 ]; then
  echo "setup: all ${#PACKAGES[@]} packages present"
  exit 0
fi
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
echo "setup: installing ${missing[*]}"
$SUDO apt-get update -q
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
