#!/usr/bin/env bash
# Soak test of the station node (not part of the default tests:
# the ctest test scripts_load runs scripts/load.sh in a short mode, the same
# code). Replays HOURS of recorded time (one strike every 0.5 s: 7200 strikes
# an hour, a 1.4 GB bag) through one node at RATE and prints the figures of
# scripts/load.sh: strikes lost and misattributed, what the node said about
# them, RSS every second (growth after warm-up), latency percentiles.
#
#   bash scripts/soak.sh [--hours H] [--rate R] [--keep DIR]
#
# Defaults: 1 hour at 20x (3 minutes of replay after the bag is made).
set -euo pipefail
hours=1
rate=20
keep=()
while [ $# -gt 0 ]; do
  case "$1" in
    --hours) hours=${2:?}; shift 2 ;;
    --rate) rate=${2:?}; shift 2 ;;
    --keep) keep=(--keep "${2:?}"); shift 2 ;;
    *) echo "soak.sh: unknown argument '$1' (see the header of $0)" >&2; exit 2 ;;
  esac
done
strikes=$(/usr/bin/python3 -c "print(max(1, round($hours * 3600 / 0.5)))")
echo "soak: $hours h of recorded time = $strikes strikes, replayed at ${rate}x"
exec bash "$(dirname "$0")/load.sh" --strikes "$strikes" --rates "$rate" "${keep[@]}"
