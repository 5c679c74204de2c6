#!/usr/bin/env bash
# The modulus factor learned on the line (src/core/lane/factor_learn.h), end to
# end: strike_bag synthesizes the 0S2 of each apple from a TRUE factor F
# (--modulus-factor, per apple times exp(S g) with --modulus-factor-spread
# S) by its own RK4 pulse and ringing; firmness_report runs the lane, which
# measures with the cultivar's modulus_factor 1 and learns. Checked against
# the truth CSV, never against the code's earlier output:
#  1. a constant factor (0.85 and 1.15): the learned value within 2 % of F
#     from 5 reliable strikes on, its 95 % interval holding F;
#  2. a 5 % apple-to-apple spread, five seeds of 120 strikes: within 2 % of
#     F, and within 0.5 % of the median of the truth's factors of the
#     strikes it took (the sample it learned from);
#  3. 20 % unreliable strikes (--unreliable-fraction 0.2: clipped): none of
#     them reliable, none taken (the learned count = the CSV's reliable
#     rows, the refused = the rest), the value = the median of the reliable
#     rows' E(0S2)/E2 (computed here), unmoved (within 1 %) from the same
#     apples without them, within 2 % of F;
#  4. modulus_factor_learn_apply: exactly one change (hysteresis), the value
#     applied within 2 % of F, the strikes after it measured with it
#     (E(0S2)/E2 within 2 % of 1), those before with 1 (ratio within 2 % of F).
#   test_factor_learn.sh FIRMNESS_REPORT STRIKE_BAG
source "$(dirname "$0")/../cli/harness.sh" "$1"
SB=${2:?path to strike_bag}

# bag NAME STRIKES F SPREAD SEED UNRELIABLE, then report NAME [--set ...]: NAME.json, NAME.csv
bag() {
  "$SB" --strikes "$2" --modulus-factor "$3" --modulus-factor-spread "$4" --seed "$5" \
    --unreliable-fraction "$6" --out "$tmp/$1.bag" >/dev/null 2>&1 || bad "strike_bag $*"
}
report() {
  local name=$1
  shift
  "$FM" "$tmp/$name.bag" --json --csv "$tmp/$name.csv" "$@" >"$tmp/$name.json" 2>"$tmp/err" ||
    bad "firmness_report $name exited $?: $(cat "$tmp/err")"
}

# 1. constant factor
for F in 0.85 1.15; do
  bag k$F 40 $F 0 11 0
  report k$F --set modulus_factor_learn_min_strikes=5
done
# 2. spread, five seeds
for seed in 1 2 3 4 5; do
  bag s$seed 120 0.85 0.05 $seed 0
  report s$seed
done
# 3. unreliable strikes, the same apples without them
bag u0 120 0.85 0.05 1 0
report u0
bag u20 120 0.85 0.05 1 0.2
report u20
# 4. apply
bag a 80 1.15 0 11 0
report a --set modulus_factor_learn_apply=true --set modulus_factor_learn_min_strikes=10

if $PY - "$tmp" <<'EOF'; then ok; else bad "learned modulus factor"; fi
import csv, json, statistics, sys
d = sys.argv[1]
failed = []
def check(cond, what):
    print(('ok   ' if cond else 'FAIL ') + what)
    if not cond:
        failed.append(what)
def summary(name):
    return json.load(open('%s/%s.json' % (d, name)))['summary']
def rows(name):
    truth = {int(r['apple_id']): r for r in csv.DictReader(open('%s/%s.truth.csv' % (d, name)))}
    out = []
    for r in csv.DictReader(open('%s/%s.csv' % (d, name))):
        r['truth'] = truth[int(r['apple_id'])]
        out.append(r)
    return out
def ratio(r):
    return float(r['modulus_from_resonance_pa']) / float(r['fitted_modulus_pa'])
def rel(a, b):
    return abs(a / b - 1.0)

for F in (0.85, 1.15):
    s = summary('k%g' % F)
    est, n = s['modulus_factor_learned'], s['modulus_factor_learned_strikes']
    check(n >= 5 and rel(est, F) <= 0.02,
          'constant F %.2f: learned %.4f (%+.2f %%) from %d reliable strikes' % (F, est, 100 * (est / F - 1), n))
    check(s['modulus_factor_learned_ci95_low'] <= F <= s['modulus_factor_learned_ci95_high'],
          'constant F %.2f: 95 %% interval [%.4f, %.4f] holds it' % (F, s['modulus_factor_learned_ci95_low'], s['modulus_factor_learned_ci95_high']))
    check(s['modulus_factor_applied'] == 1 and s['modulus_factor_changes'] == 0, 'apply off: applied 1, no change')

for seed in range(1, 6):
    s = summary('s%d' % seed)
    est, n = s['modulus_factor_learned'], s['modulus_factor_learned_strikes']
    taken = [float(r['truth']['modulus_factor']) for r in rows('s%d' % seed) if r['reliable'] == '1']
    sample = statistics.median(taken)
    check(rel(est, 0.85) <= 0.02, 'spread 5 %%, seed %d: learned %.4f (%+.2f %% of 0.85) from %d of 120 strikes'
          % (seed, est, 100 * (est / 0.85 - 1), n))
    check(rel(est, sample) <= 0.005, '  and %+.2f %% of the median true factor %.4f of the strikes taken'
          % (100 * (est / sample - 1), sample))

s0, s20 = summary('u0'), summary('u20')
r20 = rows('u20')
clipped = [r for r in r20 if r['truth']['clipped'] == '1']
reliable = [r for r in r20 if r['reliable'] == '1']
check(0.12 <= len(clipped) / len(r20) <= 0.28, '%d of %d strikes clipped' % (len(clipped), len(r20)))
check(not any(r['reliable'] == '1' for r in clipped), 'no clipped strike reliable')
check(s20['modulus_factor_learned_strikes'] == len(reliable) and
      s20['modulus_factor_learned_refused'] == len(r20) - len(reliable),
      'taken %d = reliable rows %d, refused %d' % (s20['modulus_factor_learned_strikes'], len(reliable),
                                                  s20['modulus_factor_learned_refused']))
median_reliable = statistics.median(ratio(r) for r in reliable)  # measured with factor 1
check(rel(s20['modulus_factor_learned'], median_reliable) <= 1e-9,
      'learned %.6f = median of the reliable rows\' E(0S2)/E2 %.6f' % (s20['modulus_factor_learned'], median_reliable))
check(rel(s20['modulus_factor_learned'], s0['modulus_factor_learned']) <= 0.01,
      'unreliable 20 %%: learned %.4f, without them %.4f (%+.2f %%)' % (
          s20['modulus_factor_learned'], s0['modulus_factor_learned'],
          100 * (s20['modulus_factor_learned'] / s0['modulus_factor_learned'] - 1)))
check(rel(s20['modulus_factor_learned'], 0.85) <= 0.02, '  within 2 % of 0.85')

s = summary('a')
ra = [r for r in rows('a') if r['reliable'] == '1']
check(s['modulus_factor_changes'] == 1 and rel(s['modulus_factor_applied'], 1.15) <= 0.02,
      'apply: %d change, applied %.4f' % (s['modulus_factor_changes'], s['modulus_factor_applied']))
before, after = ra[:10], ra[10:]  # the change comes with the 10th reliable strike
check(all(rel(ratio(r), 1.15) <= 0.02 for r in before), 'apply: the 10 strikes before it measured with 1')
m = statistics.median(ratio(r) for r in after)
check(len(after) >= 10 and rel(m, 1.0) <= 0.02,
      'apply: the %d reliable strikes after it: E(0S2)/E2 median %.4f' % (len(after), m))
check(rel(s['modulus_factor_learned'], 1.15) <= 0.02, 'apply: the learned value is still of the true factor: %.4f' % s['modulus_factor_learned'])
sys.exit(1 if failed else 0)
EOF
# 5. the plot over the session (--plots): modulus_factor.png, 900 x 560 px,
# decoded by ImageMagick; inside the frame (above the legend, right of the
# tick labels): the reliable strikes' green points (44, 160, 44) and the
# estimate's blue lines (31, 119, 180). (The grey of the unreliable points
# is not checked: anti-aliased black text gives the same grey.)
"$FM" "$tmp/u20.bag" --jobs 1 --plots "$tmp/plots" >/dev/null 2>"$tmp/err" ||
  bad "--plots exited $?: $(cat "$tmp/err")"
if convert "$tmp/plots/modulus_factor.png" -depth 8 "$tmp/mf.ppm" 2>"$tmp/err" &&
  $PY - "$tmp/mf.ppm" 2>"$tmp/err" <<'EOF'; then ok; else bad "modulus_factor.png: $(cat "$tmp/err")"; fi
import sys
data = open(sys.argv[1], 'rb').read()
head = data.split(maxsplit=4)
w, h = int(head[1]), int(head[2])
px = head[4]
assert (w, h) == (900, 560), (w, h)
def count(rgb, tol=12):
    n = 0
    for y in range(60, 320):
        row = px[3 * w * y:3 * w * (y + 1)]
        for x in range(125, 855):
            if all(abs(row[3 * x + i] - rgb[i]) <= tol for i in range(3)):
                n += 1
    return n
green, blue = count((44, 160, 44)), count((31, 119, 180))
print('modulus_factor.png: %d green, %d blue px' % (green, blue))
assert green >= 300 and blue >= 300, (green, blue)
EOF

# Bad input: one line naming the row or flag, exit 2.
expect_usage "modulus_factor_learn_min_strikes = 300 must be at most modulus_factor_learn_window = 200" \
  "$tmp/a.bag" --set modulus_factor_learn_min_strikes=300
expect_usage "modulus_factor_learn_min_change = 0.9 is outside the accepted range \[0, 0.5\]" \
  "$tmp/a.bag" --set modulus_factor_learn_min_change=0.9
for args in "--modulus-factor 0.01" "--modulus-factor-spread 0.5" "--unreliable-fraction 1"; do
  # shellcheck disable=SC2086
  "$SB" --strikes 2 --out "$tmp/x.bag" $args >/dev/null 2>"$tmp/err"
  code=$?
  if [ $code -eq 2 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q -- "$args is outside the accepted range \[" "$tmp/err"; then
    ok
  else
    bad "strike_bag $args: exit $code, $(cat "$tmp/err")"
  fi
done
echo "test_factor_learn: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
