#!/usr/bin/env bash
# The replay demo: builds if needed, makes a bag of synthetic strikes with
# strike_bag (force at 50 kHz, audio at 48 kHz, an AppleEstimate before each
# strike; the truth beside it), replays it through the station with
#   roslaunch acoustic_firmness replay.launch bag:=...
# and prints one line per measured strike (StrikeReport + measured
# Reliability) against the truth it was made from, then a summary.
#
#   bash scripts/demo.sh [--strikes N] [--seed S] [--rate R] [--keep DIR]
#
# Runs its own ROS master on port $AF_DEMO_PORT (default 11345, so that it
# leaves a master on 11311 alone) and stops it (by PID) on exit. --keep DIR
# keeps the bag, the truth CSV and the logs in DIR.
set -euo pipefail
source "$(dirname "$0")/env.sh"

strikes=20 seed=1 rate=1 keep=""
while [ $# -gt 0 ]; do
  case "$1" in
    --strikes) strikes=$2; shift 2 ;;
    --seed) seed=$2; shift 2 ;;
    --rate) rate=$2; shift 2 ;;
    --keep) keep=$2; shift 2 ;;
    *) echo "demo.sh: unknown argument $1 (--strikes N, --seed S, --rate R, --keep DIR)" >&2; exit 2 ;;
  esac
done

af_ensure_station_built

port=${AF_DEMO_PORT:-11345}
unset ROS_NAMESPACE
work=$(mktemp -d /tmp/af_demo.XXXXXX)
core_pid="" summary_pid=""
cleanup() {
  [ -n "$summary_pid" ] && kill "$summary_pid" 2>/dev/null || true
  if [ -n "$core_pid" ]; then
    kill "$core_pid" 2>/dev/null || true
    wait "$core_pid" 2>/dev/null || true
  fi
  if [ -n "$keep" ]; then
    mkdir -p "$keep" && cp -r "$work"/. "$keep"/ && echo "demo: bag, truth and logs kept in $keep"
  fi
  rm -rf "$work"
}
trap cleanup EXIT

"$AF_DEVEL/lib/acoustic_firmness/strike_bag" --strikes "$strikes" --seed "$seed" --out "$work/demo.bag"

af_start_master "$port" "$work/roscore.log" || { core_pid=$AF_MASTER_PID; exit 1; }
core_pid=$AF_MASTER_PID

# The summary: one line per strike, as the node publishes them.
cat >"$work/summary.py" <<'EOF'
import csv, math, signal, sys, threading
import rospy
from acoustic_firmness.msg import Reliability, StrikeReport

truth = {int(r['apple_id']): r for r in csv.DictReader(open(sys.argv[1]))}
expected = int(sys.argv[2])
lock = threading.Lock()
reports, reliabilities, printed = {}, {}, []
done = threading.Event()


def pct(x, ref):
    return 100.0 * (x / ref - 1.0)


def show(key):
    r, rel = reports.pop(key), reliabilities.pop(key)
    t = truth.get(r.apple_id)
    if t is None:
        line = 'strike at %.4f s: apple %d (no truth)' % (r.header.stamp.to_sec(), r.apple_id)
    else:
        f, tc, e2 = float(t['resonance_hz']), float(t['contact_time_s']), float(t['modulus_pa'])
        line = ('apple %3d: 0S2 %6.1f Hz (truth %6.1f, %+5.2f %%), t_c %.3f ms (%+5.2f %%), '
                'E2 fit %5.2f MPa / from 0S2 %5.2f MPa (truth %5.2f), e %.3f, %.0f N' % (
                    r.apple_id, r.resonance, f, pct(r.resonance, f), r.contact_time * 1e3,
                    pct(r.contact_time, tc), r.fitted_modulus * 1e-6, r.modulus_from_resonance * 1e-6,
                    e2 * 1e-6, r.fitted_restitution, r.peak_force))
        printed.append((pct(r.resonance, f), pct(r.contact_time, tc), pct(r.fitted_modulus, e2),
                        rel.reliable))
    print(line + (': reliable' if rel.reliable else ': NOT reliable (%s)' % rel.reason), flush=True)
    if len(printed) >= expected:
        done.set()


def on_report(msg):
    with lock:
        key = (msg.header.stamp, msg.apple_id)
        reports[key] = msg
        if key in reliabilities:
            show(key)


def on_reliability(msg):
    if msg.source != 'measured':
        return
    with lock:
        key = (msg.header.stamp, msg.apple_id)
        reliabilities[key] = msg
        if key in reports:
            show(key)


rospy.init_node('demo_summary', disable_signals=True)
rospy.Subscriber('/lane1/strike_report', StrikeReport, on_report, queue_size=100)
rospy.Subscriber('/lane1/reliability', Reliability, on_reliability, queue_size=100)
signal.signal(signal.SIGTERM, lambda *_: done.set())
signal.signal(signal.SIGINT, lambda *_: done.set())
while not done.wait(0.2):
    pass
n = len(printed)
if n:
    def worst(i):
        return max(abs(p[i]) for p in printed)
    print('demo: %d of %d strikes reported; max |error| vs truth: 0S2 %.2f %%, contact time %.2f %%, '
          'fitted E2 %.2f %%; %d reliable' % (n, expected, worst(0), worst(1), worst(2),
                                              sum(p[3] for p in printed)), flush=True)
else:
    print('demo: no strike reported', flush=True)
rospy.signal_shutdown('done')
sys.exit(0 if n == expected else 1)
EOF
/usr/bin/python3 "$work/summary.py" "$work/demo.truth.csv" "$strikes" &
summary_pid=$!

echo "demo: roslaunch acoustic_firmness replay.launch bag:=$work/demo.bag rate:=$rate (log in $work/launch.log)"
roslaunch acoustic_firmness replay.launch bag:="$work/demo.bag" rate:="$rate" >"$work/launch.log" 2>&1 ||
  { tail -20 "$work/launch.log"; exit 1; }
# The last reports follow the end of the bag by a few milliseconds.
for _ in $(seq 50); do
  kill -0 "$summary_pid" 2>/dev/null || break
  sleep 0.1
done
kill -TERM "$summary_pid" 2>/dev/null || true
status=0
wait "$summary_pid" || status=$?
summary_pid=""
exit "$status"
