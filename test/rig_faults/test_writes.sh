#!/usr/bin/env bash
# Writes that fail: a full disk, a file-size limit, a bag too large to make.
#  - every tool with its standard output on /dev/full: exit 1 and exactly one
#    line "cannot write standard output: No space left on device", no abort;
#  - analyze under a file-size limit smaller than its JSON: exit non-zero,
#    the cause named (no cut JSON passed off as a success);
#  - strike_bag under a file-size limit: exit 1, one line, the partial bag
#    removed; capture_to_bag onto a full filesystem (a 64 kB tmpfs): the
#    same; strike_bag onto it: refused before writing, the free space named;
#  - strike_bag --strikes 100000 --spacing 60 (2.4 TB): refused at once with
#    the estimate and the cap, in bounded memory;
#  - strike_bag's peak memory the same for 20 strikes and for 2000.
# The tmpfs needs mount (root); without it those cases print SKIP and the
# count of skipped cases is the last line.
set -uo pipefail
# shellcheck disable=SC1091
source "$(dirname "$0")/rig_faults.sh"
data="$(cd "$(dirname "$0")/../data" && pwd)"
fm=$rig_bin/firmness_model
skipped=0

# one_cause NAME REGEX: the case's stderr holds exactly one line matching
# REGEX and no abort (terminate, core dump).
one_cause() {
  local n
  n=$(grep -Ec -- "$2" "$tmp/$1.err")
  if [ "$n" != 1 ] || grep -Eq 'terminate|Aborted|core dumped' "$tmp/$1.err"; then
    echo "  FAIL $1: want exactly one line matching '$2' and no abort; stderr:" >&2
    head -c 2000 "$tmp/$1.err" >&2
    hostile_failed=$((hostile_failed + 1))
  fi
}

# to_full NAME CMD ARG...: CMD with its standard output on /dev/full.
to_full() {
  local name=$1
  shift
  hostile_case "$name" 1 'cannot write standard output: No space left on device' 60 256 -- \
    bash -c 'exec "$@" >/dev/full' full "$@"
  one_cause "$name" 'cannot write standard output'
}

# --- inputs ------------------------------------------------------------------------
"$rig_bin/strike_bag" --strikes 2 --seed 3 --out "$tmp/s2.bag" >/dev/null 2>&1 ||
  { echo "test_writes: strike_bag failed" >&2; exit 1; }
raw=(--force "$data/hammer_capture_5.force.f32" --audio "$data/hammer_capture_5.response.f32"
  --rate-force 25600 --rate-audio 25600)
printf 'apple_id,stamp_s,mass_kg,equatorial_radius_m,strike_radius_m,stem_axis_x,stem_axis_y,stem_axis_z,confidence\n1,0.5,0.2,0.037,0.04,1,0,0,0.9\n' \
  >"$tmp/apples.csv"

# --- standard output on /dev/full, every tool ---------------------------------------
to_full model_text "$fm" --E2 8e6
to_full model_json "$fm" --json
to_full model_help "$fm" --help
to_full analyze "$fm" analyze "${raw[@]}" --mass 0.175 --R2 0.04
to_full sweep "$fm" sweep --param E2 --from 2e6 --to 12e6 --steps 3
to_full design "$fm" design
to_full report "$rig_bin/firmness_report" "$tmp/s2.bag"
to_full report_fields "$rig_bin/firmness_report" --fields
to_full strike_bag "$rig_bin/strike_bag" --strikes 1 --out "$tmp/full_stdout.bag"
to_full strike_bag_help "$rig_bin/strike_bag" --help
to_full capture_to_bag "$rig_bin/capture_to_bag" "${raw[@]}" --apples "$tmp/apples.csv" \
  --out "$tmp/full_stdout_c.bag"
to_full settings_doc "$rig_bin/af_settings_doc"

# --- a file-size limit ---------------------------------------------------------------
# analyze's JSON is 1.7 kB: a 1 kB limit cuts it. SIGXFSZ is ignored by the
# tool itself, so the write fails with EFBIG instead of killing it.
hostile_case analyze_fsize nonzero 'cannot write standard output: File too large' 60 256 -- \
  bash -c 'ulimit -f 1; exec "$@" >"'"$tmp"'/cut.json"' limit "$fm" analyze "${raw[@]}" \
  --mass 0.175 --R2 0.04
one_cause analyze_fsize 'cannot write standard output'
hostile_case strike_bag_fsize 1 'cannot write .*lim\.bag: .*File too large; the partial bag is removed' \
  60 256 -- bash -c 'ulimit -f 600; exec "$@"' limit "$rig_bin/strike_bag" --strikes 6 \
  --out "$tmp/lim.bag"
one_cause strike_bag_fsize 'cannot write'
if [ -e "$tmp/lim.bag" ]; then
  echo "  FAIL strike_bag_fsize: the partial bag $tmp/lim.bag was left behind" >&2
  hostile_failed=$((hostile_failed + 1))
fi

# --- a full filesystem ----------------------------------------------------------------
mkdir -p "$tmp/small"
if mount -t tmpfs -o size=64k tmpfs "$tmp/small" 2>"$tmp/mount.err"; then
  # removed before the scratch folder, even on a failure
  trap 'umount "$tmp/small" 2>/dev/null; af_stop_all; rm -rf "$tmp"' EXIT
  hostile_case capture_to_bag_enospc 1 \
    'cannot write .*small/c\.bag: .*No space left on device; the partial bag is removed' 60 256 -- \
    "$rig_bin/capture_to_bag" "${raw[@]}" --apples "$tmp/apples.csv" --out "$tmp/small/c.bag"
  one_cause capture_to_bag_enospc 'cannot write'
  hostile_case strike_bag_enospc 1 'refused: 2 strikes 0.5 s apart make about 1.0 MB .*above the .* free in ' \
    10 256 -- "$rig_bin/strike_bag" --strikes 2 --out "$tmp/small/s.bag"
  one_cause strike_bag_enospc 'refused'
  left=$(ls -A "$tmp/small")
  if [ -n "$left" ]; then
    echo "  FAIL: partial files left on the full filesystem: $left" >&2
    hostile_failed=$((hostile_failed + 1))
  fi
  umount "$tmp/small"
else
  echo "SKIP capture_to_bag_enospc, strike_bag_enospc: cannot mount a 64 kB tmpfs ($(head -1 "$tmp/mount.err"))"
  skipped=2
fi

# --- sizes -------------------------------------------------------------------------
# 100000 strikes 60 s apart: 2.4 TB. Refused before any strike is drawn.
hostile_case strike_bag_too_big 1 'refused: 100000 strikes 60 s apart make about 2\.4 TB .*above the --max-size cap of 16 GB' \
  5 64 -- "$rig_bin/strike_bag" --strikes 100000 --spacing 60 --out "$tmp/big.bag"
one_cause strike_bag_too_big 'refused'
[ -e "$tmp/big.bag" ] && { echo "  FAIL strike_bag_too_big: a bag was written" >&2; hostile_failed=$((hostile_failed + 1)); }
# The cap is a flag: a small one refuses a small bag.
hostile_case strike_bag_cap 1 'above the --max-size cap of 1\.0 MB' 5 64 -- \
  "$rig_bin/strike_bag" --strikes 10 --max-size 0.001 --out "$tmp/cap.bag"
# Memory does not grow with --strikes: each pulse is made as its chunks are
# written (20 MiB for 20 strikes or 2000; holding every pulse took 99 MiB
# for 2000).
hostile_case strike_bag_rss_20 0 '' 60 32 -- "$rig_bin/strike_bag" --strikes 20 --out "$tmp/m20.bag"
hostile_case strike_bag_rss_2000 0 '' 120 32 -- "$rig_bin/strike_bag" --strikes 2000 --spacing 0.1 \
  --out "$tmp/m2000.bag"

hostile_done
status=$?
[ "$skipped" = 0 ] || echo "SKIPPED: $skipped cases (no tmpfs mount)"
exit $status
