#!/usr/bin/env python3
"""Signals for af_bench_response made here, not by the package:
accuracy before and after), and the scoring of its readings.

  bench_response.py make DIR [--seed S] [--count N]
      writes DIR/<set>.f32 (4096-sample float32 windows at 48 kHz),
      DIR/<set>.bands.csv (f_lo,f_hi: the 0S2 range +-20 %) and
      DIR/<set>.truth.csv for three sets of N windows each:
        comb   an apple's comb: 0S2 (350-900 Hz, Q 15-40), a 1S2-like mode
               1.2-1.35 f0 at 0.1-0.4 of its amplitude, the 0S3 1.45-1.6 f0
               at 0.5-2.5; white noise at 15-40 dB (0S2 amplitude over the
               noise RMS), onset 0-40 samples into the window;
        close  the 0S2 and a second mode 3-8 % above it (a split 0S2) at
               0.3-1.0 of its amplitude, the 0S3 as above, noise 25-40 dB;
        hum    comb plus 50 Hz mains hum (harmonics 1-5, each 0.05-0.3 of
               the 0S2 amplitude).
  bench_response.py score DIR SET READINGS.csv
      scores af_bench_response's output against DIR/SET.truth.csv: the 0S2
      identified (a listed peak within 1.5 % of it), its frequency error
      (median and 95th percentile of |f - f0| / f0), its Q error (median and
      p95 of |Q - Q0| / Q0); for close, also the upper mode.
Pure Python (math, random, struct): no numpy on this machine."""
import math
import os
import random
import struct
import sys

FS = 48000.0
N = 4096


def damped(n, onset, f, q, amp, phase):
    sigma = math.pi * f / q
    out = [0.0] * n
    w = 2.0 * math.pi * f / FS
    for k in range(onset, n):
        t = (k - onset) / FS
        out[k] = amp * math.exp(-sigma * t) * math.cos(w * (k - onset) + phase)
    return out


def window(rng, kind):
    f0 = rng.uniform(350.0, 900.0)
    q0 = rng.uniform(15.0, 40.0)
    onset = rng.randint(0, 40)
    modes = [(f0, q0, 1.0)]
    if kind == "close":
        modes.append((f0 * rng.uniform(1.03, 1.08), rng.uniform(15.0, 40.0), rng.uniform(0.3, 1.0)))
        snr_db = rng.uniform(25.0, 40.0)
    else:
        modes.append((f0 * rng.uniform(1.2, 1.35), rng.uniform(15.0, 40.0), rng.uniform(0.1, 0.4)))
        snr_db = rng.uniform(15.0, 40.0)
    modes.append((f0 * rng.uniform(1.45, 1.6), rng.uniform(15.0, 40.0), rng.uniform(0.5, 2.5)))
    x = [0.0] * N
    for f, q, a in modes:
        m = damped(N, onset, f, q, a, rng.uniform(0.0, 2.0 * math.pi))
        x = [u + v for u, v in zip(x, m)]
    noise_rms = 10.0 ** (-snr_db / 20.0)
    x = [u + rng.gauss(0.0, noise_rms) for u in x]
    if kind == "hum":
        for h in range(1, 6):
            a, ph = rng.uniform(0.05, 0.3), rng.uniform(0.0, 2.0 * math.pi)
            w = 2.0 * math.pi * 50.0 * h / FS
            x = [u + a * math.cos(w * k + ph) for k, u in enumerate(x)]
    return x, modes, snr_db


def make(directory, seed, count):
    os.makedirs(directory, exist_ok=True)
    for kind in ("comb", "close", "hum"):
        rng = random.Random(f"{seed}-{kind}")
        with open(f"{directory}/{kind}.f32", "wb") as fw, \
                open(f"{directory}/{kind}.bands.csv", "w") as fb, \
                open(f"{directory}/{kind}.truth.csv", "w") as ft:
            for _ in range(count):
                x, modes, snr_db = window(rng, kind)
                fw.write(struct.pack(f"<{N}f", *x))
                f0 = modes[0][0]
                fb.write(f"{0.8 * f0:.6f},{1.2 * f0:.6f}\n")
                ft.write(",".join(f"{f:.6f},{q:.6f},{a:.6f}" for f, q, a in modes) +
                         f",{snr_db:.3f}\n")


def quantile(v, p):
    if not v:
        return float("nan")
    v = sorted(v)
    return v[min(len(v) - 1, int(p * len(v)))]


def score(directory, kind, readings):
    truth = [list(map(float, l.split(","))) for l in open(f"{directory}/{kind}.truth.csv")]
    rows = [l.strip().split(",") for l in open(readings) if not l.startswith("#")]
    targets = [("0S2", 0)] + ([("upper", 1)] if kind == "close" else [])
    for name, m in targets:
        ident, ferr, qerr = 0, [], []
        for t, row in zip(truth, rows):
            f0, q0 = t[3 * m], t[3 * m + 1]
            n = int(row[2])
            peaks = [(float(row[3 + 3 * i]), float(row[4 + 3 * i])) for i in range(n)]
            near = [p for p in peaks if abs(p[0] - f0) <= 0.015 * f0]
            if not near:
                continue
            f, q = min(near, key=lambda p: abs(p[0] - f0))
            ident += 1
            ferr.append(abs(f - f0) / f0)
            qerr.append(abs(q - q0) / q0)
        print(f"{kind:5s} {name:5s} identified {ident}/{len(truth)} "
              f"f err median {100 * quantile(ferr, 0.5):.4f} % p95 {100 * quantile(ferr, 0.95):.4f} % "
              f"Q err median {100 * quantile(qerr, 0.5):.2f} % p95 {100 * quantile(qerr, 0.95):.2f} %")


def main(argv):
    if len(argv) >= 3 and argv[1] == "make":
        seed, count = 1, 100
        rest = argv[3:]
        while rest:
            if rest[0] == "--seed" and len(rest) > 1:
                seed = int(rest[1])
            elif rest[0] == "--count" and len(rest) > 1:
                count = int(rest[1])
            else:
                sys.exit(f"bench_response.py: unknown argument '{rest[0]}'")
            rest = rest[2:]
        make(argv[2], seed, count)
    elif len(argv) == 5 and argv[1] == "score":
        score(argv[2], argv[3], argv[4])
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main(sys.argv)
