#!/usr/bin/env bash
# The fruit-or-not gate over sets of taps made by fruit_or_not.py (Python's
# standard library, not the package's code), through `analyze --tap-only`:
#  - fruit-like taps at 30 dB, and the same through a phone's band (100 Hz
#    high-pass, 8 kHz low-pass): every tap found once, >= 99 % graded, the
#    0S2 within 0.06 % and the stiffness factor within 0.12 % of the truth;
#  - rings of ceramic, glass, metal and stone, and a lump whose partials the
#    sphere has not: none graded;
#  - wood, whose Q (50..150) overlaps fruit's below fruit_q_max: only taps
#    whose true Q lies under fruit_q_max (80, +5 % for the Q's estimate) are
#    graded, and none with fruit_confidence_min 0.5, which asks for the comb.
set -uo pipefail
here=$(dirname "$0")
# shellcheck disable=SC1091
source "$here/rig_faults.sh"
gen=$here/fruit_or_not.py
analyze() { # SET [--set ...]: the set's score line
  local s=$1
  shift
  "$rig_bin/firmness_model" analyze --tap-only --audio "$tmp/$s.wav" --mass 0.18 --R2 0.035 "$@" \
    >"$tmp/$s.json" 2>"$tmp/$s.err"
  /usr/bin/python3 "$gen" score "$tmp/$s.truth" "$tmp/$s.json"
}
for s in fruit phone; do
  /usr/bin/python3 "$gen" make "$s" "$tmp/$s.wav" "$tmp/$s.truth" --n 100 --seed 1 &
done
wait
for s in ceramic glass metal stone stray wood; do
  /usr/bin/python3 "$gen" make "$s" "$tmp/$s.wav" "$tmp/$s.truth" --n 30 --seed 2 &
done
wait
for s in fruit phone; do
  got=$(analyze "$s")
  check "${s}_found_once" "$got" "^$s taps 100 strikes 100 "
  check "${s}_graded" "$got" " graded (99|100) not_fruit 0 "
  check "${s}_accuracy" "$(awk '{print ($11 <= 0.06 && $13 <= 0.12) ? "within" : "beyond", $0}' <<<"$got")" '^within'
done
for s in ceramic glass metal stone stray; do
  check "${s}_never_graded" "$(analyze "$s")" " graded 0 "
done
# Wood: each graded tap's true Q under fruit_q_max (80) + 5 %.
analyze wood >/dev/null
wood_q=$(/usr/bin/python3 -c "
import json, sys
taps = json.load(open(sys.argv[1]))['taps']
graded = [s for s in json.load(open(sys.argv[2]))['strikes'] if s['reliable'] and s['grade_index'] > 0]
q = [min(taps, key=lambda p: abs(s['stamp_ns'] * 1e-9 - p['onset_s']))['q'] for s in graded]
print('graded %d, true Q above 84: %d' % (len(q), sum(v > 84 for v in q)))" "$tmp/wood.truth" "$tmp/wood.json")
check wood_q_gate "$wood_q" 'true Q above 84: 0$'
check wood_comb_asked "$(analyze wood --set fruit_confidence_min=0.5)" " graded 0 "
check wood_reason "$(/usr/bin/python3 -c "
import json, sys
print(next(s['reason'] for s in json.load(open(sys.argv[1]))['strikes'] if 'not_fruit' in s['flags']))" "$tmp/wood.json")" \
  '0S2 [0-9]+ Hz at confidence 0\.[0-9]+, below fruit_confidence_min 0\.5'
check stray_reason "$(/usr/bin/python3 -c "
import json, sys
print(next(s['reason'] for s in json.load(open(sys.argv[1]))['strikes'] if 'not_fruit' in s['flags']))" "$tmp/stray.json")" \
  "a partial at 1\.(29|30|31)x the [0-9]+ Hz mode \(\+[0-9]+ dB\), none of the sphere's: not fruit"
rig_done "fruit or not"
