#!/usr/bin/env bash
# Static checks, run by the test command as the ctest test `lint`:
# clang-format (.clang-format), cppcheck on the C and C++ sources, catkin_lint.
# Exits non-zero on any finding.
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root" || exit 1
export PATH=/usr/bin:$PATH
status=0

mapfile -t sources < <(git ls-files -co --exclude-standard -- 'src/*.c' 'src/*.h' 'src/*.cpp' \
  'src/*.hpp' 'test/*.c' 'test/*.h' 'test/*.cpp' 2>/dev/null || find src test -name '*.[ch]' -o -name '*.[ch]pp')
if ! clang-format --dry-run --Werror "${sources[@]}"; then
  echo "lint: clang-format: run 'clang-format -i' on the files above" >&2
  status=1
fi

# C with the C11 standard, C++ (the shim) on its own; ROS headers are not
# analysed (system includes), only our code. The core's layers: one include
# folder each (src/core/CMakeLists.txt).
core_inc=()
for d in src/core/*/; do core_inc+=("-I${d%/}"); done
if ! cppcheck --quiet --error-exitcode=1 --enable=warning,style,performance --std=c11 \
  --inline-suppr "${core_inc[@]}" -Isrc/shim -Isrc/tools -Isrc/plot -Isrc/report src/core src/tools src/node \
  src/plot src/report src/demo src/convert src/cfg src/doc test/core; then
  echo "lint: cppcheck (C) found the problems above" >&2
  status=1
fi
if ! cppcheck --quiet --error-exitcode=1 --enable=warning,performance --std=c++14 --language=c++ \
  --inline-suppr "${core_inc[@]}" -Isrc/shim --suppress=missingIncludeSystem src/shim; then
  echo "lint: cppcheck (C++) found the problems above" >&2
  status=1
fi

# The checkout's folder name need not be the package name (CI clones anywhere).
findings=$(catkin_lint -q -W2 --ignore package_path_name . 2>&1 | grep -v -e rosdep -e 'unknown dependencies')
if [ -n "$findings" ]; then
  echo "$findings"
  echo "lint: catkin_lint found the problems above" >&2
  status=1
fi
[ "$status" -eq 0 ] && echo "lint: clean"
exit "$status"
