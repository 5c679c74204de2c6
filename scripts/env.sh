# Sourced by the other scripts: where the package and its build live, and the
# ROS environment of the build's devel space.
AF_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
AF_BUILD=${AF_BUILD_DIR:-$AF_ROOT/build}
# A pyenv python3 first in PATH breaks catkin and rostest: Debian's ROS is
# built for /usr/bin/python3.
export PATH=/usr/bin:$PATH
af_source_devel() {
  # shellcheck disable=SC1091
  set +u
  source "$AF_BUILD/devel/setup.bash"
  set -u
}

# Builds (after installing what is missing) unless the node and strike_bag
# are already in the build's devel space, then sources it.
af_ensure_station_built() {
  local lib="$AF_BUILD/devel/lib/acoustic_firmness"
  if [ ! -x "$lib/firmness_node" ] || [ ! -x "$lib/strike_bag" ]; then
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
