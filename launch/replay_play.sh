#!/usr/bin/env bash
# replay_play.sh — the launch-prefix of replay.launch's rosbag play: runs the
# play command it is given, lets the node finish the last strike for
# --linger=S wall seconds, then ends the launch as Ctrl-C would (SIGINT to
# roslaunch, its parent). A clean end of the bag is then a clean end of the
# launch, without the red "REQUIRED process has died" of a required play.
# A play that fails ends the launch too, with its exit status said.
# The launch set /use_sim_time on the master: every node started there after
# it follows the bag's clock. Nodes already running on the master are named
# (they keep their clock but share the master with a replay), and at the end
# /use_sim_time is deleted, so that a node started later runs on wall time.
#   launch-prefix="bash $(dirname)/replay_play.sh --linger=2 --ns=lane1"
set -u
linger_s=2
ns=
while :; do
  case "${1:-}" in
  --linger=*) linger_s=${1#--linger=}; shift ;;
  --ns=*) ns=${1#--ns=}; shift ;;
  *) break ;;
  esac
done
others=$(rosnode list 2>/dev/null | grep -v -e "^/${ns}/" -e '^/rosout$' -e '^/diagnostic_aggregator$' \
  -e '^/replay$' -e '^/rostopic_' -e '^/record_' | tr '\n' ' ')
if [ -n "$others" ]; then
  echo "replay: the master also runs ${others% } (they keep their clock; a node started here while the bag plays follows its simulated clock)" >&2
fi
"$@"
status=$?
if [ "$status" -ne 0 ]; then
  echo "replay: rosbag play exited with status $status; stopping the launch" >&2
else
  echo "replay: end of the bag; stopping the launch in ${linger_s} s"
fi
sleep "$linger_s"
if rosparam delete /use_sim_time 2>/dev/null; then
  echo "replay: /use_sim_time deleted: nodes started on this master from now run on wall time"
fi
kill -INT "$PPID"
exit "$status"
