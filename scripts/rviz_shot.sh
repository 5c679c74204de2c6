#!/usr/bin/env bash
# Renders what an operator sees in rviz (config/station.rviz) headless under
# Xvfb and saves a screenshot: the station node answers one apple estimate on
# lane1, rviz draws its markers. Not part of the test command.
# Usage: bash scripts/rviz_shot.sh [OUT.png]   (default build/station.png)
set -euo pipefail
source "$(dirname "$0")/env.sh"
bash "$AF_ROOT/scripts/setup.sh" --rviz
[ -x "$AF_DEVEL/lib/acoustic_firmness/firmness_node" ] || bash "$AF_ROOT/scripts/build.sh"
af_source_devel
out=${1:-$AF_BUILD/station.png}
port=$((20000 + RANDOM % 20000))
display=:$((50 + RANDOM % 40))
export ROS_MASTER_URI=http://localhost:$port DISPLAY=$display LIBGL_ALWAYS_SOFTWARE=1
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; wait 2>/dev/null || true; }
trap cleanup EXIT

roscore -p "$port" >/tmp/af_rviz_roscore.log 2>&1 &
pids+=($!)
Xvfb "$display" -screen 0 1280x800x24 >/tmp/af_rviz_xvfb.log 2>&1 &
pids+=($!)
sleep 3
roslaunch acoustic_firmness station.launch ns:=lane1 >/tmp/af_rviz_station.log 2>&1 &
pids+=($!)
rviz -d "$AF_ROOT/config/station.rviz" >/tmp/af_rviz.log 2>&1 &
pids+=($!)
sleep 6
# An apple whose stem leans 45 degrees: the node advises a rotation.
rostopic pub -r 1 /lane1/apple acoustic_firmness/AppleEstimate \
  "{header: {stamp: now, frame_id: camera_optical_frame}, apple_id: 7, mass: 0.175, equatorial_radius: 0.040, strike_radius: 0.0, stem_axis: {x: 1.0, y: 0.0, z: -1.0}, confidence: 0.9}" \
  >/dev/null 2>&1 &
pids+=($!)
sleep 8
import -window root "$out"
echo "rviz_shot: wrote $out"
