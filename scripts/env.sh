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
