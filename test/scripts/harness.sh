# shellcheck shell=bash
# Sourced by the script tests (test/scripts/test_*.sh): the package's scripts
# environment against the build under test, a scratch folder, a free master
# port, and the check that no process of ours outlives the test.
#
# ctest passes the build under test as AF_BUILD_DIR and AF_DEVEL_DIR (see
# CMakeLists.txt); AF_NO_BUILD=1 makes the scripts fail, rather than build,
# when an executable is missing, so that a test never runs a build.
# shellcheck disable=SC1091
source "$(dirname "${BASH_SOURCE[0]}")/../../scripts/env.sh"
export AF_NO_BUILD=1
af_source_devel
unset ROS_NAMESPACE
tmp=$(mktemp -d /tmp/af_script_test.XXXXXX)
# Logs of every roscore/roslaunch of the test stay in the scratch folder.
export ROS_HOME=$tmp/ros_home ROS_LOG_DIR=$tmp/ros_home/log
# The processes a test starts in the background go into pids; af_stop_all
# stops them (SIGINT, as Ctrl-C) and the master of af_start_master, and
# runs on exit too.
pids=()
af_stop_all() {
  local p
  for p in "${pids[@]}"; do kill -INT "$p" 2>/dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done
  [ -n "${AF_MASTER_PID:-}" ] && kill "$AF_MASTER_PID" 2>/dev/null && wait "$AF_MASTER_PID" 2>/dev/null
  pids=()
  AF_MASTER_PID=""
}
trap 'af_stop_all; rm -rf "$tmp"' EXIT

# Prints a TCP port that is free now, in 20000-29999: away from the default
# master (11311), the demo's and bench's (11345, 11346) and the kernel's
# ephemeral ports, so another engineer's master or a rostest cannot hold it.
af_free_port() {
  /usr/bin/python3 - <<'PY'
import random, socket
for _ in range(200):
    port = random.randint(20000, 29999)
    with socket.socket() as s:
        try:
            s.bind(('', port))
        except OSError:
            continue
    print(port)
    break
else:
    raise SystemExit('no free port in 20000-29999')
PY
}

# Prints the PIDs of the processes started with ROS_MASTER_URI on port $1 in
# their environment: the master, the launch, the nodes, rosbag, any client
# (every one of them was started by the test under test on that port).
af_processes_on_port() {
  local want="ROS_MASTER_URI=http://localhost:$1" dir pid
  for dir in /proc/[0-9]*; do
    pid=${dir#/proc/}
    [ "$pid" = "$$" ] && continue
    tr '\0' '\n' 2>/dev/null <"/proc/$pid/environ" | grep -qxF "$want" && echo "$pid"
  done
  return 0
}

# Fails (status 1, naming them) when processes of port $1 are still running
# 10 s after the command under test ended, and then stops them by PID.
af_check_stopped() {
  local port=$1 left=""
  for _ in $(seq 50); do
    left=$(af_processes_on_port "$port")
    [ -z "$left" ] && return 0
    sleep 0.2
  done
  echo "FAIL: processes left running on master port $port:" >&2
  for pid in $left; do
    echo "  $pid: $(tr '\0' ' ' 2>/dev/null <"/proc/$pid/cmdline")" >&2
  done
  # shellcheck disable=SC2086
  kill $left 2>/dev/null || true
  return 1
}

# The test's verdict: bad names a problem and marks the test failed.
fail=0
bad() {
  fail=1
  echo "FAIL: $*" >&2
}

# Runs a package script on a master port of its own, as a user would:
#   af_run_script PORT_VAR SECONDS OUT SCRIPT [ARGS...]
# sets $port to a free port and PORT_VAR=$port in the script's environment,
# runs `bash scripts/SCRIPT ARGS` within SECONDS (timeout signals its whole
# process group on a hang, killed 5 s later), keeps and prints its output in
# OUT, and calls bad when it exits non-zero. The caller then checks OUT and
# af_check_stopped "$port".
af_run_script() {
  local var=$1 seconds=$2 out=$3 script=$4 status=0
  shift 4
  port=$(af_free_port)
  env "$var=$port" timeout -k 5 "$seconds" bash "$AF_ROOT/scripts/$script" "$@" >"$out" 2>&1 ||
    status=$?
  cat "$out"
  [ "$status" -eq 0 ] || bad "scripts/$script $* exited $status"
}
