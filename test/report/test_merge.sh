#!/usr/bin/env bash
# firmness_report --merge: bags reported apart (one report each, as on
# several machines) merge into the very combined summary one run over all the
# bags prints (text and JSON, to the last digit), in the order given; a bag
# not read counts as not read in both; reports run with other settings, or
# that are not reports, are refused with one line. Then the season recipe
# (scripts/season.sh: GNU parallel, here with this machine as its two
# "hosts") gives the same summary as one run.
#   test_merge.sh FIRMNESS_REPORT STRIKE_BAG   (in the devel space's environment)
source "$(dirname "$0")/../cli/harness.sh" "$1"
SB=${2:?path to strike_bag}
root=$(cd "$(dirname "$0")/../.." && pwd)

# Three bags that differ in what the summary adds up: clipped strikes (flags,
# fit failures), another seed and spacing, tap-only is another configuration.
"$SB" --strikes 12 --seed 3 --out "$tmp/a.bag" >/dev/null 2>&1 &&
  "$SB" --strikes 16 --seed 4 --unreliable-fraction 0.3 --out "$tmp/b.bag" >/dev/null 2>&1 &&
  "$SB" --strikes 9 --seed 5 --spacing 0.3 --modulus-factor 1.08 --out "$tmp/c.bag" >/dev/null 2>&1 ||
  bad "strike_bag failed"
head -c 50000 "$tmp/a.bag" >"$tmp/cut.bag" # a bag cut short: not read

# One run over the four bags: its combined section, text and JSON.
"$FM" "$tmp/a.bag" "$tmp/b.bag" "$tmp/cut.bag" "$tmp/c.bag" >"$tmp/run.txt" 2>/dev/null
[ $? -eq 2 ] && ok || bad "one run over a cut bag: exit status not 2"
"$FM" "$tmp/a.bag" "$tmp/b.bag" "$tmp/cut.bag" "$tmp/c.bag" --json >"$tmp/run.json" 2>/dev/null
sed -n '/^== combined/,$p' "$tmp/run.txt" >"$tmp/run_combined.txt"
grep -q "== combined: 3 bags (1 more not read), 37 strikes ==" "$tmp/run_combined.txt" && ok ||
  bad "the run's combined heading: $(head -n 1 "$tmp/run_combined.txt")"

# Each bag alone; the cut one's failure written as the run writes it.
for b in a b c; do
  "$FM" "$tmp/$b.bag" --json >"$tmp/$b.json" 2>"$tmp/err" || bad "report of $b.bag: $(cat "$tmp/err")"
done
"$PY" -c 'import json,sys; print(json.dumps({"bag": sys.argv[1], "error": "cut"}))' "$tmp/cut.bag" >"$tmp/cut.json"

"$FM" --merge "$tmp/a.json" "$tmp/b.json" "$tmp/cut.json" "$tmp/c.json" >"$tmp/merge.txt" 2>"$tmp/err"
[ $? -eq 0 ] && ok || bad "--merge exited non-zero: $(cat "$tmp/err")"
diff "$tmp/run_combined.txt" "$tmp/merge.txt" >"$tmp/diff" && ok || bad "merged text differs: $(head -n 20 "$tmp/diff")"
"$FM" --merge "$tmp/a.json" "$tmp/b.json" "$tmp/cut.json" "$tmp/c.json" --json >"$tmp/merge.json" 2>"$tmp/err" ||
  bad "--merge --json: $(cat "$tmp/err")"
if "$PY" - "$tmp/run.json" "$tmp/merge.json" <<'EOF'; then ok; else bad "merged JSON differs"; fi
import json, sys
run, merged = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
assert run['combined'] == merged['combined'], (run['combined'], merged['combined'])
assert merged['combined']['bags'] == 3 and merged['combined']['failed'] == 1, merged['combined']
assert [m.rsplit('/', 1)[1] for m in merged['merged']] == ['a.json', 'b.json', 'cut.json', 'c.json']
s = merged['combined']['summary']
assert s['strikes'] == 37 and 0 < s['reliable'] < 37, s   # b's clipped strikes are not reliable
EOF

# The run's own JSON (several bags) merges too, and a folder of reports is
# read in name order (a, b, c, cut: another order, the same counts).
"$FM" --merge "$tmp/run.json" --json >"$tmp/again.json" 2>"$tmp/err" || bad "--merge of a run's report: $(cat "$tmp/err")"
"$PY" -c 'import json,sys; a,b=(json.load(open(p))["combined"] for p in sys.argv[1:]); assert a==b' \
  "$tmp/run.json" "$tmp/again.json" && ok || bad "a run's report merged alone differs from its combined"
mkdir -p "$tmp/dir" && cp "$tmp"/{a,b,c,cut}.json "$tmp/dir/"
"$FM" --merge "$tmp/dir" >"$tmp/dir.txt" 2>"$tmp/err" && grep -q "3 bags (1 more not read), 37 strikes" "$tmp/dir.txt" &&
  ok || bad "--merge of a folder: $(cat "$tmp/err")"

# Refusals: one line, exit 2.
"$FM" "$tmp/b.bag" --json --set modulus_factor=1.1 >"$tmp/b2.json" 2>/dev/null || bad "report with --set"
expect_usage "modulus_factor: 1.1" --merge "$tmp/a.json" "$tmp/b2.json"
printf '{"bags": [1,' >"$tmp/trunc.json"
expect_usage "offset 12" --merge "$tmp/trunc.json"
printf '{"a": 1}' >"$tmp/other.json"
expect_usage 'no "merge_state"' --merge "$tmp/other.json"
sed 's/merge_state 1/merge_state 9/' "$tmp/a.json" >"$tmp/v9.json"
expect_usage "format" --merge "$tmp/v9.json"
"$PY" - "$tmp/a.json" "$tmp/nocol.json" <<'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
del d['merge_state']['session']['audio.chunks']
json.dump(d, open(sys.argv[2], 'w'))
EOF
expect_usage "session.audio.chunks: missing" --merge "$tmp/nocol.json"
printf '{"bag": "x"}\0' >"$tmp/nul.json"
expect_usage "NUL" --merge "$tmp/nul.json"
expect_usage "a report must be a regular file" --merge /dev/null
expect_usage "No such file" --merge "$tmp/none.json"
expect_usage "--merge takes only --json" --merge "$tmp/a.json" --csv "$tmp/x.csv"
expect_usage "needs the reports" --merge

# The season recipe: GNU parallel with this machine as two hosts ("2/:").
devel=$(cd "$(dirname "$FM")/../.." && pwd)
AF_DEVEL_DIR=$devel bash "$root/scripts/season.sh" --hosts 2/: "$tmp/season" \
  "$tmp/a.bag" "$tmp/b.bag" "$tmp/cut.bag" "$tmp/c.bag" >"$tmp/season.out" 2>&1
[ $? -eq 2 ] && ok || bad "season.sh with a cut bag: exit status not 2: $(tail -n 5 "$tmp/season.out")"
diff "$tmp/run_combined.txt" "$tmp/season/season.txt" >"$tmp/diff" && ok ||
  bad "season.sh's summary differs from one run: $(head -n 20 "$tmp/diff")"
"$PY" -c 'import json,sys; a,b=(json.load(open(p))["combined"] for p in sys.argv[1:]); assert a==b' \
  "$tmp/run.json" "$tmp/season/season.json" && ok || bad "season.sh's JSON differs from one run"

summary test_merge
