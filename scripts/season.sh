#!/usr/bin/env bash
# A season of bags reported on several machines with GNU parallel (Debian:
# parallel), then merged into the summary one run over all of them prints.
#
#   bash scripts/season.sh [--hosts SPEC] OUT_DIR BAG... [-- FLAG...]
#
# Each bag is reported on one of the hosts (`firmness_report BAG --json
# FLAG...`) into OUT_DIR/NAME.json (NAME: the bag's name without .bag; two
# bags of one name are refused), its stderr into OUT_DIR/NAME.log; a bag
# that cannot be read is written as {"bag", "error"} and counted as not
# read, as one run counts it. Then `firmness_report --merge` of the reports
# in the order given writes OUT_DIR/season.txt and OUT_DIR/season.json.
#
# --hosts SPEC is GNU parallel's --sshlogin: "4/lab1,4/lab2" (4 bags at once
# on each of two machines over ssh), ":" this machine (the default), or
# "2/:" two bags at once here. Every host needs the package at the same path
# as here (this script runs itself there: `season.sh --one`), the bags and
# OUT_DIR on shared storage (NFS) at the same paths, and ssh without a
# password (ssh-copy-id). FLAG... (e.g. --config FILE, --set NAME=VALUE) go
# to every bag's firmness_report; every host must use the same files: the
# merge refuses reports run with different settings.
#
# Exit status: 0, or the worst of the bags' and the merge's (1 failure, 2
# bad input), as firmness_report over several bags.
set -euo pipefail
# shellcheck disable=SC1091
source "$(dirname "$0")/env.sh"
self=$AF_ROOT/scripts/season.sh
tool=$AF_DEVEL/lib/acoustic_firmness/firmness_report

# --one OUT_DIR BAG FLAG...: one bag's report, run on a host.
if [ "${1:-}" = "--one" ]; then
  out=$2 bag=$3
  shift 3
  name=$(basename "$bag" .bag)
  if "$tool" "$bag" --json "$@" >"$out/$name.json" 2>"$out/$name.log"; then
    exit 0
  else
    code=$?
  fi
  # Not read: the failure as a report of one bag not read (merge counts it).
  /usr/bin/python3 -c 'import json, sys; print(json.dumps({"bag": sys.argv[1], "error": sys.argv[2]}))' \
    "$bag" "$(tail -n 1 "$out/$name.log")" >"$out/$name.json"
  exit "$code"
fi

hosts=:
if [ "${1:-}" = "--hosts" ]; then
  hosts=${2:?--hosts needs a SPEC (GNU parallel --sshlogin)}
  shift 2
fi
out=${1:?usage: season.sh [--hosts SPEC] OUT_DIR BAG... [-- FLAG...]}
shift
bags=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do
  case "$1" in /*) bags+=("$1") ;; *) bags+=("$PWD/$1") ;; esac
  shift
done
[ "${1:-}" = "--" ] && shift
[ ${#bags[@]} -gt 0 ] || { echo "season.sh: no BAG given" >&2; exit 2; }
command -v parallel >/dev/null || { echo "season.sh: GNU parallel is missing (apt-get install parallel)" >&2; exit 2; }
[ -x "$tool" ] || { echo "season.sh: $tool not built (bash scripts/build.sh)" >&2; exit 2; }
dup=$(for b in "${bags[@]}"; do basename "$b" .bag; done | sort | uniq -d | head -n 1)
[ -z "$dup" ] || { echo "season.sh: two bags named $dup.bag: their reports would collide in $out" >&2; exit 2; }
mkdir -p "$out"
out=$(cd "$out" && pwd)

code=0
parallel --will-cite --halt never --sshlogin "$hosts" bash "$self" --one "$out" {} "$@" ::: "${bags[@]}" ||
  code=$?
# parallel's status is the number of failed jobs: the reports tell which.
[ "$code" -eq 0 ] || code=1
for b in "${bags[@]}"; do
  grep -q '"merge_state"' "$out/$(basename "$b" .bag).json" 2>/dev/null || code=2
done
reports=()
for b in "${bags[@]}"; do reports+=("$out/$(basename "$b" .bag).json"); done
"$tool" --merge "${reports[@]}" >"$out/season.txt" || code=$?
"$tool" --merge "${reports[@]}" --json >"$out/season.json" || code=$?
echo "wrote $out/season.txt" >&2
echo "wrote $out/season.json" >&2
exit "$code"
