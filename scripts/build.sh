#!/usr/bin/env bash
# Configures and builds the package (standalone catkin build in ./build, or
# $AF_BUILD_DIR), tests included. Needs scripts/setup.sh to have run once.
set -euo pipefail
source "$(dirname "$0")/env.sh"
cmake -S "$AF_ROOT" -B "$AF_BUILD" \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 -DPython3_EXECUTABLE=/usr/bin/python3 \
  -DCATKIN_ENABLE_TESTING=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo >"$AF_BUILD.cmake.log" 2>&1 ||
  { cat "$AF_BUILD.cmake.log"; exit 1; }
make -C "$AF_BUILD" -j"$(nproc)"
make -C "$AF_BUILD" -j"$(nproc)" tests
