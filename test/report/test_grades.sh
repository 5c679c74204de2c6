#!/usr/bin/env bash
# firmness_report's grade and verdict flags, per strike, in its text, CSV and
# JSON, on a strike_bag bag (24 strikes, seed 11, a fifth clipped). The expected grade is
# worked out here: the cultivar file's grade_classes (read with PyYAML)
# applied to the strike's figure from the CSV (a value on a boundary belongs
# to the class above), 0 "ungraded" with "not reliable: REASON" for a strike
# that is not reliable. The flags are checked against the CSV's own figures
# (excites_mode <=> the 0S2 inside the measured band, damage <=> shear >=
# yield, ...). Then the same with --set grade_quantity/grade_classes,
# including a boundary placed exactly on one strike's value.
#   test_grades.sh FIRMNESS_REPORT STRIKE_BAG   (devel space environment)
source "$(dirname "$0")/../cli/harness.sh" "$1"
SB=${2:?path to strike_bag}
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
N=24

# a fifth of the strikes saturate the transducer (clipped: ungraded), so that
# both graded and ungraded strikes are checked
"$SB" --strikes $N --seed 11 --unreliable-fraction 0.2 --out "$tmp/s.bag" >/dev/null 2>"$tmp/err" || bad "strike_bag failed: $(cat "$tmp/err")"

# check.py CSV JSON TEXT QUANTITY CLASSES: every strike's grade and flags, in the three outputs.
cat >"$tmp/check.py" <<'EOF'
import bisect, csv, json, math, re, sys
csv_path, json_path, text_path, quantity, classes = sys.argv[1:6]
column = {'stiffness_factor': 'stiffness_factor_hz2_kg2_3',
          'modulus_from_resonance': 'modulus_from_resonance_pa',
          'fitted_modulus': 'fitted_modulus_pa'}[quantity]
tokens = [t.strip() for t in classes.split('|')]
names, bounds = tokens[0::2], [float(t) for t in tokens[1::2]]
assert len(names) == len(bounds) + 1, tokens
rows = list(csv.DictReader(open(csv_path)))
rep = json.load(open(json_path))['strikes']
text = {}
for line in open(text_path):  # "  id  ... | idx name | verdict [flags]: reason"
    m = re.match(r'\s+(\d+) \d+\.\d+ .*\|\s*(\d+) (.+?)\s*\| (reliable|NOT reliable \[([^\]]*)\])', line)
    if m:
        text[int(m.group(1))] = (int(m.group(2)), m.group(3), m.group(5) or '')
assert len(rows) == len(rep) == len(text) >= 20, (len(rows), len(rep), len(text))
known = {'no_apple', 'no_prediction', 'apple_doubtful', 'measure_failed', 'double_hit', 'clipped',
         'lost_samples', 'truncated', 'spectrum_failed', 'fit_failed', 'poisson', 'no_audio',
         'no_resonance', 'range_nyquist', 'audio_failed', 'mode_ambiguous', 'no_lobe',
         'outside_band', 'damage', 'refused_samples', 'audio_clipped', 'clock_fault', 'not_fruit'}
seen = {}
for r, j in zip(rows, rep):
    aid = int(r['apple_id'])
    flags = r['flags'].split('|') if r['flags'] else []
    assert set(flags) <= known, flags
    reliable = r['reliable'] == '1'
    assert reliable == (flags == []), (aid, r['reliable'], flags)
    f0, lo, hi = float(r['resonance_hz']), float(r['band_low_hz']), float(r['band_high_hz'])
    # The band is reported (excites_mode), the heard 0S2 the evidence: never a flag here.
    assert (r['excites_mode'] == '1') == (lo <= f0 <= hi), (aid, f0, lo, hi, r['excites_mode'])
    assert 'outside_band' not in flags, (aid, flags)
    if r['max_shear_stress_pa'] and r['yield_shear_stress_pa']:  # empty: no fit (a clipped pulse)
        assert ('damage' in flags) == (float(r['max_shear_stress_pa']) >= float(r['yield_shear_stress_pa'])), (aid, flags)
    else:
        assert 'damage' not in flags and not reliable, (aid, flags)
    for name in ('double_hit', 'clipped'):
        assert (name in flags) == (r[name] == '1'), (aid, name, flags)
    assert ('lost_samples' in flags) == (int(r['lost_samples']) > 0), (aid, flags)
    assert ('no_audio' in flags) == (r['with_audio'] == '0'), (aid, flags)
    if reliable:
        k = bisect.bisect_right(bounds, float(r[column])) + 1
        want = (k, names[k - 1], '')
    else:
        want = (0, 'ungraded', 'not reliable: ' + r['reason'])
    got = (int(r['grade_index']), r['grade'], r['grade_reason'])
    assert got == want, ('csv', aid, r[column], got, want)
    assert (j['apple_id'], j['grade_index'], j['grade'], j['grade_reason'], j['flags']) == \
        (aid,) + want + (flags,), ('json', j, want, flags)
    assert text[aid] == (want[0], want[1], '|'.join(flags)), ('text', aid, text[aid], want, flags)
    seen[want[1]] = seen.get(want[1], 0) + 1
print(' '.join('%s %d' % kv for kv in sorted(seen.items())))
EOF

run() { # run TAG QUANTITY CLASSES [firmness_report flags]: the three outputs, then check.py
  local tag=$1 quantity=$2 classes=$3
  shift 3
  "$FM" "$tmp/s.bag" "$@" --csv "$tmp/$tag.csv" --json >"$tmp/$tag.json" 2>"$tmp/err" &&
    "$FM" "$tmp/s.bag" "$@" >"$tmp/$tag.txt" 2>>"$tmp/err" ||
    { bad "$tag: firmness_report failed: $(cat "$tmp/err")"; return; }
  if $PY "$tmp/check.py" "$tmp/$tag.csv" "$tmp/$tag.json" "$tmp/$tag.txt" "$quantity" "$classes" >"$tmp/$tag.seen"; then
    ok
    echo "$tag: $(cat "$tmp/$tag.seen")"
  else
    bad "$tag: grades or flags"
  fi
}

# The shipped cultivar's classes, as the node would grade (the default --cultivar).
read -r quantity classes < <($PY - "$ROOT/config/station.yaml" "$ROOT/config/jonagold.yaml" <<'EOF'
import sys, yaml
d = {}
for path in sys.argv[1:]:
    d.update(yaml.safe_load(open(path)) or {})
print(d['grade_quantity'], d['grade_classes'])
EOF
)
run shipped "$quantity" "$classes"
# At least three classes and some ungraded strikes, or the test shows little.
if [ "$(wc -w <"$tmp/shipped.seen")" -ge 8 ] && grep -q ungraded "$tmp/shipped.seen"; then ok; else bad "shipped: too few classes seen: $(cat "$tmp/shipped.seen")"; fi

# Other classes on another quantity, through --set (the parameter table's rows).
run fitted fitted_modulus "low | 6e6 | high" --set grade_quantity=fitted_modulus --set "grade_classes=low | 6e6 | high"

# A yield law 40x weaker: every strike bruises (damage), none graded.
run weak "$quantity" "$classes" --set yield_ratio=0.001
# (the clipped strikes have no fit, so no shear: every other one bruises)
clipped=$(grep -c 'NOT reliable \[[a-z_|]*clipped' "$tmp/weak.txt")
if [ "$(cat "$tmp/weak.seen")" = "ungraded $N" ] &&
  [ "$(grep -c 'NOT reliable \[[a-z_|]*damage' "$tmp/weak.txt")" = "$((N - clipped))" ]; then ok; else bad "weak: $(cat "$tmp/weak.seen"), $clipped clipped"; fi

# A boundary exactly on the first reliable strike's stiffness factor: that strike
# goes to the class above.
edge=$($PY -c 'import csv,sys; print(next(r["stiffness_factor_hz2_kg2_3"] for r in csv.DictReader(open(sys.argv[1])) if r["reliable"] == "1"))' "$tmp/shipped.csv")
run edge stiffness_factor "below | $edge | above" --set "grade_classes=below | $edge | above"
if grep -q "above" "$tmp/edge.seen"; then ok; else bad "edge: no strike in the class above $edge"; fi

summary test_grades
