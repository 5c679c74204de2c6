#!/usr/bin/env bash
# Fruit or not: a heard mode counts as the fruit's 0S2 only when it rings
# like fruit flesh (its Q within fruit_q_min..fruit_q_max, 5..80). Signals
# made here with Python's standard library, not the package's code:
#  - rings of one mode at 600 Hz with Q 300 and Q 1000 (ceramic, glass) and
#    a 680 Hz mode with Q 2 (a dull thud): whatever is found of them never
#    reliable, never graded; the Q 300 ring's strikes flagged not_fruit;
#  - fruit-like taps (test/cli/tap_synth.py: the 0S2 with Q 30, a louder 0S3,
#    0S4, 1S2, a support mode, 30 dB SNR): every tap reliable and graded.
set -uo pipefail
here=$(dirname "$0")
# shellcheck disable=SC1091
source "$here/rig_faults.sh"
ring() { # OUT.wav F_HZ Q: 5 strikes 0.4 s apart, 30 dB above white noise, 16-bit
  /usr/bin/python3 - "$@" <<'PY'
import math, random, struct, sys, wave
out, f, q = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
rate, n = 48000, int(48000 * 2.2)
rnd = random.Random(7)
x = [0.0] * n
for k in range(5):
    t0 = int((0.1 + 0.4 * k) * rate)
    for i in range(t0, n):
        t = (i - t0) / rate
        a = math.exp(-math.pi * f / q * t)
        if a < 1e-6:
            break
        x[i] += 0.5 * a * math.sin(2 * math.pi * f * t)
sd = 0.5 / math.sqrt(2) / 10 ** (30 / 20)
with wave.open(out, 'wb') as w:
    w.setnchannels(1)
    w.setsampwidth(2)
    w.setframerate(rate)
    w.writeframes(b''.join(struct.pack('<h', max(-32767, min(32767, int(round(32767 * (v + rnd.gauss(0, sd))))))) for v in x))
PY
}
counts() { # JSON: strikes, reliable, not_fruit, graded
  /usr/bin/python3 -c "
import json, sys
d = json.load(open(sys.argv[1]))['strikes']
print('strikes %d reliable %d not_fruit %d graded %d' % (len(d), sum(s['reliable'] for s in d),
      sum('not_fruit' in s['flags'] for s in d), sum(s['grade_index'] > 0 for s in d)))" "$1"
}
for c in "600 300" "600 1000" "680 2"; do
  set -- $c
  ring "$tmp/ring_$1_$2.wav" "$1" "$2"
  "$rig_bin/firmness_model" analyze --tap-only --audio "$tmp/ring_$1_$2.wav" --mass 0.18 --R2 0.035 \
    >"$tmp/ring_$1_$2.json" 2>"$tmp/ring_$1_$2.err"
  got=$(counts "$tmp/ring_$1_$2.json")
  # Whatever is found of a ring: none reliable, none graded.
  check "ring_${1}Hz_Q$2" "$got" 'reliable 0 not_fruit [0-9]+ graded 0$'
done
# The Q 300 ring's strikes are heard (its decay leaves onsets) and refused as not fruit.
check ring_300_not_fruit "$(counts "$tmp/ring_600_300.json")" 'strikes [1-9][0-9]* reliable 0 not_fruit [1-9][0-9]* graded 0$'

check ring_reason "$(/usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['strikes'][0]['reason'])" "$tmp/ring_600_300.json")" \
  '^Q [0-9]+ at 60[0-9] Hz: a ringing object, not fruit flesh \(fruit_q_min\.\.fruit_q_max 5\.\.80\)'
/usr/bin/python3 "$here/../cli/tap_synth.py" "$tmp/fruit.wav" --mass 0.18 --modulus 6e6 --taps 5 >/dev/null
"$rig_bin/firmness_model" analyze --tap-only --audio "$tmp/fruit.wav" --mass 0.18 --R2 0.035 \
  >"$tmp/fruit.json" 2>"$tmp/fruit.err"
check fruit_taps_graded "$(counts "$tmp/fruit.json")" '^strikes 5 reliable 5 not_fruit 0 graded 5$'
rig_done "not fruit"
