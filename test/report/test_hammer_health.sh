#!/usr/bin/env bash
# The hammer health (src/core/lane/hammer_health.h) through firmness_report on
# replayed shifts made by strike_bag, whose force comes from its own RK4
# (af_synth_pulse_rk4), not from the fit nor the detector; the expected
# figures come from strike_bag's truth CSV (each strike's contact velocity)
# and from the force offset strike_bag adds (0.4 N + 0.01 N/s, make_chunk):
#  - a constant v0 over 100 strikes: never warned; v0 from the impulse within
#    0.3 % of the truth;
#  - v0 ramping +5 % over 100 strikes (--velocity-drift 0.05): warned, not
#    before the true v0 leaves the +-3 % band, at most 15 strikes after, and
#    where the truth's own 20-strike mean leaves it, give or take what the
#    per-strike v0's error against the truth moves that crossing: its bias
#    plus 3 sigma / sqrt(20), over the ramp's slope, plus a strike; the fitted v0
#    (measure_fit_velocity) within 0.5 % of the truth; -5 % too;
#  - the baseline check (limit 0.2 N) within 2 strikes of the offset's law;
#  - the clipping check (full scale 36 N): the window's clipped strikes
#    against the truth's peaks;
#  - bad input: --velocity-drift out of range, min strikes above the window.
#   test_hammer_health.sh FIRMNESS_REPORT STRIKE_BAG
source "$(dirname "$0")/../cli/harness.sh" "$1"
SB=${2:?path to strike_bag}
N=100

"$SB" --strikes $N --seed 3 --out "$tmp/c.bag" >/dev/null 2>&1 || bad "strike_bag (constant) failed"
"$SB" --strikes $N --seed 3 --velocity-drift 0.05 --out "$tmp/u.bag" >/dev/null 2>&1 ||
  bad "strike_bag (+5 %) failed"
"$SB" --strikes $N --seed 4 --velocity-drift -0.05 --out "$tmp/n.bag" >/dev/null 2>&1 ||
  bad "strike_bag (-5 %) failed"

# report NAME BAG [--set ...]: the JSON report in $tmp/NAME.json
report() {
  local name=$1 bag=$2
  shift 2
  "$FM" "$bag" --jobs 1 --json "$@" >"$tmp/$name.json" 2>"$tmp/err" ||
    bad "report $name exited $?: $(cat "$tmp/err")"
}
report c "$tmp/c.bag"
report u "$tmp/u.bag"
report uf "$tmp/u.bag" --set measure_fit_velocity=true
report n "$tmp/n.bag"
report b "$tmp/c.bag" --set hammer_health_baseline_drift_n=0.2
report k "$tmp/c.bag" --set strike_full_scale_n=36

# check NAME TRUTH CODE: runs the Python CODE with h (the summary's
# hammer_health), t (the truth rows) and the helpers below.
check() {
  local name=$1 truth=$2 what=$3
  if $PY - "$tmp/$name.json" "$truth" <<EOF; then ok; else bad "$what"; fi
import csv, json, sys
h = json.load(open(sys.argv[1]))['summary']['hammer_health']
t = list(csv.DictReader(open(sys.argv[2])))
v = [float(r['velocity_m_s']) for r in t]
SET, BAND, W, MIN = 1.4, 0.03, 20, 10  # strike_velocity_m_s and the hammer_health_* defaults
def first(pred):  # 1-based strike number of the first k with pred(k), or None
    return next((k + 1 for k in range(len(t)) if pred(k)), None)
def win_mean(x, k):  # mean of the newest W values up to k
    s = x[max(0, k - W + 1):k + 1]
    return sum(s) / len(s)
def slack():  # strikes the v0 error's bias and the window mean's scatter (3 sigma) move a
    # crossing of the ramp, plus one; and the per-strike error's RMS
    e = [g / r - 1 for g, r in zip(h['velocity_m_s_per_strike'], v) if g is not None]
    bias = sum(e) / len(e)
    sd = (sum((x - bias) ** 2 for x in e) / len(e)) ** 0.5
    slope = abs(v[-1] - v[0]) / SET / (len(v) - 1)  # per strike
    return (abs(bias) + 3 * sd / W ** 0.5) / slope + 1, (bias * bias + sd * sd) ** 0.5
$(cat)
EOF
}

check c "$tmp/c.truth.csv" "constant v0: warned, or v0 off the truth" <<'EOF'
assert h['status'] == 'ok' and h['text'] == '' and h['warned_strikes'] == 0, h
assert all(x is None for x in h['first_warning_strike'].values()), h
truth = win_mean(v, len(v) - 1)
print('constant: v0 %.5f m/s from the impulse, truth %.5f (%+.3f %%), SD %.5f' % (
    h['velocity_m_s'], truth, 100 * (h['velocity_m_s'] / truth - 1), h['velocity_sd_m_s']))
assert abs(h['velocity_m_s'] / truth - 1) < 0.003, h
assert len(h['velocity_m_s_per_strike']) == 100
assert h['strikes'] == 100 and h['window_strikes'] == W and h['velocity_strikes'] == W, h
EOF

check u "$tmp/u.truth.csv" "+5 % drift: not detected in time" <<'EOF'
got = h['first_warning_strike']['velocity']
leaves = first(lambda k: v[k] / SET - 1 > BAND)
ideal = first(lambda k: k + 1 >= MIN and win_mean(v, k) / SET - 1 > BAND)
s, sd = slack()
print('+5 %%: true v0 leaves the band at strike %d, its %d-strike mean at %d; warned at %s '
      '(per-strike v0 %.3f %% RMS against the truth: +- %.1f strikes)' % (leaves, W, ideal, got, 100 * sd, s))
assert got is not None and leaves <= got <= leaves + 15 and abs(got - ideal) <= s, (got, leaves, ideal)
assert h['status'] == 'warn' and 'strike_velocity_m_s' in h['text'] and '3.0 %' in h['text'], h
assert h['first_warning_strike']['baseline'] is None and h['first_warning_strike']['clipping'] is None
EOF

check uf "$tmp/u.truth.csv" "+5 % drift: fitted v0 off the truth" <<'EOF'
truth = win_mean(v, len(v) - 1)
print('+5 %%: fitted v0 %.5f m/s, from the impulse %.5f, truth %.5f' %
      (h['fit_velocity_m_s'], h['velocity_m_s'], truth))
assert abs(h['fit_velocity_m_s'] / truth - 1) < 0.005, h
EOF

check n "$tmp/n.truth.csv" "-5 % drift: not detected in time" <<'EOF'
got = h['first_warning_strike']['velocity']
leaves = first(lambda k: v[k] / SET - 1 < -BAND)
ideal = first(lambda k: k + 1 >= MIN and win_mean(v, k) / SET - 1 < -BAND)
s, sd = slack()
print('-5 %%: true v0 leaves the band at strike %d, its mean at %d; warned at %s '
      '(per-strike v0 %.3f %% RMS: +- %.1f strikes)' % (leaves, ideal, got, 100 * sd, s))
assert got is not None and leaves <= got <= leaves + 15 and abs(got - ideal) <= s, (got, leaves, ideal)
EOF

check b "$tmp/c.truth.csv" "baseline drift: not where the offset's law puts it" <<'EOF'
start = 1700000000.0  # strike_bag's bag start [s]
base = [0.4 + 0.01 * (float(r['contact_start_s']) - start) for r in t]  # make_chunk's offset
ref = sum(base[:MIN]) / MIN
ideal = first(lambda k: k + 1 >= MIN and abs(win_mean(base, k) - ref) > 0.2)
got = h['first_warning_strike']['baseline']
print('baseline: the offset law drifts 0.2 N at strike %d; warned at %s; drift %.4f N (law %.4f)' %
      (ideal, got, h['baseline_drift_n'], win_mean(base, len(base) - 1) - ref))
assert got is not None and abs(got - ideal) <= 2, (got, ideal)
assert abs(h['baseline_drift_n'] - (win_mean(base, len(base) - 1) - ref)) < 0.02, h
assert 'hammer_health_baseline_drift_n 0.2 N' in h['text'], h
EOF

check k "$tmp/c.truth.csv" "clipping: not as the truth's peaks say" <<'EOF'
start = 1700000000.0
raw = [float(r['peak_force_n']) + 0.4 + 0.01 * (float(r['contact_start_s']) - start) for r in t]
last = raw[-W:]
lo = sum(x >= 36.5 for x in last)  # surely clipped (the noise and hum are about 0.3 N)
hi = sum(x >= 35.5 for x in last)  # possibly clipped
print('clipping: %d of the last %d strikes clipped; the truth says %d to %d' %
      (h['clipped_strikes'], W, lo, hi))
assert lo <= h['clipped_strikes'] <= hi and h['clipped_strikes'] / W > 0.05, h
assert h['first_warning_strike']['clipping'] is not None and 'hammer_health_clip_rate' in h['text']
EOF

# --- the plot over the session: a PNG ------------------------------------------------
"$FM" "$tmp/u.bag" --jobs 1 --plots "$tmp/plots" >/dev/null 2>"$tmp/err" || bad "--plots exited $?: $(cat "$tmp/err")"
if [ "$(head -c 4 "$tmp/plots/hammer_velocity.png" 2>/dev/null | od -An -tx1 | tr -d ' \n')" = 89504e47 ]; then
  ok
else
  bad "--plots drew no hammer_velocity.png"
fi

# --- bad input ---------------------------------------------------------------------
"$SB" --strikes 3 --out "$tmp/x.bag" --velocity-drift 0.9 >"$tmp/out" 2>"$tmp/err"
code=$?
if [ $code -eq 2 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ] &&
  grep -q -- "--velocity-drift 0.9 is outside the accepted range \[-0.5, 0.5\]" "$tmp/err"; then ok; else
  bad "strike_bag --velocity-drift 0.9: exit $code, $(cat "$tmp/err")"
fi
expect_usage "hammer_health_min_strikes = 30 must be at most hammer_health_window = 20" \
  "$tmp/c.bag" --set hammer_health_min_strikes=30
expect_usage "hammer_health_velocity_band" "$tmp/c.bag" --set hammer_health_velocity_band=0

summary test_hammer_health
