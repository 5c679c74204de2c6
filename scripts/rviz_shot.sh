#!/usr/bin/env bash
# What an operator sees in rviz (config/station.rviz), headless under Xvfb:
# a few strikes of a strike_bag replayed on simulated time through
# station.launch (lane1, with robot_state_publisher), then a screenshot: the
# rig (RobotModel), the last apple's markers and its measured line, the
# diagnostic status over the rig, the last strike's picture (strike_plot)
# beside the 3D view, and the Displays panel (no warning expected).
# The test command runs it with 2 strikes (scripts_readme_scripts); rviz and
# Xvfb are installed here by setup.sh --rviz (ImageMagick by setup.sh).
# Usage: bash scripts/rviz_shot.sh [OUT.png]   (default doc/rviz.png)
#   AF_RVIZ_STRIKES=N (5) strikes replayed; AF_RVIZ_LOG=DIR keeps the logs there;
#   AF_RVIZ_PORT=P the master's port (default: a random one in 20000-39999).
set -euo pipefail
source "$(dirname "$0")/env.sh"
bash "$AF_ROOT/scripts/setup.sh" --rviz
[ -x "$AF_DEVEL/lib/acoustic_firmness/firmness_node" ] || bash "$AF_ROOT/scripts/build.sh"
af_source_devel
out=${1:-$AF_ROOT/doc/rviz.png}
strikes=${AF_RVIZ_STRIKES:-5}
tmp=$(mktemp -d /tmp/af_rviz_shot.XXXXXX)
log=${AF_RVIZ_LOG:-$tmp}
mkdir -p "$log"
port=${AF_RVIZ_PORT:-$((20000 + RANDOM % 20000))}
export ROS_MASTER_URI=http://localhost:$port LIBGL_ALWAYS_SOFTWARE=1
pids=()
cleanup() {
  local p
  for ((k = ${#pids[@]} - 1; k >= 0; k--)); do
    p=${pids[k]}
    kill -INT "$p" 2>/dev/null || true
    for _ in 1 2 3 4 5 6 7 8 9 10; do kill -0 "$p" 2>/dev/null || break; sleep 0.5; done
    kill "$p" 2>/dev/null || true
  done
  wait 2>/dev/null || true
  [ -n "${AF_RVIZ_LOG:-}" ] || rm -rf "$tmp"
}
trap cleanup EXIT

"$AF_DEVEL/lib/acoustic_firmness/strike_bag" --strikes "$strikes" --seed 3 --spacing 1.0 \
  --out "$tmp/shot.bag" >"$log/strike_bag.log"
roscore -p "$port" >"$log/roscore.log" 2>&1 &
pids+=($!)
# Xvfb takes the first free display and writes its number to fd 3 once it
# accepts clients (no fixed number that another X server may hold).
Xvfb -displayfd 3 -screen 0 1600x860x24 3>"$tmp/display" >"$log/xvfb.log" 2>&1 &
pids+=($!)
for _ in $(seq 100); do rosparam list >/dev/null 2>&1 && break; sleep 0.2; done
for _ in $(seq 100); do [ -s "$tmp/display" ] && break; sleep 0.2; done
[ -s "$tmp/display" ] || { cat "$log/xvfb.log" >&2; echo "rviz_shot: Xvfb did not start" >&2; exit 1; }
DISPLAY=:$(head -n 1 "$tmp/display")
export DISPLAY
# Simulated time, as replay.launch sets it, before any node starts.
rosparam set /use_sim_time true
roslaunch acoustic_firmness station.launch ns:=lane1 >"$log/station.log" 2>&1 &
pids+=($!)
rviz -d "$AF_ROOT/config/station.rviz" >"$log/rviz.log" 2>&1 &
pids+=($!)
# The replay starts once rviz takes the node's markers and the node is
# connected to the player on every topic of the bag, however long the start
# takes on a loaded machine (no fixed wait).
af_wait_subscriber /lane1/markers /rviz 120
/usr/bin/python3 "$AF_ROOT/scripts/play_connected.py" --wait /lane1/firmness_node --timeout 120 -- \
  --clock -q "$tmp/shot.bag" >"$log/play.log" 2>&1
# rviz draws at its frame rate on the last clock; the node's status marker
# came with the last diagnostics.
sleep 4
mkdir -p "$(dirname "$out")"
import -window root "$out"
echo "rviz_shot: wrote $out ($strikes strikes replayed; logs in $log)"
