#!/usr/bin/env bash
# Benchmark of the node's measured strikes (not a timed test): replays a bag
# of synthetic strikes (strike_bag: 50 kHz force + 48 kHz audio, one strike
# every 0.5 s: 2 strikes/s; --rate 10: every 0.1 s, a grading line's rate)
# at real time through station.launch and prints
#  - the node's CPU per second of streamed input: its threads' run time
#    from /proc/<pid>/task/*/schedstat [ns] over the replay, divided by the
#    bag's duration
#    (the targets: 1 % of one core at 2 strikes/s, 3 % at 10), and
#    its idle CPU before the replay;
#  - the latency per strike from the last sample it needs (the audio chunk
#    completing its window [start + delay, start + delay + window]) to its
#    StrikeReport, as a subscriber sees the two messages arrive (both through
#    TCP on this host): it includes the lane's deliberate wait for the next
#    apple's estimate (up to apple_wait_s; strike_bag sends it 0.3 s after
#    each strike), so that a late estimate cannot make a strike judged
#    against the wrong apple;
#  - inside the node (target: under 2 ms): from the callback that made the
#    strike decidable (its last audio chunk, the next apple's estimate, or
#    the end of the apple wait) to the publish, from /diagnostics (the last
#    diagnostics on the replay's clock: the last strike may come after).
#
#   bash scripts/bench_node.sh [--seconds S] [--rate R] [--floor]
#     --seconds S  input replayed [s] (default 20)
#     --rate R     strikes per second, 2 or 10 (default 2: strike_bag --spacing 0.5;
#                  10: --spacing 0.1); the last line gives, for that rate, the
#                  node's CPU and its max latency inside the node and end to end
#     --floor      also runs af_bench_floor beside the node, over the same
#                  replay: the node's subscriptions through the same shim,
#                  callbacks that only count (src/bench/bench_floor.c); its CPU
#                  is what roscpp's receive path costs on this machine for
#                  these messages, the floor under the node's figure
#
# Runs its own ROS master on $AF_BENCH_PORT (default 11346) and stops it and
# the node (by PID) on exit.
set -euo pipefail
source "$(dirname "$0")/env.sh"

seconds=20
rate=2
floor=0
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds=${2:?--seconds needs a value [s]}; shift 2 ;;
    --rate) rate=${2:?--rate needs a value: 2 or 10 [strikes/s]}; shift 2 ;;
    --floor) floor=1; shift ;;
    *) echo "bench_node.sh: unknown argument $1 (--seconds S, --rate 2|10, --floor)" >&2; exit 2 ;;
  esac
done
case "$rate" in
  2) spacing=0.5 ;;
  10) spacing=0.1 ;;
  *) echo "bench_node.sh: --rate $rate: 2 or 10 strikes per second" >&2; exit 2 ;;
esac
# strike_bag: 1 s of lead, then one strike every spacing seconds, 0.5 s of tail
strikes=$(/usr/bin/python3 -c "print(max(1, round(($seconds - 1.5) / $spacing)))")

af_ensure_station_built

port=${AF_BENCH_PORT:-11346}
unset ROS_NAMESPACE
work=$(mktemp -d /tmp/af_bench.XXXXXX)
core_pid="" launch_pid="" floor_pid=""
cleanup() {
  for pid in $floor_pid $launch_pid $core_pid; do
    kill "$pid" 2>/dev/null || true
    wait "$pid" 2>/dev/null || true
  done
  rm -rf "$work"
}
trap cleanup EXIT

"$AF_DEVEL/lib/acoustic_firmness/strike_bag" --strikes "$strikes" --spacing "$spacing" --seed 11 \
  --out "$work/bench.bag"
af_start_master "$port" "$work/roscore.log" || { core_pid=$AF_MASTER_PID; exit 1; }
core_pid=$AF_MASTER_PID
rosparam set /use_sim_time true
roslaunch acoustic_firmness station.launch >"$work/launch.log" 2>&1 &
launch_pid=$!
export AF_FLOOR_PID=0
if [ "$floor" = 1 ]; then
  floor_bin="$AF_DEVEL/lib/acoustic_firmness/af_bench_floor"
  [ -x "$floor_bin" ] || { echo "bench_node.sh: --floor needs $floor_bin (bash scripts/build.sh)" >&2; exit 1; }
  "$floor_bin" __ns:=lane1 __name:=bench_floor >"$work/floor.log" 2>&1 &
  floor_pid=$!
  AF_FLOOR_PID=$floor_pid
fi

cat >"$work/bench.py" <<'EOF'
import math, os, re, subprocess, sys, threading, time
import rosgraph, rospy, xmlrpc.client
from acoustic_firmness.msg import SignalChunk, StrikeReport
from diagnostic_msgs.msg import DiagnosticArray

bag, seconds, n_strikes, strike_rate = sys.argv[1], float(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
play_connected = sys.argv[5]   # scripts/play_connected.py
cpu_target = {'2': 1.0, '10': 3.0}[strike_rate]   # the targets [% of one core]
node = '/lane1/firmness_node'
rospy.init_node('bench_node', disable_signals=True)
lock = threading.Lock()
chunks = []    # (first_sample, n, receive wall time)
reports = []   # (msg, receive wall time)
diag = {}


def on_audio(m):
    t = time.time()
    with lock:
        chunks.append((m.first_sample, len(m.data), m.header.stamp.to_sec(), m.sample_rate, t))


def on_report(m):
    t = time.time()
    with lock:
        reports.append((m, t))


def on_diag(m):
    for s in m.status:
        if s.hardware_id == node:
            with lock:
                diag.update({kv.key: kv.value for kv in s.values})


rospy.Subscriber('/lane1/audio', SignalChunk, on_audio, queue_size=1000, tcp_nodelay=True)
rospy.Subscriber('/lane1/strike_report', StrikeReport, on_report, queue_size=100, tcp_nodelay=True)
rospy.Subscriber('/diagnostics', DiagnosticArray, on_diag, queue_size=10)

# The node's PID, from its own XML-RPC API.
master = rosgraph.Master('/bench_node')
end = time.time() + 30.0
pid = None
while time.time() < end and pid is None:
    try:
        _, _, pid = xmlrpc.client.ServerProxy(master.lookupNode(node)).getPid('/bench_node')
    except Exception:
        time.sleep(0.2)
if pid is None:
    sys.exit('bench: %s did not come up' % node)


floor_pid = int(os.environ['AF_FLOOR_PID'])   # af_bench_floor (--floor), else 0


def cpu_of(p):
    """The process's CPU time [s]: the run time of each of its threads from
    /proc/PID/task/TID/schedstat (ns, what the scheduler charged), summed;
    /proc/PID/stat's utime + stime counts whole 10 ms ticks, too coarse for
    the node's few tenths of a percent. A thread that ended between two reads
    takes its time with it: roscpp's threads live as long as the node."""
    total = 0
    for tid in os.listdir('/proc/%d/task' % p):
        try:
            with open('/proc/%d/task/%s/schedstat' % (p, tid)) as f:
                total += int(f.read().split()[0])
        except OSError:   # the thread ended while listed
            pass
    return total * 1e-9


def cpu_s():
    return cpu_of(pid)


def floor_s():
    return cpu_of(floor_pid) if floor_pid else 0.0


delay = rospy.get_param(node + '/measure_audio_delay_s')
window = rospy.get_param(node + '/measure_audio_window_s')
time.sleep(1.0)
c0, w0, f0 = cpu_s(), time.time(), floor_s()
time.sleep(3.0)
idle = (cpu_s() - c0) / (time.time() - w0)
floor_idle = (floor_s() - f0) / (time.time() - w0)

# The replay starts once the node, af_bench_floor (--floor) and this script
# are connected to rosbag play on every topic they take (play_connected.py),
# not after a fixed wait: a subscriber still connecting misses the first
# chunks. The figures count from the first message played.
wait = ['--wait', node] + (['--wait', '/lane1/bench_floor'] if floor_pid else [])
play = subprocess.Popen(['/usr/bin/python3', play_connected] + wait + ['--', '--clock', '-q', bag],
                        stdout=subprocess.PIPE, text=True)
for line in play.stdout:
    if line.startswith('play_connected: playing'):
        break
c0, w0, f0 = cpu_s(), time.time(), floor_s()
for line in play.stdout:
    pass
if play.wait() != 0:
    sys.exit('bench: the replay failed (play_connected.py exited %d)' % play.returncode)
c1, w1, f1 = cpu_s(), time.time(), floor_s()
end = time.time() + 5.0   # the last reports, then the diagnostics after them
while time.time() < end:
    with lock:
        if len(reports) >= n_strikes:
            break
    time.sleep(0.1)
time.sleep(2.5)
cpu = c1 - c0

with lock:
    chunks_, reports_, diag_ = list(chunks), list(reports), dict(diag)
lat = []
for m, t_rx in reports_:
    # The window's last sample, by the node's rule (lane_io.h): the first
    # sample at or after start + delay, then round(window * rate) samples.
    first0, _, stamp0, rate, _ = chunks_[0]
    i0 = math.ceil(first0 + (m.header.stamp.to_sec() + delay - stamp0) * rate - 1e-6)
    i_last = i0 + int(round(window * rate)) - 1
    for first, n, _, _, t_chunk in chunks_:
        if first <= i_last < first + n:   # the chunk that completes the window
            lat.append((t_rx - t_chunk) * 1e3)
            break
lat.sort()


def q(p):
    return lat[min(len(lat) - 1, int(p * len(lat)))] if lat else float('nan')


print('bench: %d strikes in %.1f s of input (force 50 kHz + audio 48 kHz, 1024-sample chunks), '
      'replayed at real time in %.1f s wall' % (len(reports_), seconds, w1 - w0))
print('  node CPU: %.3f s over the replay = %.2f %% of one core per second of streamed input '
      '(target %g %%); idle before the replay %.2f %%' % (cpu, 100.0 * cpu / seconds, cpu_target,
                                                          100.0 * idle))
print('  strike latency, end to end (audio chunk completing the window -> StrikeReport, as a '
      'subscriber sees them, with the wait for the next apple) [ms]: median %.3f, 90 %% %.3f, '
      'max %.3f over %d' % (
          q(0.5), q(0.9), lat[-1] if lat else float('nan'), len(lat)))
if floor_pid:
    print('  floor (af_bench_floor: the same subscriptions, callbacks that only count): %.3f s = '
          '%.2f %% of one core; idle before the replay %.2f %%; the node above it %.2f %%' % (
              f1 - f0, 100.0 * (f1 - f0) / seconds, 100.0 * floor_idle,
              100.0 * (cpu - (f1 - f0)) / seconds))
print('  inside the node (target < 2 ms) [ms]: %s' % diag_.get('strike report latency [ms]', 'n/a'))
print('  strikes %s, without audio %s, queue overflows %s, force gaps %s, audio gaps %s' % (
    diag_.get('strikes'), diag_.get('strikes without audio'), diag_.get('strike queue overflows'),
    diag_.get('force gaps'), diag_.get('audio gaps')))
inside = re.search(r'max ([0-9.]+)', diag_.get('strike report latency [ms]', ''))
print('bench at %s strikes/s: node CPU %.2f %% of one core (target %g %%), max latency inside the '
      'node %s ms (target 2 ms), end to end %.3f ms (with the apple wait)' % (
          strike_rate, 100.0 * cpu / seconds, cpu_target, inside.group(1) if inside else 'n/a',
          lat[-1] if lat else float('nan')))
rospy.signal_shutdown('done')
EOF
/usr/bin/python3 "$work/bench.py" "$work/bench.bag" \
  "$(/usr/bin/python3 -c "print(1.0 + $strikes * $spacing + 0.5)")" "$strikes" "$rate" \
  "$AF_ROOT/scripts/play_connected.py"
if [ -n "$floor_pid" ]; then
  # SIGINT: roscpp's shutdown, after which af_bench_floor prints what it took
  kill -INT "$floor_pid" 2>/dev/null || true
  wait "$floor_pid" 2>/dev/null || true
  floor_pid=""
  grep '^af_bench_floor' "$work/floor.log" | sed 's/^/  /' || true
fi
