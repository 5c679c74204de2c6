#!/usr/bin/env bash
# launch/replay.launch end to end, as a user runs it: `roslaunch
# acoustic_firmness replay.launch bag:=...` on a 3-strike strike_bag bag, with
# a master of its own. Passes when the launch ends by itself with status 0
# after "replay: end of the bag", its output holds neither the red
# "REQUIRED process [...] has died" nor the false "'rig_base' is not in TF"
# warning, the 3 strikes are reported (StrikeReport, recorded by rostopic
# while the launch runs), every apple's StrikeAdvice knows its strike point
# (the rig's frames were in TF: the warning was not just hidden), the
# replay deleted /use_sim_time at its end (a node started later on the same
# master runs on wall time), and no process is left running. Registered in ctest as scripts_replay_launch.
set -euo pipefail
source "$(dirname "$0")/harness.sh"

"$AF_DEVEL/lib/acoustic_firmness/strike_bag" --strikes 3 --seed 3 --out "$tmp/s3.bag" >/dev/null
port=$(af_free_port)
export ROS_MASTER_URI=http://localhost:$port
echo "test_replay_launch: roslaunch acoustic_firmness replay.launch bag:=s3.bag (port $port)"
status=0
timeout -k 5 90 roslaunch -p "$port" acoustic_firmness replay.launch bag:="$tmp/s3.bag" \
  >"$tmp/launch.out" 2>&1 &
launch=$!
# The recorders, once the master is up (before playback: the launch waits 4 s).
for _ in $(seq 100); do
  rostopic list >/dev/null 2>&1 && break
  sleep 0.1
done
rostopic echo -p /lane1/strike_report/apple_id >"$tmp/reports.csv" 2>/dev/null &
reports=$!
rostopic echo -p /lane1/strike_advice/text >"$tmp/advice.csv" 2>/dev/null &
advice=$!
wait "$launch" || status=$?
kill -INT "$reports" "$advice" 2>/dev/null || true
wait "$reports" "$advice" 2>/dev/null || true
cat "$tmp/launch.out"
[ "$status" -eq 0 ] || bad "roslaunch exited $status"
grep -q 'replay: end of the bag' "$tmp/launch.out" || bad "no 'replay: end of the bag' line"
grep -q 'replay: /use_sim_time deleted' "$tmp/launch.out" || bad "/use_sim_time left set on the master"
! grep -q 'REQUIRED process' "$tmp/launch.out" || bad "'REQUIRED process ... has died' in the output"
! grep -q "is not in TF" "$tmp/launch.out" || bad "a 'not in TF' warning in the output"
n_reports=$(grep -cE '^[0-9]+,' "$tmp/reports.csv" || true)
echo "StrikeReports: $n_reports"
[ "$n_reports" -eq 3 ] || bad "$n_reports StrikeReports, expected 3"
n_advice=$(grep -cE '^[0-9]+,' "$tmp/advice.csv" || true)
echo "StrikeAdvice: $n_advice"; sed 's/^/  /' "$tmp/advice.csv"
[ "$n_advice" -ge 3 ] || bad "$n_advice StrikeAdvice, expected at least 3"
! grep -q 'strike point unknown' "$tmp/advice.csv" || bad "an apple's strike point is unknown (TF)"
af_check_stopped "$port" || fail=1
[ "$fail" -eq 0 ] && echo "test_replay_launch: passed"
exit "$fail"
