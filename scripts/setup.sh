#!/usr/bin/env bash
# Installs every Debian package acoustic_firmness needs to build, test and run,
# on Debian 12 (a minimal one included: scripts/fresh_check.sh proves it).
#
# One dependency list: package.xml names the keys (as rosdep reads them), and
# scripts/debian_packages.yaml maps each key to its Debian packages. Beside
# them, TOOLS: what a minbase system lacks to check out, build and lint (no
# package.xml key: they are not dependencies of the package itself).
# --rviz: also the `rviz` key (rviz, Xvfb) for scripts/rviz_shot.sh.
# Idempotent: packages already present are left alone. Needs root (or sudo).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
map=$root/scripts/debian_packages.yaml

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
)

# Every key of package.xml: <depend>, <build_depend>, <exec_depend>, ... but
# the package's own name.
keys() {
  sed -n 's/.*<\([a-z_]*\)depend>[[:space:]]*\([^<[:space:]]*\)[[:space:]]*<\/\1depend>.*/\2/p' \
    "$root/package.xml"
}

# The packages of one key, from the map; fails naming the key when unmapped.
packages_of() {
  local line
  line=$(grep -E "^$1:[[:space:]]*\[" "$map" || true)
  if [ -z "$line" ]; then
    echo "setup: package.xml names '$1', which $map does not map to Debian packages" >&2
    return 1
  fi
  echo "$line" | sed 's/^[^[]*\[\(.*\)\].*/\1/' | tr ',' ' '
}

want=$(keys)
[ "${1:-}" = "--rviz" ] && want="$want rviz"
PACKAGES=("${TOOLS[@]}")
for k in $want; do
  pkgs=$(packages_of "$k") || exit 1
  read -r -a more <<<"$pkgs"
  PACKAGES+=("${more[@]}")
done

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
