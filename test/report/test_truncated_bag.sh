#!/usr/bin/env bash
# A bag cut short (head -c, as a recorder killed mid-write leaves it):
# firmness_report says so in one line on stderr, naming the bag once, with
# the `rosbag reindex` hint, exit 2. A copy reindexed by rosbag gives back
# the strikes recorded before the cut: each one of the full bag's, the same
# apple and contact time, and none after the cut. A file that is not a bag
# at all gets one line without the hint.
#   test_truncated_bag.sh FIRMNESS_REPORT STRIKE_BAG   (devel space environment: rosbag)
source "$(dirname "$0")/../cli/harness.sh" "$1"
SB=${2:?path to strike_bag}
N=12

"$SB" --strikes $N --seed 5 --out "$tmp/full.bag" >/dev/null 2>"$tmp/err" || bad "strike_bag failed: $(cat "$tmp/err")"
"$FM" "$tmp/full.bag" --csv "$tmp/full.csv" >/dev/null 2>"$tmp/err" || bad "full bag: $(cat "$tmp/err")"

# one_line PATTERN FILE: the bag exits 2 with one stderr line naming the bag
# once and matching PATTERN.
one_line() {
  local pattern=$1 bag=$2
  "$FM" "$bag" >"$tmp/out" 2>"$tmp/err"
  local code=$?
  local times
  times=$(grep -o -F -- "$bag" "$tmp/err" | wc -l)
  if [ $code -eq 2 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -Eq -- "$pattern" "$tmp/err" && [ "$times" -le 2 ] &&
    ! grep -qF "$bag: $bag" "$tmp/err"; then
    ok
    echo "  $(cat "$tmp/err")"
  else
    bad "'$bag' exited $code, expected 2 and one line matching '$pattern': $(cat "$tmp/err")"
  fi
}

size=$(stat -c %s "$tmp/full.bag")
for frac in 2 3; do # cut at 1/2 and at 2/3 of the file
  cut=$((size * (frac - 1) / frac))
  head -c $cut "$tmp/full.bag" >"$tmp/cut$frac.bag"
  one_line "^firmness_report: $tmp/cut$frac.bag: .*rosbag reindex $tmp/cut$frac.bag" "$tmp/cut$frac.bag"
  cp "$tmp/cut$frac.bag" "$tmp/fixed$frac.bag"
  (cd "$tmp" && rosbag reindex "fixed$frac.bag" >/dev/null 2>&1) || bad "rosbag reindex fixed$frac.bag failed"
  "$FM" "$tmp/fixed$frac.bag" --csv "$tmp/fixed$frac.csv" >/dev/null 2>"$tmp/err" || bad "reindexed bag: $(cat "$tmp/err")"
  if $PY - "$tmp/full.csv" "$tmp/fixed$frac.csv" "$cut" "$size" $N <<'EOF'; then ok; else bad "strikes of the reindexed bag (cut at 1/$frac)"; fi
import csv, sys
full = {r['apple_id']: r for r in csv.DictReader(open(sys.argv[1]))}
fixed = list(csv.DictReader(open(sys.argv[2])))
cut, size, n = int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5])
assert len(full) == n, len(full)
# Recovered: some strikes, not all, and the first ones (the bag's whole
# chunks before the cut; rosbag writes chunks of ~768 KB, here ~4 strikes).
assert 1 <= len(fixed) < n, len(fixed)
assert sorted(int(r['apple_id']) for r in fixed) == list(range(1, len(fixed) + 1)), fixed
for r in fixed:
    f = full[r['apple_id']]
    assert r['stamp_ns'] == f['stamp_ns'], (r, f)
    assert r['grade'] == f['grade'] or r['grade'] == 'ungraded', (r['grade'], f['grade'])
print('cut at %d of %d bytes: %d of %d strikes recovered' % (cut, size, len(fixed), n))
EOF
done

# Not a bag: one line, no reindex hint (reindex cannot help).
echo "not a bag at all" >"$tmp/text.bag"
one_line "^firmness_report: $tmp/text.bag: not a readable bag: not a ROS bag" "$tmp/text.bag"
if grep -q reindex "$tmp/err"; then bad "a text file got the reindex hint"; else ok; fi

summary test_truncated_bag
