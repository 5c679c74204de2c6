#!/usr/bin/env bash
# CLI tests of `firmness_model analyze`: strikes synthesised by the standard
# library of Debian's python3 (a Hertz contact with hysteresis damping
# integrated by RK4, sampled at 50 kHz with noise, hum and an offset; audio
# at 48 kHz: the 0S2 as a decaying sinusoid with a louder mode above the
# searched range and white noise), written as raw little-endian float32; the
# JSON checked against that truth; bad input exits 2 naming the flag or file.
# Usage: test_analyze.sh /path/to/firmness_model
source "$(dirname "$0")/harness.sh" "$@"

# The recording: 3 strikes of the default strike (10 g hammer, 1.4 m/s, E2
# 8 MPa, nu 0.35, R2 40 mm, e 0.6 by the exact law's chi 0.975) at 0.1, 0.4
# and 0.7 s (+ a sub-sample offset); truth in truth.json.
"$PY" - "$tmp" <<'EOF'
import json, math, random, struct, sys
out = sys.argv[1]
rnd = random.Random(20240611)
m1, v0, g, E2, nu, R, chi = 0.010, 1.4, 9.80665, 8e6, 0.35, 0.04, 0.975
K = 4.0 / 3.0 * E2 / (1 - nu * nu) * math.sqrt(R)

def accel(d, v):
    f = K * d ** 1.5 * (1 + chi * v / v0) if d > 0 else 0.0
    return g - f / m1, f

# RK4 at 0.25 us until the deformation returns to zero
h, d, v, t, fine = 0.25e-6, 0.0, v0, 0.0, [0.0]
while True:
    k1 = accel(d, v)[0]
    k2 = accel(d + h / 2 * v, v + h / 2 * k1)[0]
    k3 = accel(d + h / 2 * (v + h / 2 * k1), v + h / 2 * k2)[0]
    k4 = accel(d + h * (v + h / 2 * k2), v + h * k3)[0]
    d_new = d + h * v + h * h / 6 * (k1 + k2 + k3)
    v = v + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    t += h
    if d_new <= 0:
        tc = t - h + h * d / (d - d_new)  # linear crossing
        break
    d = d_new
    fine.append(max(accel(d, v)[1], 0.0))

def force_at(s):
    if s <= 0 or s >= tc:
        return 0.0
    u = s / h
    j = int(u)
    if j + 1 < len(fine):
        return fine[j] + (u - j) * (fine[j + 1] - fine[j])
    return fine[-1] * (tc - s) / (tc - (len(fine) - 1) * h)

peak = max(fine)
fs_f, fs_a, span = 50000.0, 48000.0, 1.0
starts = [0.1 + 0.3 * i + rnd.random() / fs_f for i in range(3)]
sigma_f = peak / 100.0  # 40 dB
force = []
for k in range(int(span * fs_f)):
    t = k / fs_f
    x = 1.5 + 0.2 * t + sigma_f * math.sin(2 * math.pi * 50 * t) + rnd.gauss(0, sigma_f)
    for t0 in starts:
        if t0 < t < t0 + tc:
            x += force_at(t - t0)
    force.append(x)
f0, q0 = 650.0, 30.0
modes = [(f0, q0, 1.0), (2300.0, 25.0, 3.0)]  # the louder one above the range
audio = []
for k in range(int(span * fs_a)):
    t = k / fs_a
    x = rnd.gauss(0, 10 ** (-30 / 20))  # 30 dB below the 0S2's amplitude
    for t0 in starts:
        s = t - t0
        if 0 <= s < 0.3:
            for f, q, a in modes:
                x += a * math.exp(-math.pi * f / q * s) * math.cos(2 * math.pi * f * s)
    audio.append(x)
with open(out + "/force.f32", "wb") as fp:
    fp.write(struct.pack("<%df" % len(force), *force))
with open(out + "/audio.f32", "wb") as fp:
    fp.write(struct.pack("<%df" % len(audio), *audio))
# the same audio, its recording started 50 ms later
skip = int(0.05 * fs_a)
with open(out + "/audio_late.f32", "wb") as fp:
    fp.write(struct.pack("<%df" % (len(audio) - skip), *audio[skip:]))
# Lamb: E = 2 (1 + nu) rho (2 pi f a / xi)^2, xi(0.35) = 2.6519, a of 175 g at 840 kg/m3
a = (3 * 0.175 / (4 * math.pi * 840)) ** (1 / 3)
E_f = 2 * (1 + nu) * 840 * (2 * math.pi * f0 * a / 2.6519) ** 2
json.dump({"starts": starts, "tc": tc, "peak": peak, "f0": f0, "E_f": E_f},
          open(out + "/truth.json", "w"))
EOF
[ -s "$tmp/force.f32" ] && [ -s "$tmp/audio.f32" ] || { echo "test_analyze: synthesis failed" >&2; exit 1; }
printf 'abc' >"$tmp/odd.f32"  # 3 bytes: not float32
: >"$tmp/empty.f32"

base=(--rate-force 50000 --rate-audio 48000 --mass 0.175 --R2 0.04)

# json_check 'python expression on d (the report list) and t (the truth)' args...
json_check() {
  local expr=$1
  shift
  if "$FM" analyze "$@" >"$tmp/json" 2>"$tmp/err" &&
    "$PY" -c "
import json, sys
d = json.load(open('$tmp/json'))
t = json.load(open('$tmp/truth.json'))
sys.exit(0 if ($expr) else 1)"; then
    ok
  else
    bad "'analyze $*' does not satisfy: $expr ($(head -c 2000 "$tmp/json"; cat "$tmp/err"))"
  fi
}

run=(--force "$tmp/force.f32" --audio "$tmp/audio.f32" "${base[@]}")
keys="contact_start_s contact_time_s peak_force_N impulse_Ns band_low_Hz band_high_Hz resonance_Hz resonance_q snr_dB stiffness_factor modulus_from_resonance_Pa fitted_modulus_Pa fitted_restitution fit_residual double_hit clipped lost_samples excites_mode no_damage reliable reason"
pykeys=$(printf "'%s'," $keys)
# one report per strike, each with exactly the keys, at the strike's time
json_check "len(d) == 3 and all(set(r) == {$pykeys} for r in d)" "${run[@]}"
json_check "all(abs(r['contact_start_s'] - s) < 2e-5 for r, s in zip(d, t['starts']))" "${run[@]}"
# the 0S2 within 0.5 %, the modulus from it within 1 %
json_check "all(abs(r['resonance_Hz'] - t['f0']) < 0.005 * t['f0'] for r in d)" "${run[@]}"
json_check "all(abs(r['modulus_from_resonance_Pa'] - t['E_f']) < 0.01 * t['E_f'] for r in d)" "${run[@]}"
# contact time within the detector's 4 % (1.0-1.2 % RMS at 40 dB), peak 2 %
json_check "all(abs(r['contact_time_s'] - t['tc']) < 0.04 * t['tc'] for r in d)" "${run[@]}"
json_check "all(abs(r['peak_force_N'] - t['peak']) < 0.02 * t['peak'] for r in d)" "${run[@]}"
# the fit: E2 within 3 %, e within 0.05 (chi 0.975 is the exact law's e 0.6)
json_check "all(abs(r['fitted_modulus_Pa'] - 8e6) < 0.03 * 8e6 and abs(r['fitted_restitution'] - 0.6) < 0.05 for r in d)" "${run[@]}"
# clean strikes: no flags; 650 Hz inside the default strike's main lobe band; reliable
json_check "all(r['double_hit'] is False and r['clipped'] is False and r['lost_samples'] == 0 for r in d)" "${run[@]}"
json_check "all(r['reliable'] is True and r['reason'] == '' and r['snr_dB'] > 15 for r in d)" "${run[@]}"
# the audio recording started 50 ms late, said so: the same resonances
json_check "len(d) == 3 and all(abs(r['resonance_Hz'] - t['f0']) < 0.005 * t['f0'] for r in d)" \
  --force "$tmp/force.f32" --audio "$tmp/audio_late.f32" --audio-offset 0.05 "${base[@]}"
# the force alone (audio of nothing): measured, unreliable, resonance null, reason "no audio"
json_check "len(d) == 3 and all(r['resonance_Hz'] is None and r['reliable'] is False and r['reason'] == 'no audio' for r in d)" \
  --force "$tmp/force.f32" --audio "$tmp/empty.f32" "${base[@]}"
# no force: no strikes
json_check "d == []" --force "$tmp/empty.f32" --audio "$tmp/audio.f32" "${base[@]}"
# model flags land: the paper profile reads lobe 2 at power-half, which never holds the 0S2
json_check "len(d) == 3 and all(r['excites_mode'] is False and 'lobe 2' in r['reason'] for r in d)" \
  "${run[@]}" --profile paper

# expect_analyze_usage pattern args...: as expect_usage, for `analyze args`.
expect_analyze_usage() {
  local pattern=$1
  shift
  expect_usage "$pattern" analyze "$@"
}

A=(--audio "$tmp/audio.f32")
F=(--force "$tmp/force.f32")
expect_analyze_usage "--force" "${A[@]}" "${base[@]}"
expect_analyze_usage "--audio" "${F[@]}" "${base[@]}"
expect_analyze_usage "--rate-force" "${F[@]}" "${A[@]}" --rate-audio 48000 --mass 0.175 --R2 0.04
expect_analyze_usage "--rate-force" "${F[@]}" "${A[@]}" --rate-force abc --rate-audio 48000 --mass 0.175 --R2 0.04
expect_analyze_usage "--rate-audio" "${F[@]}" "${A[@]}" --rate-force 50000 --rate-audio 0 --mass 0.175 --R2 0.04
expect_analyze_usage "--rate-audio" "${F[@]}" "${A[@]}" --rate-force 50000 --rate-audio -48000 --mass 0.175 --R2 0.04
expect_analyze_usage "--mass" "${F[@]}" "${A[@]}" --rate-force 50000 --rate-audio 48000 --R2 0.04
expect_analyze_usage "--R2" "${F[@]}" "${A[@]}" --rate-force 50000 --rate-audio 48000 --mass 0.175
expect_analyze_usage "--R2" "${F[@]}" "${A[@]}" "${base[@]}" --R2 -0.01
expect_analyze_usage "--mass" "${F[@]}" "${A[@]}" "${base[@]}" --mass 0
expect_analyze_usage "--audio-offset" "${F[@]}" "${A[@]}" "${base[@]}" --audio-offset nan
expect_analyze_usage "--audio-offset" "${F[@]}" "${A[@]}" "${base[@]}" --audio-offset
expect_analyze_usage "--bogus" "${F[@]}" "${A[@]}" "${base[@]}" --bogus 1
expect_analyze_usage "$tmp/missing.f32" --force "$tmp/missing.f32" "${A[@]}" "${base[@]}"
expect_analyze_usage "$tmp/missing.f32" "${F[@]}" --audio "$tmp/missing.f32" "${base[@]}"
expect_analyze_usage "$tmp/odd.f32" --force "$tmp/odd.f32" "${A[@]}" "${base[@]}"
expect_analyze_usage "$tmp/odd.f32" "${F[@]}" --audio "$tmp/odd.f32" "${base[@]}"
expect_analyze_usage "--modulus-max" "${F[@]}" "${A[@]}" "${base[@]}" --modulus-min 12e6 --modulus-max 2e6

summary test_analyze
