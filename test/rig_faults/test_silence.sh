#!/usr/bin/env bash
# Digital silence: what sound cards and recorders write between sounds (exact
# zeros through a noise gate or padding), in signals written here with
# Python's struct, never by the station's own code:
#  - firmness_model analyze --tap-only on 10 s of exact zeros (raw float32,
#    16-bit WAV): no strike, "no audio onset" said;
#  - the same zeros with one decaying 680 Hz tap at 5 s, and with a tap after
#    10 s of zeros (float and 16-bit): exactly one strike, within 1 ms of it;
#  - a noise gate opening onto noise 20 ms before a tap: exactly one strike,
#    at the tap; a DC step of 0.1: no strike;
#  - firmness_report on a 10-strike strike_bag --tap-only bag whose audio is
#    all exact zeros: no strike; exact zeros between taps
#    (test/rig_faults/gate_bag.py), the gate opening at each tap and 20 ms
#    before it: every strike once, within 1 ms.
set -uo pipefail
# shellcheck disable=SC1091
source "$(dirname "$0")/rig_faults.sh"
fm=$rig_bin/firmness_model
py=/usr/bin/python3

# write KIND OUT SECONDS [TAP_S]: zeros (KIND zeros), one tap at TAP_S (tap),
# a gate opening onto 1e-3 RMS of noise 20 ms before the tap (gate), or a
# step to 0.1 at TAP_S (dc); OUT .wav = 16-bit PCM, else raw float32.
write() {
  "$py" - "$@" <<'PYEOF'
import math, random, struct, sys
RATE = 48000
kind, out, n = sys.argv[1], sys.argv[2], int(float(sys.argv[3]) * RATE)
t0 = float(sys.argv[4]) if len(sys.argv) > 4 else 0.0
r = random.Random(7)
def tap(t):  # one mode, Q 30, 0.3 of full scale
    return 0.3 * math.exp(-math.pi * 680.0 * t / 30.0) * math.sin(2 * math.pi * 680.0 * t) if t >= 0 else 0.0
x = [0.0] * n
for k in range(n):
    t = k / RATE
    if kind == "tap":
        x[k] = tap(t - t0)
    elif kind == "gate" and t >= t0 - 0.02:
        x[k] = 1e-3 * r.gauss(0, 1) + tap(t - t0)
    elif kind == "dc" and t >= t0:
        x[k] = 0.1
if out.endswith(".wav"):
    s = [max(-32768, min(32767, int(round(v * 32768.0)))) for v in x]
    data = struct.pack("<%dh" % n, *s)
    fmt = struct.pack("<IHHIIHH", 16, 1, 1, RATE, 2 * RATE, 2, 16)
    open(out, "wb").write(b"RIFF" + struct.pack("<I", 36 + len(data)) + b"WAVE" + b"fmt " + fmt
                          + b"data" + struct.pack("<I", len(data)) + data)
else:
    open(out, "wb").write(struct.pack("<%df" % n, *x))
PYEOF
}

# strikes NAME N [TAP_S...]: the case's JSON holds N strikes, each within
# 1 ms of the tap times given.
strikes() {
  local name=$1
  shift
  if ! "$py" - "$tmp/$name.out" "$@" <<'PYEOF'; then
import json, sys
s = json.load(open(sys.argv[1]))["strikes"]
n, taps = int(sys.argv[2]), [float(t) for t in sys.argv[3:]]
print("  %d strikes (want %d)" % (len(s), n))
ok = len(s) == n and all(abs(r["stamp_ns"] * 1e-9 - t) <= 0.001 for r, t in zip(s, taps))
sys.exit(0 if ok else 1)
PYEOF
    echo "  FAIL $name: strike count or times" >&2
    hostile_failed=$((hostile_failed + 1))
  fi
}

tap_only=(analyze --tap-only --mass 0.18 --R2 0.035 --max-samples 1000000)
write zeros "$tmp/zeros.f32" 10
write zeros "$tmp/zeros.wav" 10
write tap "$tmp/tap.f32" 10 5.0
write tap "$tmp/tap.wav" 10 5.0
write tap "$tmp/late.f32" 10.5 10.0
write tap "$tmp/late.wav" 10.5 10.0
write gate "$tmp/gate.f32" 2 1.0
write gate "$tmp/gate.wav" 2 1.0
write dc "$tmp/dc.f32" 2 1.0

hostile_case zeros_f32 0 'no audio onset' 60 256 -- "$fm" "${tap_only[@]}" --audio "$tmp/zeros.f32" --rate-audio 48000
strikes zeros_f32 0
hostile_case zeros_wav 0 'no audio onset' 60 256 -- "$fm" "${tap_only[@]}" --audio "$tmp/zeros.wav"
strikes zeros_wav 0
hostile_case tap_f32 0 '' 60 256 -- "$fm" "${tap_only[@]}" --audio "$tmp/tap.f32" --rate-audio 48000
strikes tap_f32 1 5.0
hostile_case tap_wav 0 '' 60 256 -- "$fm" "${tap_only[@]}" --audio "$tmp/tap.wav"
strikes tap_wav 1 5.0
hostile_case late_f32 0 '' 60 256 -- "$fm" "${tap_only[@]}" --audio "$tmp/late.f32" --rate-audio 48000
strikes late_f32 1 10.0
hostile_case late_wav 0 '' 60 256 -- "$fm" "${tap_only[@]}" --audio "$tmp/late.wav"
strikes late_wav 1 10.0
hostile_case gate_f32 0 '' 60 256 -- "$fm" "${tap_only[@]}" --audio "$tmp/gate.f32" --rate-audio 48000
strikes gate_f32 1 1.0
hostile_case gate_wav 0 '' 60 256 -- "$fm" "${tap_only[@]}" --audio "$tmp/gate.wav"
strikes gate_wav 1 1.0
hostile_case dc_f32 0 'no audio onset' 60 256 -- "$fm" "${tap_only[@]}" --audio "$tmp/dc.f32" --rate-audio 48000
strikes dc_f32 0

# firmness_report: a tap-only bag of 10 s, its audio all exact zeros, and
# exact zeros but around each tap.
"$rig_bin/strike_bag" --strikes 10 --spacing 1.0 --seed 30 --tap-only --out "$tmp/t.bag" >/dev/null 2>&1 ||
  { echo "test_silence: strike_bag failed" >&2; exit 1; }
for open_s in never 0 0.02; do
  name=report_gate_$open_s
  "$py" "$(dirname "$0")/gate_bag.py" "$tmp/t.bag" "$tmp/t.truth.csv" "$tmp/$name.bag" "$open_s" ||
    { echo "test_silence: gate_bag.py failed" >&2; exit 1; }
  hostile_case "$name" 0 '' 120 256 -- "$rig_bin/firmness_report" "$tmp/$name.bag" \
    --set tap_only=true --csv "$tmp/$name.csv"
  if ! "$py" - "$tmp/$name.csv" "$tmp/t.truth.csv" "$open_s" <<'PYEOF'; then
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
truth = sorted(float(r["contact_start_s"]) for r in csv.DictReader(open(sys.argv[2])))
if sys.argv[3] == "never":
    truth = []
got = sorted(int(r["stamp_ns"]) * 1e-9 for r in rows)
print("  %d strikes (want %d)" % (len(got), len(truth)))
sys.exit(0 if len(got) == len(truth) and all(abs(a - b) <= 0.001 for a, b in zip(got, truth)) else 1)
PYEOF
    echo "  FAIL $name: strike count or times" >&2
    hostile_failed=$((hostile_failed + 1))
  fi
done

# The force side: a 16-bit force WAV of exact zeros with single-step flickers
# (+-1 LSB of 500 N full scale, 0.015 N), the threshold's own floor set far
# below a step: the format's step bounds it, no strike.
"$py" - "$tmp/flicker_f.wav" "$tmp/flicker_a.wav" <<'PYEOF'
import struct, sys, wave
def save(path, rate, x):
    with wave.open(path, "wb") as w:
        w.setnchannels(1); w.setsampwidth(2); w.setframerate(rate)
        w.writeframes(b"".join(struct.pack("<h", v) for v in x))
f = [0] * 50000
for k in range(5000, 50000, 7919):
    f[k] = 1 if (k // 7919) % 2 else -1
save(sys.argv[1], 50000, f)
save(sys.argv[2], 48000, [0] * 48000)
PYEOF
"$fm" analyze --force "$tmp/flicker_f.wav" --audio "$tmp/flicker_a.wav" --force-scale 500 \
  --mass 0.18 --R2 0.035 --set strike_threshold_min_n=0.001 >"$tmp/flicker.json" 2>"$tmp/flicker.err"
n=$("$py" -c "import json,sys; print(len(json.load(open(sys.argv[1]))['strikes']))" "$tmp/flicker.json" 2>&1)
if [ "$n" = 0 ]; then
  echo "force_step_flicker: ok (0 strikes)"
else
  echo "  FAIL force_step_flicker: $n strikes from one-step flickers after exact zeros" >&2
  hostile_failed=$((hostile_failed + 1))
fi
hostile_done
