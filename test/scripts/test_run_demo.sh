#!/usr/bin/env bash
# The main command end to end, as the README gives it: `bash scripts/run.sh`
# (the replay demo) with --strikes 3, against the build under test, on a
# master port of its own. Passes when it exits 0, prints 3 measured strikes
# and its summary, and leaves no process running. Registered in ctest as
# scripts_run_demo.
set -euo pipefail
source "$(dirname "$0")/harness.sh"

echo "test_run_demo: bash scripts/run.sh --strikes 3"
# run.sh's own exit trap stops its master.
af_run_script AF_DEMO_PORT 90 "$tmp/run.out" run.sh --strikes 3
strikes=$(grep -cE '^apple +[0-9]+: 0S2 ' "$tmp/run.out" || true)
[ "$strikes" -eq 3 ] || bad "$strikes measured strike lines, expected 3"
grep -q '^demo: 3 of 3 strikes reported' "$tmp/run.out" || bad "no summary 'demo: 3 of 3 strikes reported'"
af_check_stopped "$port" || fail=1
[ "$fail" -eq 0 ] && echo "test_run_demo: passed"
exit "$fail"
