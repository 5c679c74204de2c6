# shellcheck shell=bash
# Sourced by the rig-fault suite (test/rig_faults/test_*.sh, ctest
# rig_faults_*): the hostile suite's case runner (test/hostile/hostile.sh:
# hostile_case NAME EXIT REGEX TIME_S RSS_MIB -- CMD ARG..., hostile_done),
# the build under test ($hostile_bin: the package's executables) and a
# scratch folder ($tmp), removed on exit.
# shellcheck disable=SC1091
source "$(dirname "${BASH_SOURCE[0]}")/../hostile/hostile.sh"
rig_bin=$hostile_bin

# check NAME TEXT REGEX: one case, TEXT matched against the extended regex;
# rig_done NAME: the suite's last line, exit 1 when a case failed.
rig_fails=0
check() {
  if grep -Eq -- "$3" <<<"$2"; then echo "$1: ok ($2)"; else
    echo "$1: FAIL: '$2' does not match '$3'" >&2
    rig_fails=$((rig_fails + 1))
  fi
}
rig_done() {
  echo "$1: $rig_fails failed"
  [ "$rig_fails" = 0 ]
}
