# shellcheck shell=bash
# Sourced by the other scripts: where the package, its build and its devel
# space live, and the ROS environment of that devel space.
#
# Layout (that of a catkin workspace, where build/ and devel/ are siblings):
#   default              build in $AF_ROOT/build, devel space in $AF_ROOT/devel
#   AF_BUILD_DIR=DIR     build in DIR, devel space in DIR_devel beside it
#   AF_DEVEL_DIR=DIR     the devel space in DIR (overrides both)
# The devel space must not lie below $AF_ROOT/build/: rosrun skips every path
# under <package>/build/, so it would find none of the package's executables.
AF_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
AF_BUILD=${AF_BUILD_DIR:-$AF_ROOT/build}
case "$AF_BUILD" in /*) ;; *) AF_BUILD=$PWD/$AF_BUILD ;; esac
AF_BUILD=${AF_BUILD%/}
if [ -n "${AF_DEVEL_DIR:-}" ]; then
  AF_DEVEL=${AF_DEVEL_DIR%/}
  case "$AF_DEVEL" in /*) ;; *) AF_DEVEL=$PWD/$AF_DEVEL ;; esac
elif [ "$AF_BUILD" = "$AF_ROOT/build" ]; then
  AF_DEVEL=$AF_ROOT/devel
else
  AF_DEVEL=${AF_BUILD}_devel
fi
case "$AF_DEVEL/" in
  "$AF_ROOT/build/"*)
    echo "env.sh: devel space $AF_DEVEL is below $AF_ROOT/build/, where rosrun finds nothing;" \
      "set AF_BUILD_DIR or AF_DEVEL_DIR elsewhere" >&2
    return 2
    ;;
esac
# A pyenv python3 first in PATH breaks catkin and rostest: Debian's ROS is
# built for /usr/bin/python3.
export PATH=/usr/bin:$PATH
af_source_devel() {
  set +u
  # shellcheck disable=SC1091
  source "$AF_DEVEL/setup.bash"
  set -u
}

# Builds (after installing what is missing) unless the node and strike_bag
# are already in the devel space, then sources it. With AF_NO_BUILD=1 (the
# script tests, which run against a finished build) a missing executable is
# an error instead.
af_ensure_station_built() {
  local lib="$AF_DEVEL/lib/acoustic_firmness"
  if [ ! -x "$lib/firmness_node" ] || [ ! -x "$lib/strike_bag" ]; then
    if [ "${AF_NO_BUILD:-0}" = 1 ]; then
      echo "firmness_node or strike_bag missing from $lib (AF_NO_BUILD=1: not building)" >&2
      return 1
    fi
    bash "$AF_ROOT/scripts/setup.sh"
    bash "$AF_ROOT/scripts/build.sh"
  fi
  af_source_devel
}

# Starts a ROS master of our own on port $1 (log in $2) and waits until it
# answers; its PID is left in AF_MASTER_PID for the caller to stop.
af_start_master() {
  export ROS_MASTER_URI="http://localhost:$1"
  roscore -p "$1" >"$2" 2>&1 &
  AF_MASTER_PID=$!
  for _ in $(seq 100); do
    rosparam list >/dev/null 2>&1 && return 0
    kill -0 "$AF_MASTER_PID" 2>/dev/null || break
    sleep 0.2
  done
  cat "$2" >&2
  echo "roscore on port $1 did not start" >&2
  return 1
}

# Replays bag $1 through the lane node already running in namespace $3 (on
# the master of ROS_MASTER_URI, /use_sim_time set) and records the node's
# StrikeReport and Reliability into $2 (record log beside it). Rate: $4
# (default 1). The recorder is subscribed before the first message is
# played, stopped once its bag has not grown for 2 s after the end of the
# play (the node may still be deciding the last strikes), and waited for
# until it has closed $2: under SIGINT from a script rosbag's Python wrapper
# exits at once while its recorder is still closing the bag.
af_replay_record() {
  local in=$1 out=$2 ns=$3 rate=${4:-1} topic i size last=-1 rec
  rosbag record -q -O "$out" "/$ns/strike_report" "/$ns/reliability" __name:=af_replay_record \
    >"$out.record.log" 2>&1 &
  rec=$!
  for topic in "/$ns/strike_report" "/$ns/reliability"; do
    for i in $(seq 150); do
      rostopic info "$topic" 2>/dev/null | sed -n '/Subscribers:/,$p' | grep -q af_replay_record && break
      [ "$i" = 150 ] && { echo "af_replay_record: the recorder never subscribed to $topic" >&2; kill -INT "$rec"; return 1; }
      sleep 0.2
    done
  done
  rosbag play --clock -q --delay=1 --wait-for-subscribers --rate="$rate" "$in" >/dev/null
  sleep 1
  for _ in $(seq 300); do
    size=$(stat -c %s "$out.active" 2>/dev/null || echo 0)
    [ "$size" = "$last" ] && [ "$size" != 0 ] && break
    last=$size
    sleep 2
  done
  kill -INT "$rec" 2>/dev/null || true
  wait "$rec" 2>/dev/null || true
  for i in $(seq 150); do
    [ -f "$out" ] && return 0
    sleep 0.2
  done
  echo "af_replay_record: rosbag record wrote no $out" >&2
  cat "$out.record.log" >&2
  return 1
}

# Waits up to 20 s for node $1 (a full name) to register with the master.
af_wait_node() {
  for _ in $(seq 100); do
    rosnode list 2>/dev/null | grep -qx "$1" && return 0
    sleep 0.2
  done
  echo "node $1 did not come up in 20 s" >&2
  return 1
}

# Waits up to $3 s (default 60) until a node whose name starts with $2 is
# registered with the master (ROS_MASTER_URI) as a subscriber of topic $1:
# one Python process polling the master, no fixed sleep.
af_wait_subscriber() {
  /usr/bin/python3 - "$1" "$2" "${3:-60}" <<'PY'
import sys, time
import rosgraph
topic, prefix, seconds = sys.argv[1], sys.argv[2], float(sys.argv[3])
master = rosgraph.Master('/af_wait_subscriber')
end = time.time() + seconds
while time.time() < end:
    try:
        subs = dict(master.getSystemState()[1])
        if any(n.startswith(prefix) for n in subs.get(topic, [])):
            sys.exit(0)
    except Exception:
        pass
    time.sleep(0.1)
sys.exit('no subscriber %s* on %s within %g s' % (prefix, topic, seconds))
PY
}
