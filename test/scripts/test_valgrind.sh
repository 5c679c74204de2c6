#!/usr/bin/env bash
# scripts/valgrind.sh --short: memcheck on firmness_model, analyze and the
# node on a 2-strike replay; passes when it exits 0 (no error, no definite
# leak in any of the three) and prints the three figures lines. Registered
# in ctest as scripts_valgrind.
set -euo pipefail
source "$(dirname "$0")/harness.sh"

af_run_script AF_VALGRIND_PORT 280 "$tmp/vg.out" valgrind.sh --short
for run in firmness_model analyze firmness_node; do
  grep -qE "^valgrind $run +[0-9]+ s: 0 errors, definitely lost 0 bytes" "$tmp/vg.out" ||
    bad "valgrind.sh: $run not clean"
done
af_check_stopped "$port" || fail=1
[ "$fail" -eq 0 ] && echo "test_valgrind: passed"
exit "$fail"
