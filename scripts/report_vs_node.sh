#!/usr/bin/env bash
# firmness_report against the node on the same recording, apple by apple:
# a bag of N synthetic strikes (strike_bag, default 1000, seed 5) is replayed
# through station.launch on simulated time (rosbag play --clock, rate
# AF_REPLAY_RATE = 5) on a master of our own (port AF_REPORT_PORT = 11346),
# the node's StrikeReport and measured Reliability messages are recorded, and
# firmness_report --json of the same bag must give the same strikes, apple
# ids, verdicts and reasons, and every figure within 1e-9 relative.
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
for _ in $(seq 100); do
  rosnode list 2>/dev/null | grep -q /lane1/firmness_node && break
  sleep 0.2
done
rosbag record -q -O "$tmp/out.bag" /lane1/strike_report /lane1/reliability __name:=af_report_record \
  >"$tmp/record.log" 2>&1 &
pids+=($!)
# The recorder must be subscribed to both outputs before the first strike is
# played (a loaded machine once stopped it before it had subscribed).
for topic in /lane1/strike_report /lane1/reliability; do
  for i in $(seq 150); do
    rostopic info "$topic" 2>/dev/null | sed -n '/Subscribers:/,$p' | grep -q af_report_record && break
    [ "$i" = 150 ] && { echo "report_vs_node: the recorder never subscribed to $topic" >&2; exit 1; }
    sleep 0.2
  done
done
echo "report_vs_node: replaying $N strikes at ${RATE}x through the node"
rosbag play --clock -q --delay=1 --wait-for-subscribers --rate="$RATE" "$tmp/in.bag" >/dev/null
sleep 1
# The node may still be working through the last strikes: stop the recorder
# once its file has stopped growing for 2 s, then wait for it to close the bag.
last=-1
for _ in $(seq 300); do
  size=$(stat -c %s "$tmp/out.bag.active" 2>/dev/null || echo 0)
  [ "$size" = "$last" ] && [ "$size" != 0 ] && break
  last=$size
  sleep 2
done
kill -INT "${pids[1]}" && wait "${pids[1]}" || true
for i in $(seq 150); do
  [ -f "$tmp/out.bag" ] && break
  [ "$i" = 150 ] && { echo "report_vs_node: rosbag record wrote no $tmp/out.bag" >&2; cat "$tmp/record.log" >&2; exit 1; }
  sleep 0.2
done
"$lib/firmness_report" "$tmp/in.bag" --json --bench >"$tmp/report.json"
/usr/bin/python3 - "$tmp/report.json" "$tmp/out.bag" "$N" <<'PY'
import json, math, sys
import rosbag
rep = json.load(open(sys.argv[1]))
n = int(sys.argv[3])
reports, measured = {}, {}
for topic, m, _ in rosbag.Bag(sys.argv[2]).read_messages():
    if topic.endswith('strike_report'):
        reports[m.header.stamp.to_nsec()] = m
    elif m.source == 'measured':
        measured[m.header.stamp.to_nsec()] = m
offline = {o['stamp_ns']: o for o in rep['strikes']}
fields = (('contact_time', 'contact_time_s'), ('peak_force', 'peak_force_N'), ('impulse', 'impulse_Ns'),
          ('band_low', 'band_low_Hz'), ('band_high', 'band_high_Hz'), ('resonance', 'resonance_Hz'),
          ('resonance_q', 'resonance_q'), ('snr_db', 'snr_dB'), ('stiffness_factor', 'stiffness_factor'),
          ('modulus_from_resonance', 'modulus_from_resonance_Pa'), ('fitted_modulus', 'fitted_modulus_Pa'),
          ('fitted_restitution', 'fitted_restitution'), ('fit_residual', 'fit_residual'))
bad, worst = [], 0.0
if not (len(offline) == len(reports) == len(measured) == n):
    bad.append('counts: report %d, node %d StrikeReports, %d measured Reliabilities, bag %d'
               % (len(offline), len(reports), len(measured), n))
for stamp, o in sorted(offline.items()):
    r, m = reports.get(stamp), measured.get(stamp)
    if r is None or m is None:
        bad.append('strike at %d: not in the node output' % stamp)
        continue
    if r.apple_id != o['apple_id'] or m.reason != o['reason'] or m.reliable != o['reliable'] \
            or m.excites_mode != o['excites_mode'] or m.no_damage != o['no_damage']:
        bad.append('strike at %d: apple/verdict/reason differ' % stamp)
    for f, key in fields:
        a, b = getattr(r, f), o[key]
        if b is None:
            if not math.isnan(a):
                bad.append('%s at %d: node %r, report NaN' % (f, stamp, a))
            continue
        d = abs(a - b) / max(abs(b), 1e-300)
        worst = max(worst, d)
        if d > 1e-9:
            bad.append('%s at %d: node %r, report %r' % (f, stamp, a, b))
rel = sum(o['reliable'] for o in rep['strikes'])
print('report_vs_node: %d strikes, %d reliable; node and firmness_report: %s; worst relative '
      'difference %.3g' % (len(offline), rel, 'the same apples, verdicts and reasons' if not bad
                          else '%d DIFFERENCES' % len(bad), worst))
for line in bad[:10]:
    print('  ' + line)
sys.exit(1 if bad else 0)
PY
