#!/usr/bin/env bash
# CLI tests of `firmness_model analyze --tap-only` (a microphone-only
# rig): taps made by test/cli/tap_synth.py (Python's standard library, its own
# mode set with a LOUDER 0S3, noise at 30 dB SNR, 5 ms pre-trigger), as 16-bit
# WAV and as raw float32; every tap found, its 0S2 within 0.5 % and its
# stiffness factor within 1 % of the closed-form truth; the verdict names what
# came from the model; 10 minutes of white noise (os.urandom's bytes as 16-bit
# samples) give no strike; the force flags refused in tap-only mode.
# Usage: test_tap_only.sh /path/to/firmness_model
source "$(dirname "$0")/harness.sh" "$@"
SYNTH="$(dirname "$0")/tap_synth.py"

# check TRUTH_JSON OUT_JSON N_TAPS: the taps and their figures.
check() {
  "$PY" - "$1" "$2" "$3" <<'PYEOF'
import json, sys
truth = json.loads(open(sys.argv[1]).read())
out = json.load(open(sys.argv[2]))
n = int(sys.argv[3])
s = out["strikes"]
errs = []
if len(s) != n:
    errs.append("%d strikes, expected %d" % (len(s), n))
worst_f = worst_sf = 0.0
for k, r in enumerate(s):
    t_s = r["stamp_ns"] * 1e-9
    if k < len(truth["onsets_s"]) and abs(t_s - truth["onsets_s"][k]) > 0.001:
        errs.append("strike %d at %.6f s, the tap at %.6f s" % (k, t_s, truth["onsets_s"][k]))
    ef = abs(r["resonance_hz"] / truth["f0_hz"] - 1.0) if r["resonance_hz"] else 1.0
    es = abs(r["stiffness_factor_hz2_kg2_3"] / truth["stiffness_factor"] - 1.0) if r["resonance_hz"] else 1.0
    worst_f, worst_sf = max(worst_f, ef), max(worst_sf, es)
    if not r["tap_only"] or r["judged_from_model"] != (
            "shear judged from the model only"):
        errs.append("strike %d: tap_only %s, judged_from_model '%s'" % (k, r["tap_only"], r["judged_from_model"]))
    if r["fitted_modulus_pa"] is not None or r["peak_force_n"] is not None:
        errs.append("strike %d: a pulse figure without a pulse" % k)
print("0S2 %.3f Hz: worst 0S2 error %.3f %%, stiffness factor %.3f %% over %d strikes"
      % (truth["f0_hz"], 100 * worst_f, 100 * worst_sf, len(s)))
if worst_f > 0.005:
    errs.append("0S2 off by %.3f %% (bound 0.5 %%)" % (100 * worst_f))
if worst_sf > 0.01:
    errs.append("stiffness factor off by %.3f %% (bound 1 %%)" % (100 * worst_sf))
for e in errs:
    print("FAIL:", e, file=sys.stderr)
sys.exit(1 if errs else 0)
PYEOF
}

# Four apples, soft to firm: the 0S3 of the soft ones lies inside the searched range.
i=0
for apple in "0.12 3e6" "0.16 5e6" "0.20 8e6" "0.24 11e6"; do
  set -- $apple
  i=$((i + 1))
  "$PY" "$SYNTH" "$tmp/tap$i.wav" --mass "$1" --modulus "$2" --taps 5 --snr 30 --seed "$i" >"$tmp/truth$i.json"
  if "$FM" analyze --tap-only --audio "$tmp/tap$i.wav" --mass "$1" --R2 0.035 >"$tmp/out$i.json" 2>"$tmp/err"; then
    check "$tmp/truth$i.json" "$tmp/out$i.json" 5 && ok || bad "WAV apple $apple"
  else
    bad "analyze --tap-only on apple $apple exited non-zero: $(cat "$tmp/err")"
  fi
done

# Raw float32 with its rate; tap_only from --set instead of the switch.
"$PY" "$SYNTH" "$tmp/raw.f32" --mass 0.18 --modulus 6e6 --taps 4 --rate 44100 --seed 9 >"$tmp/truth_raw.json"
"$FM" analyze --set tap_only=true --audio "$tmp/raw.f32" --rate-audio 44100 --mass 0.18 --R2 0.035 \
  >"$tmp/out_raw.json" 2>"$tmp/err" && check "$tmp/truth_raw.json" "$tmp/out_raw.json" 4 && ok ||
  bad "raw float32 at 44.1 kHz: $(cat "$tmp/err")"

# Ten minutes of white noise: no strike (the false-trigger rate through analyze).
"$PY" - "$tmp/noise.wav" <<'PYEOF'
import os, sys, wave
with wave.open(sys.argv[1], "wb") as f:
    f.setnchannels(1); f.setsampwidth(2); f.setframerate(48000)
    f.writeframes(os.urandom(2 * 48000 * 600))
PYEOF
"$FM" analyze --tap-only --audio "$tmp/noise.wav" --mass 0.18 --R2 0.035 --max-samples 30000000 \
  >"$tmp/out_noise.json" 2>"$tmp/err"
n_noise=$("$PY" -c 'import json,sys; print(len(json.load(open(sys.argv[1]))["strikes"]))' "$tmp/out_noise.json" 2>/dev/null)
echo "10 min of white noise through analyze --tap-only: ${n_noise:-?} strikes"
[ "${n_noise:-x}" = 0 ] && grep -q 'no audio onset' "$tmp/err" && ok || bad "noise: ${n_noise:-?} strikes; $(cat "$tmp/err")"

# Bad input: each mode's inputs, one line naming the flag.
expect_usage "--force FILE is required (or --tap-only" analyze --audio "$tmp/tap1.wav" --mass 0.18 --R2 0.035
expect_usage "--force $tmp/tap1.wav: tap_only is set" analyze --tap-only --force "$tmp/tap1.wav" \
  --audio "$tmp/tap1.wav" --mass 0.18 --R2 0.035
: >"$tmp/empty.f32"
expect_usage "--audio $tmp/empty.f32 is empty" analyze --tap-only --audio "$tmp/empty.f32" \
  --rate-audio 48000 --mass 0.18 --R2 0.035
expect_usage "onset_snr_db" analyze --tap-only --audio "$tmp/tap1.wav" --mass 0.18 --R2 0.035 \
  --set onset_snr_db=1
# A frame of fewer than 4 samples at a slow audio rate: refused only in tap-only mode.
expect_usage "onset_frame_s = 0.001 gives 1.0 audio samples at 1000 Hz: at least 4" analyze \
  --tap-only --audio "$tmp/raw.f32" --rate-audio 1000 --mass 0.18 --R2 0.035 \
  --set measure_noise_band_low_hz=200

summary test_tap_only
