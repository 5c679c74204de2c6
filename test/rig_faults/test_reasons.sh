#!/usr/bin/env bash
# Reasons that tell the truth: each fault below once gave a reason that
# pointed away from its cause. Every input is written here byte by byte
# (python, no code of the package), and each case requires the words that
# name the cause.
set -uo pipefail
# shellcheck disable=SC1091
source "$(dirname "$0")/rig_faults.sh"
fm=$rig_bin/firmness_model
data=$AF_ROOT/test/data # the package's own copies of the real captures (test/data/README.md)
py=/usr/bin/python3

# ---- the force: no finite sample, or the wrong sign ---------------------------
# 25600 NaN at 25.6 kHz; a -31 N pulse (sin^1.5 over 1 ms, at 0.2 s) on
# 0.05 N noise, nothing upwards above the noise.
"$py" - "$tmp" <<'PY'
import math, random, struct, sys
out = sys.argv[1]
n, fs = 25600, 25600.0
open(out + '/nan.f32', 'wb').write(struct.pack('<%df' % n, *([float('nan')] * n)))
rng = random.Random(29)
x = [0.05 * rng.gauss(0.0, 1.0) for _ in range(n)]
k0, w = int(0.2 * fs), int(1e-3 * fs)
for k in range(w + 1):
    x[k0 + k] -= 31.0 * math.sin(math.pi * k / w) ** 1.5
open(out + '/inverted.f32', 'wb').write(struct.pack('<%df' % n, *x))
PY
audio=(--audio "$data/hammer_capture_4.response.f32" --rate-audio 48000 --mass 0.2 --R2 0.03)
# Before: "still in warm-up: 0 of the 512 samples ... largest excursion 0 N".
hostile_case force_all_nan 0 'no strike found: the force recording .*nan.f32 holds no finite sample \(25600 samples, all NaN or infinite\)' \
  10 256 -- "$fm" analyze --force "$tmp/nan.f32" --rate-force 25600 "${audio[@]}"
# Before: "never above threshold: largest excursion 0.2 N ..." (the noise's).
hostile_case force_inverted 0 'no strike found: the largest excursion is -31 N at sample 51[0-9][0-9], against 0\.[0-9]+ N at most upwards: is the force inverted \(transducer polarity\)\?' \
  10 256 -- "$fm" analyze --force "$tmp/inverted.f32" --rate-force 25600 "${audio[@]}"
# The real capture, its sign flipped: a strike is found on the rebound (5 N),
# and the -89 N pulse is named.
"$py" - "$data/hammer_capture_4.force.f32" "$tmp/capture_inverted.f32" <<'PY'
import struct, sys
b = open(sys.argv[1], 'rb').read()
x = struct.unpack('<%df' % (len(b) // 4), b)
open(sys.argv[2], 'wb').write(struct.pack('<%df' % len(x), *[-v for v in x]))
PY
hostile_case force_inverted_capture 0 'warning: the largest excursion in .*capture_inverted.f32 is -88.9 N at sample 22, against 5.1. N for the largest strike found: is the force inverted' \
  10 256 -- "$fm" analyze --force "$tmp/capture_inverted.f32" --rate-force 25600 "${audio[@]}"

hostile_done
