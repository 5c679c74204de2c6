#!/usr/bin/env bash
# Installs every Debian package acoustic_firmness needs to build, test and run.
# Idempotent: packages already present are left alone. Needs root (or sudo).
set -euo pipefail

PACKAGES=(
  # toolchain and checks
  build-essential cmake pkg-config clang-format clang-tidy cppcheck catkin-lint
  # the sanitizer stage and the fuzzers (scripts/sanitize.sh, fuzz.sh: clang-14 with
  # ASan, UBSan, libFuzzer), valgrind memcheck (scripts/valgrind.sh)
  clang-14 libclang-rt-14-dev valgrind
  # numerics
  libgsl-dev libfftw3-dev
  # plots (src/plot: PLplot with its cairo PNG/SVG/memory drivers)
  libplplot-dev plplot-driver-cairo
  # ROS 1 from Debian
  catkin python3-catkin-pkg ros-core-dev ros-message-generation ros-message-runtime
  libroscpp-dev librosbag-dev python3-rostest python3-rosbag python3-roslaunch python3-rostopic python3-rosnode python3-rosbag librostest-dev rosbash
  libstd-msgs-dev python3-std-msgs ros-std-msgs libgeometry-msgs-dev python3-geometry-msgs ros-geometry-msgs
  libvisualization-msgs-dev python3-visualization-msgs
  # ~strike_plot (sensor_msgs/Image); the strike geometry through TF: tf2_ros, the rig's
  # frames from robot_state_publisher (+ joint_state_publisher for the hammer's slide)
  libsensor-msgs-dev python3-sensor-msgs libtf2-ros-dev python3-tf2-ros python3-tf2-msgs
  ros-robot-state-publisher joint-state-publisher
  libdiagnostic-msgs-dev python3-diagnostic-msgs libdiagnostic-updater-dev
  # audio_common_msgs on ~audio_input audio_common, subscribed generically (ShapeShifter);
  # its rostest builds the message classes at test time (genpy)
  libtopic-tools-dev python3-genpy
  # dynamic_reconfigure of the criteria, thresholds and grades (its generator and client)
  libdynamic-reconfigure-config-init-mutex-dev python3-dynamic-reconfigure
  # one diagnostic_aggregator per master, the lanes grouped (config/analyzers.yaml)
  libdiagnostic-aggregator-dev libdiagnostic-aggregator-tools
  liburdfdom-dev liburdfdom-headers-dev libtinyxml-dev
  libgtest-dev
  # the node's rostests (Python test nodes)
  python3-rospy python3-rosparam python3-roslib python3-rospkg python3-rosunit
  # scripts/bench_node.sh (the node's PID from its XML-RPC API)
  python3-rosgraph
)

# --rviz: also what scripts/rviz_shot.sh needs (not needed to build or test).
if [ "${1:-}" = "--rviz" ]; then
  PACKAGES+=(rviz xvfb imagemagick)
fi

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -eq 0 ]; then
  echo "setup: all ${#PACKAGES[@]} packages present"
  exit 0
fi
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
echo "setup: installing ${missing[*]}"
$SUDO apt-get update -q
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
