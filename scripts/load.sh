#!/usr/bin/env bash
# Load test of the station node (not part of the default tests:
# the ctest test scripts_load runs it in a short mode). Makes a strike bag
# (strike_bag, 1000 strikes by default: 501 s of recorded time) and replays
# it through a fresh node at each rate (rosbag play --clock -r RATE on
# simulated time), counting StrikeReports against the bag's truth with the
# apple each was judged against: lost, misattributed, and whether the node
# said so itself (the strike's reason, /diagnostics); the node's RSS every
# second; the latency from the strike's last needed sample to its report
# (scripts/load_replay.py says how each is measured). With --max, the rate
# doubles after the listed ones until the first strike is lost or
# misattributed (at most 1280x): the highest rate with none is the highest
# this machine sustains.
#
#   bash scripts/load.sh [--strikes N] [--rates "1 10 20"] [--max] [--seed S]
#                        [--spacing S] [--bag FILE --truth FILE] [--keep DIR]
#
# Exit 0 when every listed rate lost and misattributed nothing (the --max
# search is allowed to find the limit). Runs its own master on
# $AF_LOAD_PORT (default 11347); stops it and everything it started by PID.
set -euo pipefail
source "$(dirname "$0")/env.sh"

strikes=1000
rates="1 10 20"
search=0
seed=5
spacing=0.5
bag=""
truth=""
keep=""
while [ $# -gt 0 ]; do
  case "$1" in
    --strikes) strikes=${2:?}; shift 2 ;;
    --rates) rates=${2:?}; shift 2 ;;
    --max) search=1; shift ;;
    --seed) seed=${2:?}; shift 2 ;;
    --spacing) spacing=${2:?}; shift 2 ;;
    --bag) bag=${2:?}; shift 2 ;;
    --truth) truth=${2:?}; shift 2 ;;
    --keep) keep=${2:?}; shift 2 ;;
    *) echo "load.sh: unknown argument '$1' (see the header of $0)" >&2; exit 2 ;;
  esac
done

af_ensure_station_built
port=${AF_LOAD_PORT:-11347}
unset ROS_NAMESPACE
work=${keep:-$(mktemp -d /tmp/af_load.XXXXXX)}
mkdir -p "$work"
core_pid=""
cleanup() {
  if [ -n "$core_pid" ]; then
    kill "$core_pid" 2>/dev/null || true
    wait "$core_pid" 2>/dev/null || true
  fi
  [ -n "$keep" ] || rm -rf "$work"
}
trap cleanup EXIT

if [ -z "$bag" ]; then
  bag=$work/load.bag
  truth=$work/load.truth.csv
  t0=$(date +%s)
  "$AF_DEVEL/lib/acoustic_firmness/strike_bag" --strikes "$strikes" --seed "$seed" --spacing "$spacing" \
    --out "$bag" --truth "$truth"
  echo "load: $strikes strikes, $(du -m "$bag" | cut -f1) MB bag made in $(($(date +%s) - t0)) s"
fi
[ -n "$truth" ] || truth=${bag%.bag}.truth.csv

af_start_master "$port" "$work/roscore.log" || { core_pid=$AF_MASTER_PID; exit 1; }
core_pid=$AF_MASTER_PID
rosparam set /use_sim_time true

status=0
run() {
  /usr/bin/python3 "$AF_ROOT/scripts/load_replay.py" "$bag" "$truth" "$1" "$work/rate_$1.json"
}
bad_at() { # lost + misattributed at rate $1
  /usr/bin/python3 -c "import json; d = json.load(open('$work/rate_$1.json')); print(d['lost'] + d['misattributed'])"
}
last=1
for r in $rates; do
  run "$r" || status=1
  [ -f "$work/rate_$r.json" ] && [ "$(bad_at "$r")" -eq 0 ] || status=1
  last=$r
done
if [ "$search" = 1 ]; then
  sustained=""
  r=$((last * 2))
  while [ "$r" -le 1280 ]; do
    run "$r" || break
    if [ "$(bad_at "$r")" -gt 0 ]; then
      echo "load: first strike lost or misattributed at ${r}x; highest rate without: ${sustained:-${last}}x"
      break
    fi
    sustained=$r
    r=$((r * 2))
  done
fi
exit "$status"
