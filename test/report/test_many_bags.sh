#!/usr/bin/env bash
# firmness_report on several bags and on a folder of bags: each bag's section
# the same as its own run, the combined summary's counts the sums of the
# bags' (and of strike_bag's truth), its quantiles those of every strike
# taken together (computed here), the same output with one worker or two,
# the CSV's bag column; bad --jobs, an empty folder, --plots with several
# bags, a bad bag among good ones. And --bench: the per-stage table's rows,
# every figure finite, each stage's p99 and max not below its median.
#   test_many_bags.sh FIRMNESS_REPORT STRIKE_BAG   (run in the devel space's environment)
source "$(dirname "$0")/../cli/harness.sh" "$1"
SB=${2:?path to strike_bag}

mkdir -p "$tmp/d"
# Made in an order other than the names' (the folder is read sorted by name).
"$SB" --strikes 4 --seed 23 --spacing 0.2 --out "$tmp/d/c.bag" >/dev/null 2>&1 || bad "strike_bag c"
"$SB" --strikes 2 --seed 21 --out "$tmp/d/a.bag" >/dev/null 2>&1 || bad "strike_bag a"
"$SB" --strikes 3 --seed 22 --out "$tmp/d/b.bag" >/dev/null 2>&1 || bad "strike_bag b"
echo "not a bag either" >"$tmp/d/notes.txt"

for b in a b c; do
  "$FM" "$tmp/d/$b.bag" --json >"$tmp/$b.json" 2>"$tmp/err" || bad "single $b exited $?: $(cat "$tmp/err")"
done
"$FM" "$tmp/d" --json --jobs 1 --csv "$tmp/j1.csv" >"$tmp/j1.json" 2>"$tmp/err" ||
  bad "folder --jobs 1: $(cat "$tmp/err")"
"$FM" "$tmp/d" --json --jobs 2 --csv "$tmp/j2.csv" >"$tmp/j2.json" 2>"$tmp/err" ||
  bad "folder --jobs 2: $(cat "$tmp/err")"
if cmp -s "$tmp/j1.json" "$tmp/j2.json" && cmp -s "$tmp/j1.csv" "$tmp/j2.csv"; then ok; else bad "--jobs 1 and --jobs 2 differ"; fi

if $PY - "$tmp" <<'EOF'; then ok; else bad "several bags against their single runs and the truth"; fi
import csv, json, math, sys
d = sys.argv[1]
many = json.load(open(d + '/j1.json'))
names = [d + '/d/%s.bag' % b for b in 'abc']
assert [b['bag'] for b in many['bags']] == names, [b['bag'] for b in many['bags']]  # sorted
additive = ['strikes', 'reliable', 'with_apple', 'without_apple', 'without_audio', 'doubtful',
            'apples', 'apples_refused', 'apples_without_strike', 'apples_predicted_reliable']
sums = dict.fromkeys(additive, 0)
reasons = {}
res = []
for b, sec in zip('abc', many['bags']):
    one = json.load(open(d + '/%s.json' % b))
    truth = list(csv.DictReader(open(d + '/d/%s.truth.csv' % b)))
    # the bag's section is its own run, strike by strike
    assert sec['strikes'] == one['strikes'] and sec['summary'] == one['summary'], b
    assert sec['summary']['strikes'] == len(truth) == sec['summary']['apples'], b
    for k in additive:
        sums[k] += one['summary'][k]
    for k, v in one['summary']['unreliable_by_reason'].items():
        reasons[k] = reasons.get(k, 0) + v
    res += [s['resonance_hz'] for s in one['strikes'] if s['resonance_hz'] is not None]
c = many['combined']
assert c['bags'] == 3 and c['failed'] == 0, c
s = c['summary']
for k in additive:
    assert s[k] == sums[k], (k, s[k], sums[k])
assert s['strikes'] == 9, s
assert s['unreliable_by_reason'] == reasons, (s['unreliable_by_reason'], reasons)
for k in ('chunks', 'gaps', 'lost_samples'):
    assert s['force'][k] == sum(b['summary']['force'][k] for b in many['bags']), k
assert abs(s['recorded_s'] - sum(b['summary']['recorded_s'] for b in many['bags'])) < 1e-6
# quantiles over every strike together (linear between order statistics), not per bag
res.sort()
def q(p):
    h = p * (len(res) - 1)
    lo = int(math.floor(h)); hi = min(lo + 1, len(res) - 1)
    return res[lo] + (h - lo) * (res[hi] - res[lo])
got = s['resonance_hz']
assert got['n'] == len(res) == 9, got
for p, v in zip([0, 0.1, 0.25, 0.5, 0.75, 0.9, 1], got['q']):
    assert abs(v - q(p)) <= 1e-6 * abs(q(p)), (p, v, q(p))
# the CSV: a first column bag, each bag's rows as many as its strikes
rows = list(csv.DictReader(open(d + '/j1.csv')))
assert list(rows[0].keys())[0] == 'bag', rows[0].keys()
assert [r['bag'] for r in rows] == [names[0]] * 2 + [names[1]] * 3 + [names[2]] * 4
EOF

# Text: a section per bag in the order given, then the combined summary.
"$FM" "$tmp/d/b.bag" "$tmp/d/a.bag" >"$tmp/two.txt" 2>"$tmp/err" || bad "two bags exited $?: $(cat "$tmp/err")"
if grep -q "^== bag 1 of 2: $tmp/d/b.bag ==" "$tmp/two.txt" && grep -q "^== bag 2 of 2: $tmp/d/a.bag ==" "$tmp/two.txt" &&
  grep -q "^== combined: 2 bags, 5 strikes ==" "$tmp/two.txt" && grep -q "^  strikes 5: " "$tmp/two.txt"; then
  ok
else
  bad "two bags, text: $(grep '==' "$tmp/two.txt")"
fi

# --- refusals ------------------------------------------------------------------------
for j in 0 -3 257; do
  expect_usage "--jobs $j is outside the accepted range \[1, 256\] workers" "$tmp/d" --jobs "$j"
done
expect_usage "--jobs 'two' is not a finite number (accepted range \[1, 256\] workers)" "$tmp/d" --jobs two
expect_usage "--jobs '1.5' is not a whole number (accepted range \[1, 256\] workers)" "$tmp/d" --jobs 1.5
mkdir -p "$tmp/empty"
expect_usage "$tmp/empty: the folder holds no \*.bag file" "$tmp/empty"
expect_usage "--plots $tmp/p draws one bag's figures" "$tmp/d" --plots "$tmp/p"

# A bad bag among good ones: the good ones reported, one line for the bad, exit 2.
echo "not a bag" >"$tmp/bad.bag"
"$FM" "$tmp/d/a.bag" "$tmp/bad.bag" --json >"$tmp/bad.json" 2>"$tmp/err"
code=$?
if [ $code -eq 2 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q "$tmp/bad.bag: not a readable bag" "$tmp/err" &&
  $PY - "$tmp/bad.json" <<'EOF'; then ok; else bad "a bad bag among good: exit $code, stderr $(cat "$tmp/err")"; fi
import json, sys
d = json.load(open(sys.argv[1]))
assert d['bags'][0]['summary']['strikes'] == 2 and 'not a readable bag' in d['bags'][1]['error']
assert d['combined']['bags'] == 1 and d['combined']['failed'] == 1
assert d['combined']['summary']['strikes'] == 2
EOF

# --- --bench: the per-stage table ----------------------------------------------------
"$FM" "$tmp/d" --bench --jobs 2 >/dev/null 2>"$tmp/bench" || bad "--bench exited $?"
if $PY - "$tmp/bench" <<'EOF'; then ok; else bad "--bench table: $(cat "$tmp/bench")"; fi
import math, re, sys
text = open(sys.argv[1]).read()
rows, tails = {}, {}
for line in text.splitlines():
    m = re.match(r'^  (\w+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)', line)
    if m and m.group(1) != 'stage':
        rows[m.group(1)] = [m.group(k) for k in range(2, 7)]
        tails[m.group(1)] = [m.group(7), m.group(8)]
stages = ['setup', 'detect', 'window', 'predict', 'fft', 'modes', 'fit', 'verdict', 'serialize']
assert list(rows) == stages + ['other', 'all'], list(rows)
for name in stages:
    calls, median, mean, total, share = rows[name]
    for v in (median, mean, total, share):
        assert math.isfinite(float(v)) and float(v) >= 0, (name, v)
    assert int(calls) >= 1, (name, calls)
    # the tail per strike: median <= p99 <= max, all finite
    p99, top = (float(v) for v in tails[name])
    assert float(median) <= p99 <= top and math.isfinite(top), (name, median, p99, top)
for name in ('detect', 'fft', 'modes', 'fit', 'serialize'):
    assert float(rows[name][1]) > 0, (name, rows[name])   # a median of real work
assert int(rows['setup'][0]) == 3 and int(rows['fit'][0]) == 9 and int(rows['serialize'][0]) == 9
# The stages are timed on the monotonic clock, "all" is the workers' CPU
# time: on a loaded machine a stage holds time its thread waited, so their
# sum may pass "all". "other" is then no negative cost but the line that says
# by how much the stages pass it; else the shares add up.
stage_us = sum(float(rows[n][3]) for n in stages)
all_us = float(rows['all'][3])
if rows['other'][2] == '-':
    over = re.search(r"exceeds the workers' CPU time by ([0-9.]+) us", text)
    assert over and abs(float(over.group(1)) - (stage_us - all_us)) < 0.2, (over, stage_us, all_us)
else:
    assert float(rows['other'][2]) >= 0 and float(rows['other'][3]) >= 0, rows['other']
    assert abs(sum(float(rows[n][4]) for n in stages + ['other']) - 100.0) < 0.1
m = re.search(r'real-time factor ([0-9.]+) x .* 2 workers\); CPU ([0-9.]+) x', text)
assert m and float(m.group(1)) > 0 and float(m.group(2)) > 0, text
assert len(re.findall(r'^bench: .*/[abc]\.bag: .* x real time', text, re.M)) == 3, text
assert 'nan' not in text.lower() and 'inf' not in text.lower()
EOF

summary test_many_bags
