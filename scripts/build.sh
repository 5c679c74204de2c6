#!/usr/bin/env bash
# Configures and builds the package, tests included: a standalone catkin build
# in ./build with its devel space in ./devel, side by side as in a catkin
# workspace (AF_BUILD_DIR=DIR: DIR and DIR_devel; see scripts/env.sh). The
# devel space is kept out of build/ because rosrun skips every path under
# <package>/build/. Needs scripts/setup.sh to have run once. AF_CMAKE_ARGS:
# more cmake arguments (scripts/sanitize.sh: the sanitizer and fuzzing
# build); CC and CXX choose the compilers on the first configure.
set -euo pipefail
source "$(dirname "$0")/env.sh"
cmake -S "$AF_ROOT" -B "$AF_BUILD" -DCATKIN_DEVEL_PREFIX="$AF_DEVEL" \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 -DPython3_EXECUTABLE=/usr/bin/python3 \
  -DCATKIN_ENABLE_TESTING=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo ${AF_CMAKE_ARGS:-} \
  >"$AF_BUILD.cmake.log" 2>&1 ||
  { cat "$AF_BUILD.cmake.log"; exit 1; }
# catkin marks its build folder CATKIN_IGNORE, not the devel space; without the
# mark, tools that walk the package (catkin_lint, package crawlers) would take
# ./devel's files for the package's own.
touch "$AF_DEVEL/CATKIN_IGNORE"
make -C "$AF_BUILD" -j"$(nproc)"
make -C "$AF_BUILD" -j"$(nproc)" tests
echo "build: done; for rosrun and roslaunch: source $AF_DEVEL/setup.bash"
