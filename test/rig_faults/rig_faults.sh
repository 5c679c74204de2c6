# shellcheck shell=bash
# Sourced by the rig-fault suite (test/rig_faults/test_*.sh, ctest
# rig_faults_*): the hostile suite's case runner (test/hostile/hostile.sh:
# hostile_case NAME EXIT REGEX TIME_S RSS_MIB -- CMD ARG..., hostile_done),
# the build under test ($hostile_bin: the package's executables) and a
# scratch folder ($tmp), removed on exit.
# shellcheck disable=SC1091
source "$(dirname "${BASH_SOURCE[0]}")/../hostile/hostile.sh"
rig_bin=$hostile_bin
