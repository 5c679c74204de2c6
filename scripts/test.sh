#!/usr/bin/env bash
# The one test command: installs what is missing, builds, and runs every test
# (core unit tests, CLI tests, shim tests, rostests, lint) with ctest.
# Exits non-zero when any test fails.
set -euo pipefail
source "$(dirname "$0")/env.sh"
bash "$AF_ROOT/scripts/setup.sh"
bash "$AF_ROOT/scripts/build.sh"
af_source_devel
cd "$AF_BUILD"
ctest --output-on-failure "$@"
