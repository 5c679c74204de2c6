#!/usr/bin/env bash
# firmness_report end to end on a small synthetic bag (strike_bag, seed 11)
# against the truth it was made from, and every kind of bad input: one line
# on stderr naming what is wrong, exit 2, never a crash.
#   test_report.sh FIRMNESS_REPORT STRIKE_BAG   (run in the devel space's environment:
#                                                 the bad bags are written with rosbag's Python)
source "$(dirname "$0")/../cli/harness.sh" "$1"
SB=${2:?path to strike_bag}
N=6

"$SB" --strikes $N --seed 11 --out "$tmp/s.bag" >/dev/null || bad "strike_bag failed"

# --- a good bag: the report against the truth ------------------------------------
"$FM" "$tmp/s.bag" --json --csv "$tmp/s.csv" >"$tmp/s.json" 2>"$tmp/err" || bad "report exited $?: $(cat "$tmp/err")"
if $PY - "$tmp/s.json" "$tmp/s.truth.csv" "$tmp/s.csv" $N <<'EOF'; then ok; else bad "report vs truth"; fi
import csv, json, sys
rep = json.load(open(sys.argv[1]))
truth = {int(r['apple_id']): r for r in csv.DictReader(open(sys.argv[2]))}
rows = list(csv.DictReader(open(sys.argv[3])))
n = int(sys.argv[4])
s = rep['summary']
assert s['strikes'] == n and s['with_apple'] == n and s['without_apple'] == 0, s
assert s['without_audio'] == 0 and s['apples'] == n and s['apples_without_strike'] == 0, s
assert s['force']['gaps'] == 0 and s['audio']['gaps'] == 0, s
assert sorted(o['apple_id'] for o in rep['strikes']) == list(range(1, n + 1))
assert len(rows) == n and [int(r['apple_id']) for r in rows] == [o['apple_id'] for o in rep['strikes']]
for o in rep['strikes']:
    t = truth[o['apple_id']]
    assert abs(o['resonance_hz'] / float(t['resonance_hz']) - 1) < 0.01, (o, t)
    assert abs(o['fitted_modulus_pa'] / float(t['modulus_pa']) - 1) < 0.05, (o, t)
    assert abs(o['stamp_ns'] * 1e-9 - float(t['contact_start_s'])) < 5 / 50000.0, (o, t)
    assert abs(o['mass_kg'] - float(t['mass_kg'])) < 1e-6, (o, t)  # truth: 6 decimals
    assert o['reliable'] == (o['flags'] == []) and o['reliable'] == (o['reason'] == ''), o
# The bag is made with the modulus factor 1: the 0S2's modulus and the fitted
# E2 estimate the same truth, so the suggested factor is 1 within the fit's scatter.
assert abs(s['modulus_factor_suggested'] - 1.0) < 0.02, s
assert abs(s['modulus_ratio']['q'][3] - 1.0) < 0.02, s
EOF
"$FM" "$tmp/s.bag" >"$tmp/s.txt" 2>"$tmp/err"
if [ "$(grep -c 'reliable' "$tmp/s.txt")" -ge $N ] && grep -q "strikes $N: $N on an apple" "$tmp/s.txt"; then ok; else bad "text report: $(cat "$tmp/s.txt")"; fi
"$FM" "$tmp/s.bag" --bench >/dev/null 2>"$tmp/err"
if grep -Eq '[0-9]+ x real time' "$tmp/err"; then ok; else bad "--bench: $(cat "$tmp/err")"; fi

# --fields: the table of a strike's fields. --json: one row per key of a JSON
# strike and per CSV column (the report's apple fields after them), in order,
# each unit-suffixed, each mapped to a field of its message's .msg file (read
# here) or report-only; the markdown: a header, a rule and the same rows.
"$FM" --fields --json >"$tmp/fields.json" 2>"$tmp/err" && "$FM" --fields >"$tmp/fields.md" 2>>"$tmp/err" ||
  bad "--fields exited $?: $(cat "$tmp/err")"
if $PY - "$tmp/fields.json" "$tmp/fields.md" "$tmp/s.json" "$tmp/s.csv" "$(dirname "$0")/../../msg" <<'EOF'; then ok; else bad "--fields"; fi
import csv, json, os, sys
fields = json.load(open(sys.argv[1]))
md = open(sys.argv[2]).read().splitlines()
strike = json.load(open(sys.argv[3]))['strikes'][0]
header = next(csv.reader(open(sys.argv[4])))
names = [f['name'] for f in fields]
apple = ['apple_stamp_ns', 'mass_kg', 'predicted']
assert list(strike) == names + apple, (list(strike), names)
assert header[:len(names)] == names, header
assert md[0] == '| field | type | unit | message field | meaning |' and len(md) == len(fields) + 2, md[:2]
suffix = {'s': '_s', 'N': '_n', 'N s': '_n_s', 'Hz': '_hz', 'Pa': '_pa', 'dB': '_db', 'ns': '_ns',
          'samples': '_samples', 'J': '_j', 'Hz^2 kg^(2/3)': '_hz2_kg2_3', '-': '', '': ''}
def msg_fields(name):
    out = []
    for line in open(os.path.join(sys.argv[5], name + '.msg')):
        words = line.split('#')[0].split()
        if len(words) >= 2:
            out.append(words[1])
    return out
for f, row in zip(fields, md[2:]):
    s = suffix[f['unit']]
    assert f['name'].endswith(s), (f['name'], f['unit'])
    if f['message'] is None:
        assert f['message_field'] is None and '| report-only |' in row, (f, row)
    else:
        assert f['message_field'].split('.')[0] in msg_fields(f['message']), f
        assert '| %s.%s |' % (f['message'], f['message_field']) in row, (f, row)
    assert row.startswith('| `%s` | %s | %s |' % (f['name'], f['type'], f['unit'])), (f, row)
mapped = sum(f['message'] is not None for f in fields)
print('  --fields: %d fields, %d mapped to a message field, %d report-only' % (len(fields), mapped, len(fields) - mapped))
EOF
expect_usage "--fields takes no bag" --fields "$tmp/s.bag"
expect_usage "--fields takes only --json" --fields --csv "$tmp/f.csv"

"$FM" "$tmp/s.bag" --plots "$tmp/plots" >/dev/null 2>"$tmp/err" || bad "--plots exited $?: $(cat "$tmp/err")"
n_png=$(ls "$tmp/plots"/*.png 2>/dev/null | wc -l)
# One per strike and the five session figures (report_plots.h), each a PNG.
if [ "$n_png" -eq $((N + 5)) ]; then ok; else bad "--plots made $n_png PNGs, expected $((N + 5))"; fi
for f in firmness_histogram stiffness_vs_mass resonance_vs_band hammer_velocity modulus_factor; do
  if [ "$(head -c 4 "$tmp/plots/$f.png" 2>/dev/null | od -An -tx1 | tr -d ' \n')" = 89504e47 ]; then ok; else bad "--plots drew no $f.png"; fi
done

# --- bad bags ------------------------------------------------------------------------
echo "not a bag" >"$tmp/text.bag"
expect_usage "not a readable bag" "$tmp/text.bag"
head -c $(($(stat -c %s "$tmp/s.bag") / 2)) "$tmp/s.bag" >"$tmp/truncated.bag"
expect_usage "truncated" "$tmp/truncated.bag"
expect_usage "no message on /lane2/force" "$tmp/s.bag" --ns lane2
expect_usage "no-such.bag cannot be opened" "$tmp/no-such.bag"
# Wrong types: a topic of a type this tool does not read, and one of a type it
# reads on the wrong topic.
$PY - "$tmp" <<'EOF' || bad "could not write the wrong-type bags"
import sys, rosbag, rospy
from std_msgs.msg import String
from acoustic_firmness.msg import AppleEstimate, SignalChunk
d = sys.argv[1]
t = rospy.Time(1700000000, 0)
chunk = SignalChunk(first_sample=0, sample_rate=50000.0, unit='N', data=[0.0] * 16)
with rosbag.Bag(d + '/string_force.bag', 'w') as b:
    b.write('/lane1/force', String(data='x'), t)
    b.write('/lane1/audio', chunk, t)
    b.write('/lane1/apple', AppleEstimate(apple_id=1, mass=0.17), t)
with rosbag.Bag(d + '/apple_on_audio.bag', 'w') as b:
    b.write('/lane1/force', chunk, t)
    b.write('/lane1/audio', AppleEstimate(apple_id=1, mass=0.17), t)
    b.write('/lane1/apple', AppleEstimate(apple_id=1, mass=0.17), t)
EOF
expect_usage "/lane1/force has type std_msgs/String" "$tmp/string_force.bag"
expect_usage "/lane1/audio carries acoustic_firmness/AppleEstimate, not acoustic_firmness/SignalChunk" "$tmp/apple_on_audio.bag"

# --- bad flags -------------------------------------------------------------------------
expect_usage "a bag is required"
expect_usage "--jobs 0 is outside the accepted range \[1, 256\] workers" "$tmp/s.bag" --jobs 0
expect_usage "unknown flag '--frobnicate'" "$tmp/s.bag" --frobnicate
expect_usage "--ns needs a value" "$tmp/s.bag" --ns
expect_usage "--ns 'lane 1' is not a lane namespace" "$tmp/s.bag" --ns "lane 1"
expect_usage "--config" "$tmp/s.bag" --config "$tmp/none.yaml"
expect_usage "--cultivar" "$tmp/s.bag" --cultivar "$tmp/none.yaml"
expect_usage "--set lobe=0" "$tmp/s.bag" --set lobe=0
expect_usage "modulus_factor = -1 is outside the accepted range" "$tmp/s.bag" --set modulus_factor=-1
expect_usage "--csv $tmp/no/dir/x.csv: cannot write" "$tmp/s.bag" --csv "$tmp/no/dir/x.csv"

touch "$tmp/afile"
expect_usage "--plots $tmp/afile: not a folder" "$tmp/s.bag" --plots "$tmp/afile"
expect_usage "--plots $tmp/no/dir: cannot make the folder" "$tmp/s.bag" --plots "$tmp/no/dir"

summary test_report
