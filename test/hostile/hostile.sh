# shellcheck shell=bash
# Sourced by the hostile-input suite (test/hostile/test_*.sh, ctest
# hostile_*): each case runs one command on a hostile input and states what
# the answer must be: the exit code, a line of its output (an extended regex,
# searched in stdout + stderr), a wall-time bound and a peak-RSS bound.
#
#   hostile_case NAME EXIT REGEX TIME_S RSS_MIB -- CMD ARG...
#
# EXIT is a number or `nonzero`; REGEX '' = no line required. A case that
# hangs is killed at its bound and fails. Every case prints one row
#   NAME: exit N (want E), T s (<= B), M MiB (<= R), line ok|MISSING
# and the script ends with `hostile_done` (exit 1 when any case failed).
# Under the sanitizer build (ctest sets AF_SANITIZED=1) ASan's shadow memory
# and slowdown make RSS and time meaningless as bounds: the time bound is
# multiplied by 10 and the RSS bound is not checked; exit codes and lines
# still are.
# shellcheck disable=SC1091
source "$(dirname "${BASH_SOURCE[0]}")/../scripts/harness.sh"
hostile_failed=0
hostile_count=0
hostile_bin=$AF_DEVEL/lib/acoustic_firmness

hostile_case() {
  local name=$1 want=$2 regex=$3 time_s=$4 rss_mib=$5
  shift 5
  [ "$1" = "--" ] && shift
  local bound=$time_s
  [ "${AF_SANITIZED:-0}" = 1 ] && bound=$(/usr/bin/python3 -c "print($time_s * 10)")
  local res
  res=$(/usr/bin/python3 "$(dirname "${BASH_SOURCE[0]}")/measure.py" "$bound" \
    "$tmp/$name.out" "$tmp/$name.err" -- "$@")
  local code wall rss timed
  code=$(sed -E 's/.*exit=(-?[0-9]+).*/\1/' <<<"$res")
  wall=$(sed -E 's/.*wall_s=([0-9.]+).*/\1/' <<<"$res")
  rss=$(sed -E 's/.*rss_mib=([0-9.]+).*/\1/' <<<"$res")
  timed=$(sed -E 's/.*timed_out=([01]).*/\1/' <<<"$res")
  local ok=1 line=ok
  if [ "$want" = nonzero ]; then [ "$code" != 0 ] || ok=0; else [ "$code" = "$want" ] || ok=0; fi
  [ "$timed" = 0 ] || ok=0
  if [ "${AF_SANITIZED:-0}" != 1 ]; then
    /usr/bin/python3 -c "import sys; sys.exit(0 if $rss <= $rss_mib else 1)" || ok=0
  fi
  # grep reads the files itself: `cat | grep -q` under pipefail fails when grep
  # stops at a match before cat has written everything (SIGPIPE, exit 141).
  if [ -n "$regex" ] && ! grep -Eqs -- "$regex" "$tmp/$name.out" "$tmp/$name.err"; then
    line=MISSING
    ok=0
  fi
  hostile_count=$((hostile_count + 1))
  printf '%s: exit %s (want %s), %s s (<= %s), %s MiB (<= %s), line %s%s\n' "$name" "$code" \
    "$want" "$wall" "$bound" "$rss" "$rss_mib" "$line" "$([ "$timed" = 1 ] && echo ', TIMED OUT')"
  if [ "$ok" = 0 ]; then
    hostile_failed=$((hostile_failed + 1))
    echo "  FAIL $name; its output:" >&2
    head -c 2000 "$tmp/$name.out" "$tmp/$name.err" >&2
  fi
}

hostile_done() {
  echo "hostile: $hostile_count cases, $hostile_failed failed"
  [ "$hostile_failed" = 0 ]
}
