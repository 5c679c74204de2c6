#!/usr/bin/env bash
# capture_to_bag's bag through the node, as report_vs_node.sh does with
# strike_bag's: the lab session of test/convert/capture_files.py (the real
# captures 5, 4, 5 at 25.6 kHz as a 16-bit force WAV of python's wave module
# and a float audio WAV, three apples in a CSV) converted, then replayed with
# rosbag play --clock through station.launch (its config with the captures'
# rates) on a master of our own (a free port), the node's StrikeReport and
# measured Reliability recorded; firmness_report on the same bag and config
# must give the same strikes: three, on apples 11, 12, 13, the same contact
# starts, verdicts, reasons, grades and every figure the same double; and the
# contact starts within one sample of the onsets python finds in the captures.
# No process of ours may outlive the test. Registered as scripts_capture_replay.
set -euo pipefail
source "$(dirname "$0")/harness.sh"
lib="$AF_DEVEL/lib/acoustic_firmness"
for exe in capture_to_bag firmness_report firmness_node; do
  [ -x "$lib/$exe" ] || { echo "test_capture_replay: $lib/$exe missing (built?)" >&2; exit 1; }
done
/usr/bin/python3 "$AF_ROOT/test/convert/capture_files.py" "$tmp" "$AF_ROOT/test/data"
"$lib/capture_to_bag" --force "$tmp/force16.wav" --force-scale 100 --audio "$tmp/audio32.wav" \
  --apples "$tmp/apples.csv" --out "$tmp/in.bag"
# The station's config with the captures' rates (every other value the shipped one).
sed -e 's/^force_sample_rate_hz: .*/force_sample_rate_hz: 25600.0/' \
  -e 's/^audio_sample_rate_hz: .*/audio_sample_rate_hz: 25600.0/' \
  "$AF_ROOT/config/station.yaml" >"$tmp/station.yaml"
grep -q '^force_sample_rate_hz: 25600.0' "$tmp/station.yaml" || bad "station.yaml: no force_sample_rate_hz line to set"

port=$(af_free_port)
af_start_master "$port" "$tmp/master.log"
rosparam set /use_sim_time true
roslaunch acoustic_firmness station.launch ns:=lane1 config:="$tmp/station.yaml" >"$tmp/launch.log" 2>&1 &
pids+=("$!")
af_wait_node /lane1/firmness_node || fail=1
af_replay_record "$tmp/in.bag" "$tmp/out.bag" lane1 || fail=1
af_stop_all
af_check_stopped "$port" || fail=1

"$lib/firmness_report" "$tmp/in.bag" --config "$tmp/station.yaml" --json >"$tmp/report.json"
/usr/bin/python3 - "$tmp/report.json" "$tmp/out.bag" "$tmp/expect.json" "$AF_ROOT/scripts" \
  "$lib/firmness_report" <<'PY' || bad "node and firmness_report differ"
import json, sys
sys.path.insert(0, sys.argv[4])
from node_vs_report import compare
exp = json.load(open(sys.argv[3]))
offline, bad, worst = compare(sys.argv[1], sys.argv[2], 3, sys.argv[5])
if len(exp['strikes']) != 3:
    bad.append('the captures: %d strikes, expected 3' % len(exp['strikes']))
for (stamp, o), e in zip(sorted(offline.items()), exp['strikes']):
    start_s = stamp * 1e-9 - 1700000000
    if o['apple_id'] != e['apple_id'] or abs(start_s - e['onset_s']) > 1.0 / exp['rate_hz']:
        bad.append('strike at %d: apple %d, start %.7f s; the captures: apple %d, onset %.7f s'
                   % (stamp, o['apple_id'], start_s, e['apple_id'], e['onset_s']))
for stamp, o in sorted(offline.items()):
    print('  apple %d: start %.6f s, peak %.3f N, t_c %.4f ms, 0S2 %.1f Hz, %s'
          % (o['apple_id'], stamp * 1e-9, o['peak_force_n'], o['contact_time_s'] * 1e3,
             o['resonance_hz'], 'reliable' if o['reliable'] else 'not reliable: ' + o['reason']))
print('capture_replay: %d strikes; node and firmness_report: %s; worst relative difference %.3g'
      % (len(offline), 'the same apples, starts, verdicts and reasons' if not bad
         else '%d DIFFERENCES' % len(bad), worst))
for line in bad[:10]:
    print('  ' + line)
sys.exit(1 if bad else 0)
PY
[ "$fail" -eq 0 ] || { echo "launch log:" >&2; tail -20 "$tmp/launch.log" >&2; }
exit "$fail"
