#!/usr/bin/env bash
# replay_play.sh — the launch-prefix of replay.launch's rosbag play: runs the
# play command it is given, lets the node finish the last strike for
# --linger=S wall seconds, then ends the launch as Ctrl-C would (SIGINT to
# roslaunch, its parent). A clean end of the bag is then a clean end of the
# launch, without the red "REQUIRED process has died" of a required play.
# A play that fails ends the launch too, with its exit status said.
#   launch-prefix="bash $(dirname)/replay_play.sh --linger=2"
set -u
linger_s=2
case "${1:-}" in --linger=*) linger_s=${1#--linger=}; shift ;; esac
"$@"
status=$?
if [ "$status" -ne 0 ]; then
  echo "replay: rosbag play exited with status $status; stopping the launch" >&2
else
  echo "replay: end of the bag; stopping the launch in ${linger_s} s"
fi
sleep "$linger_s"
kill -INT "$PPID"
exit "$status"
