#!/usr/bin/env bash
# launch/record.launch end to end: a recorder started beside a lane records
# a replay of a 3-strike strike_bag bag (simulated time, so the recording
# keeps the bag's times); the recording holds the inputs, the node's
# settings snapshot and URDF (latched), /tf_static, /diagnostics and the
# node's StrikeReports, LZ4-compressed; firmness_report on the recording
# says it judges with the recorded settings, and finds the strikes the node
# reported live, apple by apple. Registered in ctest as scripts_record_launch.
set -euo pipefail
source "$(dirname "$0")/harness.sh"

"$AF_DEVEL/lib/acoustic_firmness/strike_bag" --strikes 3 --seed 5 --out "$tmp/s3.bag" >/dev/null
port=$(af_free_port)
af_start_master "$port" "$tmp/master.log"
rosparam set /use_sim_time true
roslaunch -p "$port" acoustic_firmness record.launch ns:=lane1 prefix:="$tmp/rec" \
  >"$tmp/record.out" 2>&1 &
pids+=($!)
recorder=$!
af_wait_subscriber /lane1/force /record_lane1 60
timeout -k 5 90 roslaunch -p "$port" acoustic_firmness replay.launch bag:="$tmp/s3.bag" \
  >"$tmp/launch.out" 2>&1 || bad "replay.launch exited $?: $(tail -n 20 "$tmp/launch.out")"
kill -INT "$recorder"
wait "$recorder" 2>/dev/null || true
pids=()
for _ in $(seq 100); do
  ! ls "$tmp"/rec*.bag.active >/dev/null 2>&1 && ls "$tmp"/rec*.bag >/dev/null 2>&1 && break
  sleep 0.2
done
rec=$(ls "$tmp"/rec*.bag | head -n 1)
[ -n "$rec" ] || bad "record.launch wrote no bag: $(cat "$tmp/record.out")"
/usr/bin/python3 - "$rec" "$tmp/live_ids" <<'PY' || bad "the recording"
import sys, rosbag
bag = rosbag.Bag(sys.argv[1])
info = bag.get_type_and_topic_info()
topics = {t: v.message_count for t, v in info.topics.items()}
print('recorded:', ', '.join('%s %d' % kv for kv in sorted(topics.items())))
need = ['/lane1/force', '/lane1/audio', '/lane1/apple', '/lane1/settings', '/lane1/robot_description',
        '/tf_static', '/diagnostics', '/lane1/strike_report']
missing = [t for t in need if topics.get(t, 0) == 0]
assert not missing, 'not recorded: %s' % missing
assert info.topics['/lane1/settings'].msg_type == 'std_msgs/String'
settings = next(bag.read_messages(topics=['/lane1/settings']))[1].data
rows = dict(l.split(': ', 1) for l in settings.splitlines())
assert rows['modulus_factor'] == '1' and rows['lobe'] == '1', rows
urdf = next(bag.read_messages(topics=['/lane1/robot_description']))[1].data
assert '<robot' in urdf and 'hammer' in urdf, urdf[:200]
chunks = {c.compression for c in bag._chunk_headers.values()}  # rosbag's own index of chunks
assert chunks == {'lz4'}, chunks
ids = [m.apple_id for _, m, _ in bag.read_messages(topics=['/lane1/strike_report'])]
assert len(ids) == 3, ids
open(sys.argv[2], 'w').write(' '.join(map(str, sorted(ids))))
PY
"$AF_DEVEL/lib/acoustic_firmness/firmness_report" "$rec" --json >"$tmp/rep.json" 2>"$tmp/rep.err" ||
  bad "firmness_report on the recording: $(cat "$tmp/rep.err")"
grep -q "settings from /lane1/settings of the bag" "$tmp/rep.err" || bad "the report does not say it used the recorded settings: $(cat "$tmp/rep.err")"
ids=$(/usr/bin/python3 -c 'import json,sys; print(" ".join(map(str, sorted(s["apple_id"] for s in json.load(open(sys.argv[1]))["strikes"]))))' "$tmp/rep.json")
[ "$ids" = "$(cat "$tmp/live_ids")" ] || bad "the report's apples ($ids) are not the node's live ones ($(cat "$tmp/live_ids"))"
af_stop_all
af_check_stopped "$port" || fail=1
[ "$fail" -eq 0 ] && echo "test_record_launch: passed"
exit "$fail"
