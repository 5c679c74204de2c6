#!/usr/bin/env bash
# firmness_report against the node on the same recording, apple by apple:
# a bag of N synthetic strikes (strike_bag, default 1000, seed 5) is replayed
# through station.launch on simulated time (rosbag play --clock, rate
# AF_REPLAY_RATE = 5) on a master of our own (port AF_REPORT_PORT = 11346),
# the node's StrikeReport and measured Reliability messages are recorded, and
# firmness_report --json of the same bag must give the same strikes, apple
# ids, verdicts, reasons and grades, and every figure the same double (every
# field of both messages in the report's field that firmness_report --fields
# maps to it, serialize.h).
#   bash scripts/report_vs_node.sh [N] [SEED]
# Exit 0 when they agree. The strikes rostest does the same on 100 strikes.
set -euo pipefail
source "$(dirname "$0")/env.sh"
af_ensure_station_built
N=${1:-1000}
SEED=${2:-5}
RATE=${AF_REPLAY_RATE:-5}
lib="$AF_DEVEL/lib/acoustic_firmness"
tmp=$(mktemp -d)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -INT "$p" 2>/dev/null || true; done
  sleep 1
  [ -n "${AF_MASTER_PID:-}" ] && kill "$AF_MASTER_PID" 2>/dev/null || true
  rm -rf "$tmp"
}
trap cleanup EXIT
"$lib/strike_bag" --strikes "$N" --seed "$SEED" --out "$tmp/in.bag"
af_start_master "${AF_REPORT_PORT:-11346}" "$tmp/master.log"
rosparam set /use_sim_time true
roslaunch acoustic_firmness station.launch ns:=lane1 >"$tmp/launch.log" 2>&1 &
pids+=($!)
af_wait_node /lane1/firmness_node
echo "report_vs_node: replaying $N strikes at ${RATE}x through the node"
af_replay_record "$tmp/in.bag" "$tmp/out.bag" lane1 "$RATE"
"$lib/firmness_report" "$tmp/in.bag" --json --bench >"$tmp/report.json"
/usr/bin/python3 "$(dirname "$0")/node_vs_report.py" "$tmp/report.json" "$tmp/out.bag" "$N" \
  "$lib/firmness_report"
