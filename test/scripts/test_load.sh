#!/usr/bin/env bash
# scripts/load.sh and scripts/soak.sh in a short mode (not the default
# figures: those take minutes, see README "Robustness"): 6 strikes replayed
# at 5x, then 0.002 h of soak (14 strikes) at 10x, each on a master port of
# its own. Passes when both exit 0 (no strike lost or misattributed), print
# their figures line, and leave no process running. Registered in ctest as
# scripts_load.
set -euo pipefail
source "$(dirname "$0")/harness.sh"

af_run_script AF_LOAD_PORT 100 "$tmp/load.out" load.sh --strikes 6 --rates 5
grep -qE '^rate 5x .*: 6 strikes, 6 reports, 0 lost, 0 misattributed' "$tmp/load.out" ||
  bad "load.sh: no line '6 strikes, 6 reports, 0 lost, 0 misattributed'"
grep -qE 'RSS [0-9.]+ MB after warm-up.*latency p50 [0-9.]+ ms, p99 [0-9.]+ ms, max [0-9.]+ ms' \
  "$tmp/load.out" || bad "load.sh: no RSS or latency figures"
af_check_stopped "$port" || fail=1

af_run_script AF_LOAD_PORT 100 "$tmp/soak.out" soak.sh --hours 0.002 --rate 10
grep -qE '^rate 10x .*: 14 strikes, 14 reports, 0 lost, 0 misattributed' "$tmp/soak.out" ||
  bad "soak.sh: no line '14 strikes, 14 reports, 0 lost, 0 misattributed'"
af_check_stopped "$port" || fail=1
[ "$fail" -eq 0 ] && echo "test_load: passed"
exit "$fail"
