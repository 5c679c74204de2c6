#!/usr/bin/env bash
# The suite's own check: a command that hangs is stopped at its bound and
# fails the case; a clear refusal passes; a missing line fails.
set -uo pipefail
# shellcheck disable=SC1091
source "$(dirname "$0")/hostile.sh"
fm=$hostile_bin/firmness_model
hostile_case unknown_flag 2 'unknown' 2 256 -- "$fm" --no-such-flag
# The harness must fail these three (checked, then forgotten):
before=$hostile_failed
# (sleep 600: far beyond the bound, 0.5 s or 5 s under the sanitizers, which
# stops it; a 5 s sleep once ended within the sanitizers' 5 s bound.)
hostile_case must_time_out 0 '' 0.5 256 -- sleep 600 >/dev/null 2>&1
hostile_case must_miss_line 2 'no such line anywhere' 2 256 -- "$fm" --no-such-flag >/dev/null 2>&1
hostile_case must_miss_exit 0 '' 2 256 -- "$fm" --no-such-flag >/dev/null 2>&1
if [ $((hostile_failed - before)) != 3 ]; then
  echo "hostile.sh: the harness passed a case it must fail" >&2
  exit 1
fi
hostile_failed=$before
hostile_done
