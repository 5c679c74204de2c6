#!/usr/bin/env bash
# valgrind memcheck (not part of the default tests: the ctest test
# scripts_valgrind runs it with --short) on the default build:
#   1. firmness_model --json (one strike, the R2_min search included);
#   2. firmness_model analyze on the real impact-hammer capture
#      test/data/hammer_capture_4 (25.6 kHz force and microphone);
#   3. firmness_node under valgrind on a short replay (strike_bag, N strikes,
#      rosbag play --clock on simulated time), stopped with SIGINT as
#      roslaunch stops it.
# Each must show no memcheck error and no definitely-lost block
# (--leak-check=full; possibly-lost and still-reachable blocks are listed in
# the logs but are the libraries' caches: roscpp's, FFTW's plans, GSL's).
# Prints the figures of each run; exit 1 on any error or definite leak.
#
#   bash scripts/valgrind.sh [--strikes N] [--short] [--keep DIR]
#
# --short: 2 strikes (the test); default 6. Runs its own master on
# $AF_VALGRIND_PORT (default 11348), stopped by PID.
set -euo pipefail
source "$(dirname "$0")/env.sh"
strikes=6
keep=""
while [ $# -gt 0 ]; do
  case "$1" in
    --strikes) strikes=${2:?}; shift 2 ;;
    --short) strikes=2; shift ;;
    --keep) keep=${2:?}; shift 2 ;;
    *) echo "valgrind.sh: unknown argument '$1' (see the header of $0)" >&2; exit 2 ;;
  esac
done
command -v valgrind >/dev/null || { echo "valgrind.sh: valgrind is not installed (scripts/setup.sh)" >&2; exit 1; }
af_ensure_station_built
lib="$AF_DEVEL/lib/acoustic_firmness"
work=${keep:-$(mktemp -d /tmp/af_valgrind.XXXXXX)}
mkdir -p "$work"
core_pid="" node_pid="" play_pid=""
cleanup() {
  for pid in $play_pid $node_pid $core_pid; do
    kill "$pid" 2>/dev/null || true
    wait "$pid" 2>/dev/null || true
  done
  [ -n "$keep" ] || rm -rf "$work"
}
trap cleanup EXIT

vg=(valgrind --tool=memcheck --leak-check=full --show-leak-kinds=definite,indirect
  --errors-for-leak-kinds=definite --track-origins=yes --num-callers=30)
status=0
# summary NAME LOG SECONDS: the error and leak figures of one run.
summary() {
  local errors definite indirect possible
  errors=$(sed -n 's/.*ERROR SUMMARY: \([0-9,]*\) errors.*/\1/p' "$2" | tail -1 | tr -d ,)
  definite=$(sed -n 's/.*definitely lost: \([0-9,]*\) bytes.*/\1/p' "$2" | tail -1 | tr -d ,)
  indirect=$(sed -n 's/.*indirectly lost: \([0-9,]*\) bytes.*/\1/p' "$2" | tail -1 | tr -d ,)
  possible=$(sed -n 's/.*possibly lost: \([0-9,]*\) bytes.*/\1/p' "$2" | tail -1 | tr -d ,)
  printf 'valgrind %-16s %4s s: %s errors, definitely lost %s bytes, indirectly lost %s, possibly lost %s\n' \
    "$1" "$3" "${errors:-?}" "${definite:-0}" "${indirect:-0}" "${possible:-0}"
  if [ "${errors:-1}" != 0 ] || [ "${definite:-0}" != 0 ]; then
    echo "valgrind: $1 has errors or definite leaks (log $2)" >&2
    status=1
  fi
}

t0=$(date +%s)
"${vg[@]}" --log-file="$work/model.log" "$lib/firmness_model" --json >/dev/null
summary firmness_model "$work/model.log" $(($(date +%s) - t0))

data="$AF_ROOT/test/data"
if [ -s "$data/hammer_capture_4.force.f32" ]; then
  t0=$(date +%s)
  "${vg[@]}" --log-file="$work/analyze.log" "$lib/firmness_model" analyze \
    --force "$data/hammer_capture_4.force.f32" --audio "$data/hammer_capture_4.response.f32" \
    --rate-force 25600 --rate-audio 25600 --mass 0.175 --R2 0.04 >/dev/null
  summary analyze "$work/analyze.log" $(($(date +%s) - t0))
else
  echo "valgrind: $data/hammer_capture_4.force.f32 missing: analyze not run" >&2
  status=1
fi

# The node on a short replay.
port=${AF_VALGRIND_PORT:-11348}
unset ROS_NAMESPACE
"$AF_DEVEL/lib/acoustic_firmness/strike_bag" --strikes "$strikes" --seed 9 --out "$work/vg.bag" >/dev/null
af_start_master "$port" "$work/roscore.log" || { core_pid=$AF_MASTER_PID; exit 1; }
core_pid=$AF_MASTER_PID
rosparam set /use_sim_time true
rosparam load "$AF_ROOT/config/station.yaml" /lane1/firmness_node
rosparam load "$AF_ROOT/config/jonagold.yaml" /lane1/firmness_node
rosparam set --textfile="$AF_ROOT/config/rig.urdf" /lane1/robot_description
t0=$(date +%s)
"${vg[@]}" --log-file="$work/node.log" "$lib/firmness_node" __ns:=/lane1 __name:=firmness_node \
  >"$work/node.out" 2>&1 &
node_pid=$!
# valgrind slows the node ~30x: wait for its subscriptions, replay at half speed
for _ in $(seq 300); do
  rostopic info /lane1/force 2>/dev/null | grep -q firmness_node && break
  sleep 0.2
done
cat >"$work/count.py" <<'EOF'
import sys, time, rospy
from acoustic_firmness.msg import StrikeReport
rospy.init_node('vg_count', disable_signals=True)
n = [0]
rospy.Subscriber('/lane1/strike_report', StrikeReport, lambda m: n.__setitem__(0, n[0] + 1), queue_size=100)
end = time.time() + float(sys.argv[2])
while time.time() < end and n[0] < int(sys.argv[1]):
    time.sleep(0.2)
print(n[0])
EOF
/usr/bin/python3 "$work/count.py" "$strikes" 600 >"$work/count.txt" &
count_pid=$!
sleep 1
rosbag play --clock -q --wait-for-subscribers -r 0.5 "$work/vg.bag" >/dev/null 2>&1 &
play_pid=$!
wait "$play_pid" || true
play_pid=""
wait "$count_pid" || true
kill -INT "$node_pid"
wait "$node_pid" || true
node_pid=""
reports=$(cat "$work/count.txt" 2>/dev/null || echo 0)
echo "valgrind: the node reported $reports of $strikes strikes under memcheck"
summary firmness_node "$work/node.log" $(($(date +%s) - t0))
[ "$reports" -ge 1 ] || { echo "valgrind: the node reported no strike" >&2; status=1; }
exit "$status"
