#!/usr/bin/env bash
# The one test command: installs what is missing, builds, and runs every test
# (core unit tests, CLI tests, shim tests, rostests, lint) with ctest, in
# parallel: `ctest -j N`, N from nproc unless AF_TEST_JOBS=N says (1: one at
# a time). Every test that starts a ROS master takes a free port of its own
# and a scratch folder of its own (doc/tests.md), so they run side by side.
# Extra arguments go to ctest (e.g. -L unit, -R core_, -LE slow).
# Exits non-zero when any test fails.
set -euo pipefail
source "$(dirname "$0")/env.sh"
bash "$AF_ROOT/scripts/setup.sh"
bash "$AF_ROOT/scripts/build.sh"
af_source_devel
cd "$AF_BUILD"
jobs=${AF_TEST_JOBS:-$(nproc)}
ctest --output-on-failure -j "$jobs" "$@"
