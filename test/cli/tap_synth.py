#!/usr/bin/env python3
"""tap_synth.py — taps of an apple on a microphone-only rig, made with the
standard library alone (not the package's code): an explicit mode set per tap
(0S2; a LOUDER 0S3, 2.5x; 0S4 and 1S2 at the published Lamb ratios for
nu 0.35, PHYSICS.md 5; a support mode at 0.3 f), white Gaussian noise at a
given SNR (the tap's mean square over its first 40 ms against the noise
variance), the first tap PRE seconds after the start (a short pre-trigger).

usage: tap_synth.py OUT.wav|OUT.f32 --mass KG --modulus PA [--taps N]
       [--spacing S] [--pre S] [--snr DB] [--rate HZ] [--seed N] [--noise-only S]
Prints one JSON line: the true 0S2 [Hz], stiffness factor, modulus, onsets [s].
WAV: 16-bit PCM mono; .f32: raw little-endian float32."""
import argparse
import json
import math
import random
import struct
import wave

XI_0S2 = 2.6519  # Lamb's root of the 0S2 at nu 0.35 (PHYSICS.md 5)
NU, RHO = 0.35, 840.0
MODES = [(1.0, 1.0, 30.0), (1.4919, 2.5, 30.0), (1.9153, 0.6, 35.0), (1.9381, 0.4, 35.0),
         (0.3, 0.8, 8.0)]  # (ratio to the 0S2, amplitude, Q)


def f_0s2(mass, modulus):
    a = (3.0 * mass / (4.0 * math.pi * RHO)) ** (1.0 / 3.0)
    return XI_0S2 / (2.0 * math.pi * a) * math.sqrt(modulus / (2.0 * (1.0 + NU) * RHO))


def main():
    p = argparse.ArgumentParser()
    p.add_argument("out")
    p.add_argument("--mass", type=float, default=0.18)
    p.add_argument("--modulus", type=float, default=6e6)
    p.add_argument("--taps", type=int, default=5)
    p.add_argument("--spacing", type=float, default=0.3)
    p.add_argument("--pre", type=float, default=0.005)
    p.add_argument("--snr", type=float, default=30.0)
    p.add_argument("--rate", type=float, default=48000.0)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--noise-only", type=float, default=0.0, help="seconds of noise alone")
    a = p.parse_args()
    rng = random.Random(a.seed)
    f0 = f_0s2(a.mass, a.modulus)
    fs = a.rate
    w = int(0.04 * fs)
    if a.noise_only > 0:
        n = int(a.noise_only * fs)
        x = [0.01 * rng.gauss(0.0, 1.0) for _ in range(n)]
        onsets = []
    else:
        n = int((a.pre + a.spacing * a.taps) * fs)
        x = [0.0] * n
        onsets = []
        sigma = None
        for k in range(a.taps):
            t0 = a.pre + a.spacing * k
            i0 = int(round(t0 * fs))
            onsets.append(i0 / fs)
            tap = [0.0] * int(0.25 * fs)
            for ratio, amp, q in MODES:
                f = f0 * ratio
                ph = 2.0 * math.pi * rng.random()
                d = math.pi * f / q
                for j in range(len(tap)):
                    t = j / fs
                    tap[j] += amp * math.exp(-d * t) * math.sin(2.0 * math.pi * f * t + ph)
            if sigma is None:
                ms = sum(v * v for v in tap[:w]) / w
                scale = 0.2 / math.sqrt(ms)  # the tap's RMS over 40 ms: 0.2 of full scale
                sigma = 0.2 / math.sqrt(10.0 ** (a.snr / 10.0))
            for j, v in enumerate(tap):
                if i0 + j < n:
                    x[i0 + j] += scale * v
        x = [v + sigma * rng.gauss(0.0, 1.0) for v in x]
    if a.out.endswith(".wav"):
        with wave.open(a.out, "wb") as f:
            f.setnchannels(1)
            f.setsampwidth(2)
            f.setframerate(int(fs))
            f.writeframes(b"".join(struct.pack("<h", max(-32767, min(32767, int(round(v * 32767)))))
                                   for v in x))
    else:
        with open(a.out, "wb") as f:
            f.write(struct.pack("<%df" % len(x), *x))
    print(json.dumps({"f0_hz": f0, "stiffness_factor": f0 * f0 * a.mass ** (2.0 / 3.0),
                      "modulus_pa": a.modulus, "onsets_s": onsets}))


if __name__ == "__main__":
    main()
