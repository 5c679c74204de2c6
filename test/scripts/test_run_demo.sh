#!/usr/bin/env bash
# The main command end to end, as the README gives it: `bash scripts/run.sh`
# (the replay demo) with --strikes 3, against the build under test, on a
# master port of its own. Passes when it exits 0, prints 3 measured strikes
# and its summary, and leaves no process running. Registered in ctest as
# scripts_run_demo.
set -euo pipefail
source "$(dirname "$0")/harness.sh"

port=$(af_free_port)
export AF_DEMO_PORT=$port
echo "test_run_demo: bash scripts/run.sh --strikes 3 (master port $port)"
status=0
# timeout signals the whole process group (run.sh, roscore, roslaunch) on a
# hang; run.sh's own exit trap stops its master.
timeout -k 5 90 bash "$AF_ROOT/scripts/run.sh" --strikes 3 >"$tmp/run.out" 2>&1 || status=$?
cat "$tmp/run.out"

fail=0
bad() { fail=1; echo "FAIL: $*" >&2; }
[ "$status" -eq 0 ] || bad "scripts/run.sh --strikes 3 exited $status"
strikes=$(grep -cE '^apple +[0-9]+: 0S2 ' "$tmp/run.out" || true)
[ "$strikes" -eq 3 ] || bad "$strikes measured strike lines, expected 3"
grep -q '^demo: 3 of 3 strikes reported' "$tmp/run.out" || bad "no summary 'demo: 3 of 3 strikes reported'"
af_check_stopped "$port" || fail=1
[ "$fail" -eq 0 ] && echo "test_run_demo: passed"
exit "$fail"
