#!/usr/bin/env bash
# The report's fields against the node's messages, field by field: a small
# strike_bag bag (16 strikes, seed 3) replayed with rosbag play --clock
# through station.launch on a master of our own (a free port), the node's
# StrikeReport and measured Reliability recorded; firmness_report --json and
# --csv of the same bag. scripts/node_vs_report.py: for every field of both
# messages, the JSON strike's field that firmness_report --fields --json maps
# to it (resonance_hz: StrikeReport.resonance) has the same value (every real
# the same double), and every other field of the JSON strike is a
# report-only row of that table or one of firmness_report's apple fields. The CSV
# has the same columns as the JSON's keys (predicted's flattened) and the
# same values. No process of ours may outlive the test. Registered as
# scripts_report_fields.
set -euo pipefail
source "$(dirname "$0")/harness.sh"
lib="$AF_DEVEL/lib/acoustic_firmness"
for exe in strike_bag firmness_report firmness_node; do
  [ -x "$lib/$exe" ] || { echo "test_report_fields: $lib/$exe missing (built?)" >&2; exit 1; }
done
N=16
"$lib/strike_bag" --strikes $N --seed 3 --out "$tmp/in.bag" >/dev/null

port=$(af_free_port)
af_start_master "$port" "$tmp/master.log"
rosparam set /use_sim_time true
roslaunch acoustic_firmness station.launch ns:=lane1 >"$tmp/launch.log" 2>&1 &
pids+=("$!")
af_wait_node /lane1/firmness_node || fail=1
af_replay_record "$tmp/in.bag" "$tmp/out.bag" lane1 || fail=1
af_stop_all
af_check_stopped "$port" || fail=1

"$lib/firmness_report" "$tmp/in.bag" --json --csv "$tmp/report.csv" >"$tmp/report.json"
/usr/bin/python3 "$AF_ROOT/scripts/node_vs_report.py" "$tmp/report.json" "$tmp/out.bag" $N \
  "$lib/firmness_report" || bad "node and firmness_report differ"

/usr/bin/python3 - "$tmp/report.json" "$tmp/report.csv" <<'PY' || bad "the CSV differs from the JSON"
import csv, json, math, sys
strikes = json.load(open(sys.argv[1]))['strikes']
rows = list(csv.DictReader(open(sys.argv[2])))
assert len(rows) == len(strikes) > 0, (len(rows), len(strikes))
checked = 0
for o, r in zip(strikes, rows):
    keys = [k for k in o if k != 'predicted'] + ['predicted_' + k for k in
                                                  ('band_low_hz', 'band_high_hz', 'resonance_hz', 'reliable')]
    assert list(r) == keys, ('columns', list(r), keys)
    for k, v in o.items():
        if k == 'predicted':
            continue
        c = r[k]
        if v is None:
            assert c == '', (k, c)
        elif isinstance(v, bool):
            assert c == ('1' if v else '0'), (k, v, c)
        elif isinstance(v, list):
            assert c == '|'.join(v), (k, v, c)
        elif isinstance(v, int):
            assert int(c) == v, (k, v, c)
        elif isinstance(v, float):
            assert float(c) == v, (k, v, c)
        else:
            assert c == v, (k, v, c)
        checked += 1
print('report_fields: CSV and JSON: %d strikes, %d values, the same' % (len(rows), checked))
PY
[ "$fail" -eq 0 ] || { echo "launch log:" >&2; tail -20 "$tmp/launch.log" >&2; }
exit "$fail"
