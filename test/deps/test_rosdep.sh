#!/usr/bin/env bash
# ctest rosdep_keys: rosdep itself resolves every key of package.xml, against a
# local rosdep database and nothing else: a sources.list.d in a scratch folder
# with the package's rules (rosdep/acoustic_firmness.yaml, rosdep/debian_ros.yaml,
# as README.md's "rosdep" section installs them, before 20-default.list) and a
# local copy of upstream's rules for the other keys (test/data/rosdep_upstream.yaml,
# as 20-default.list), an empty rosdistro index, a scratch ROS_HOME, and a proxy
# that refuses every connection: the system's rosdep configuration and cache are
# never read nor written, and no network is used.
#   1. `rosdep check --from-paths <pkg> --ignore-src` passes (every key resolves,
#      every package is installed), with ROS_PACKAGE_PATH unset so that no ROS
#      key is skipped as a source package;
#   2. `rosdep resolve` gives, key by key, the packages scripts/setup.sh
#      installs (`setup.sh --list`): one mapping;
#   3. without the package's rules, libplplot-dev, libgsl and libfftw3 do not
#      resolve on this release (what the rules are for), and with them listed
#      AFTER upstream's, libgsl and libfftw3 still do not (why README.md says
#      "before 20-default.list").
set -uo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
status=0 nbad=0
bad() { echo "FAIL: $*"; status=1; nbad=$((nbad + 1)); }

command -v rosdep >/dev/null || {
  echo "FAIL: no rosdep (Debian's python3-rosdep2): run scripts/setup.sh"
  exit 1
}
tmp=$(mktemp -d /tmp/af_rosdep.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/home" "$tmp/sources"
printf '%%YAML 1.1\n---\ntype: index\nversion: 4\ndistributions: {}\n' >"$tmp/index-v4.yaml"
export ROS_HOME=$tmp/home ROSDEP_SOURCE_PATH=$tmp/sources \
  ROSDISTRO_INDEX_URL=file://$tmp/index-v4.yaml \
  http_proxy=http://127.0.0.1:9 https_proxy=http://127.0.0.1:9 no_proxy=
unset ROS_PACKAGE_PATH

ours="yaml file://$root/rosdep/acoustic_firmness.yaml
yaml file://$root/rosdep/debian_ros.yaml"
upstream="yaml file://$root/test/data/rosdep_upstream.yaml"
# sources NAME=CONTENT...: the sources.list.d holds exactly these files, then
# `rosdep update` reads them into the scratch cache.
sources() {
  rm -rf "${ROSDEP_SOURCE_PATH:?}"/* "$ROS_HOME/rosdep"
  local f
  for f in "$@"; do printf '%s\n' "${f#*=}" >"$ROSDEP_SOURCE_PATH/${f%%=*}"; done
  rosdep update >"$tmp/update.log" 2>&1 || {
    cat "$tmp/update.log"
    bad "rosdep update failed on the local sources"
  }
}
# packages KEY: the packages `rosdep resolve KEY` gives (one line), or nothing.
packages() {
  rosdep resolve "$1" 2>/dev/null | grep -v '^#' | tr '\n' ' ' | sed 's/ *$//'
}

echo "== rosdep check, the package's rules first, then upstream's"
sources "10-acoustic_firmness.list=$ours" "20-default.list=$upstream"
grep -F file:// "$tmp/update.log"
# rosdep 0.22 exits 0 when a key has no rule (it prints an ERROR block): read
# the words as well as the status.
out=$(rosdep check --from-paths "$root" --ignore-src 2>&1) || bad "rosdep check failed"
echo "$out"
grep -q "^All system dependencies have been satisfied" <<<"$out" || bad "rosdep check: not satisfied"
! grep -q "ERROR" <<<"$out" || bad "rosdep check: a key does not resolve"

echo "== rosdep resolve, key by key, against setup.sh --list"
keys=$(rosdep keys --from-paths "$root" --ignore-src 2>&1 | sort -u)
[ -n "$keys" ] || bad "rosdep keys found no key in $root"
listed=$(bash "$root/scripts/setup.sh" --list) || bad "setup.sh --list failed"
listed=$(sort -u <<<"$listed")
# one rosdep call for every key: `#ROSDEP[key]`, `#apt`, then the packages
# shellcheck disable=SC2086
resolved=$(rosdep resolve $keys 2>/dev/null | awk '
  /^#ROSDEP\[/ { if (k != "") print k ": " p; k = substr($0, 9, length($0) - 9); p = ""; next }
  /^#/ { next }
  { p = (p == "" ? $0 : p " " $0) }
  END { if (k != "") print k ": " p }' | sort -u)
n=0 before=$nbad
for key in $keys; do
  n=$((n + 1))
  got=$(sed -n "s/^$key: //p" <<<"$resolved")
  want=$(sed -n "s/^$key: //p" <<<"$listed")
  if [ -z "$got" ]; then
    bad "rosdep does not resolve '$key'"
  elif [ -n "$want" ] && [ "$got" != "$want" ]; then
    bad "'$key': rosdep resolves [$got], setup.sh installs [$want]"
  fi
done
[ "$nbad" = "$before" ] && echo "rosdep_keys: $n keys resolved, as setup.sh installs them"
[ "$n" -eq "$(grep -c . <<<"$listed")" ] ||
  bad "rosdep keys gives $n keys, setup.sh --list $(grep -c . <<<"$listed")"

echo "== upstream's rules alone (must not resolve libplplot-dev, libgsl, libfftw3 here)"
sources "20-default.list=$upstream"
for key in libplplot-dev libgsl; do
  got=$(packages "$key")
  [ -z "$got" ] || bad "'$key' resolved to [$got] without the package's rules"
done
[ "$(packages libfftw3)" = "libfftw3-3 libfftw3-dev" ] ||
  bad "upstream's libfftw3 no longer names libfftw3-3: is the package's libfftw3 rule still needed?"

echo "== the package's rules AFTER upstream's (upstream's Debian rules win)"
sources "20-default.list=$upstream" "30-acoustic_firmness.list=$ours"
[ -z "$(packages libgsl)" ] || bad "libgsl resolved with the package's rules after upstream's"
[ -n "$(packages libplplot-dev)" ] || bad "libplplot-dev did not resolve"

[ "$status" -eq 0 ] && echo "rosdep_keys: pass"
exit "$status"
