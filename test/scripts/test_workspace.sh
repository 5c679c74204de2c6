#!/usr/bin/env bash
# The package as an integrator installs it: copied alone into a fresh catkin
# workspace (ws/src/acoustic_firmness, no ../shared beside it, no build of
# ours), built with catkin_make, and its fast tier run the two catkin ways:
# `catkin_make run_tests_acoustic_firmness_af_unit` with catkin_test_results
# counting one result per unit test (every test ctest runs is a catkin
# run_tests target too: cmake/af_tests.cmake), and `catkin_make test` with
# ctest's -L unit. Registered in ctest as scripts_workspace.
set -euo pipefail
source "$(dirname "$0")/harness.sh"

ws=$tmp/ws
mkdir -p "$ws/src/acoustic_firmness"
# The package's files, not its builds (a build's CMakeCache names its own folder).
tar -C "$AF_ROOT" --exclude=./build --exclude=./devel --exclude='./build-*' --exclude='./build_*' \
  --exclude=./.git -cf - . | tar -C "$ws/src/acoustic_firmness" -xf -
[ ! -e "$ws/shared" ] && [ ! -e "$ws/src/shared" ] || bad "a shared folder beside the workspace's package"
cd "$ws"
# Not the test's own devel space: a workspace of its own, from /usr's ROS alone.
env -u CMAKE_PREFIX_PATH -u ROS_PACKAGE_PATH -u PYTHONPATH -u LD_LIBRARY_PATH -u PKG_CONFIG_PATH \
  bash -c 'source /usr/share/catkin/setup.bash 2>/dev/null || true; catkin_make -j2 >build.log 2>&1' ||
  { tail -n 40 build.log; bad "catkin_make failed"; exit 1; }
echo "test_workspace: catkin_make built the workspace"
units=$(ls "$ws/src/acoustic_firmness/test/core"/test_*.c | wc -l)
(source devel/setup.bash && catkin_make run_tests_acoustic_firmness_af_unit >run_tests.log 2>&1) ||
  { tail -n 40 run_tests.log; bad "catkin_make run_tests_acoustic_firmness_af_unit failed"; }
(source devel/setup.bash && catkin_test_results build/test_results/acoustic_firmness) >results.log 2>&1 ||
  bad "catkin_test_results: $(tail -n 5 results.log)"
cat results.log | tail -n 1
grep -qx "Summary: $units tests, 0 errors, 0 failures, 0 skipped" results.log ||
  bad "catkin_test_results did not see the $units unit tests pass: $(tail -n 1 results.log)"
(source devel/setup.bash && catkin_make test ARGS="-L unit -j2" >test.log 2>&1) ||
  { tail -n 30 test.log; bad "catkin_make test -L unit failed"; }
grep -q "100% tests passed, 0 tests failed out of $units" test.log ||
  bad "catkin_make test: $(grep 'tests passed' test.log)"
[ "$fail" -eq 0 ] && echo "test_workspace: passed ($units unit tests seen by catkin_test_results and by catkin_make test)"
exit "$fail"
