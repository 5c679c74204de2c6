#!/usr/bin/env python3
"""fruit_or_not.py — sets of taps for the fruit-or-not gate, made with the
standard library alone (not the package's code), and their score.

  fruit_or_not.py make SET OUT.wav TRUTH.json [--n N] [--seed S] [--snr DB]
  fruit_or_not.py score TRUTH.json ANALYZE.json

make writes N taps (fruit 0.4 s apart, objects 1.5 s: each ring faded out
before the next tap) (48 kHz, 16-bit, white noise at --snr dB
below the tap's mean square over its first 40 ms) and their truth. A 0.18 kg
apple of the default cultivar (E 2..12 MPa: a 0S2 in about [340, 830] Hz);
every object's fundamental is drawn inside that range, the worst case.

Sets (ratio: partial / fundamental; Q: quality factor pi f / sigma):
  fruit     the 0S2 (Q 15..45), the 0S3 at 1.4919 (0.5..2.5 x as loud),
            0S4 1.9153, 1S2 1.9381 (Lamb's ratios at nu 0.35, each within
            0.3 %), a support mode at 0.3 f (Q 8); E 3..11 MPa log-uniform
  phone     the fruit set through a phone's band: 2nd-order Butterworth
            high-pass at 100 Hz and low-pass at 8 kHz
  ceramic   a cup's ring modes 1 : 2.83 : 5.42 (n(n^2-1)/sqrt(n^2+1), n=2..4),
            Q 300..1000
  glass     the same ring modes, Q 1000..3000
  metal     a free bar, 1 : 2.756 : 5.404, Q 1000..10000 (loss factor 1e-4 ..
            1e-3, metals in Cremer & Heckl's table)
  stone     a free plate, 1 : 1.47 : 1.81 : 2.55, Q 100..300 (loss factor
            of the order of 1e-2 for concrete and cast iron)
  wood      a free bar, 1 : 2.756 : 5.404, Q 50..150 (loss factor 0.007 ..
            0.02): overlaps fruit's Q range below 100
  stray     a lump whose partials stand at 1.30 and 1.70, louder than its
            fundamental, Q 20..60: fruit's damping, not the sphere's ratios

score prints one line: set, taps, strikes, graded (reliable, grade_index > 0),
not_fruit, and for fruit sets the worst 0S2 and stiffness-factor errors of the
graded taps [%] and the least confidence among them."""
import json
import math
import random
import struct
import sys
import wave

RATE = 48000
PRE = 0.05
RING_S = 1.2  # a tap's sound lasts at most this [s], a long ring faded out over its last 20 ms
MASS, RHO, NU = 0.18, 840.0, 0.35
XI_0S2 = 2.6519  # Lamb's root of the 0S2 at nu 0.35
E_MIN, E_MAX = 2.5e6, 11.5e6  # fundamentals drawn inside the 0S2 range


def f_0s2(modulus):
    a = (3.0 * MASS / (4.0 * math.pi * RHO)) ** (1.0 / 3.0)
    return XI_0S2 / (2.0 * math.pi * a) * math.sqrt(modulus / (2.0 * (1.0 + NU) * RHO))


def fruit_modes(rng):
    """(ratio, amplitude, Q) of one fruit tap; the 0S2 first."""
    j = lambda r: r * (1.0 + rng.uniform(-0.003, 0.003))
    return [(1.0, 1.0, rng.uniform(15, 45)), (j(1.4919), rng.uniform(0.5, 2.5), rng.uniform(20, 45)),
            (j(1.9153), 0.6, rng.uniform(25, 45)), (j(1.9381), 0.4, rng.uniform(25, 45)),
            (0.3, 0.8, 8.0)]


OBJECTS = {  # ratios, amplitudes, Q range
    "ceramic": ([1.0, 2.83, 5.42], [1.0, 0.5, 0.25], (300, 1000)),
    "glass": ([1.0, 2.83, 5.42], [1.0, 0.5, 0.25], (1000, 3000)),
    "metal": ([1.0, 2.756, 5.404], [1.0, 0.4, 0.2], (1000, 10000)),
    "stone": ([1.0, 1.47, 1.81, 2.55], [1.0, 0.6, 0.5, 0.3], (100, 300)),
    "wood": ([1.0, 2.756, 5.404], [1.0, 0.4, 0.2], (50, 150)),
    "stray": ([1.0, 1.30, 1.70], [1.0, 1.5, 1.2], (20, 60)),
}


def object_modes(kind, rng):
    ratios, amps, (qlo, qhi) = OBJECTS[kind]
    q = math.exp(rng.uniform(math.log(qlo), math.log(qhi)))
    return [(r, a, q) for r, a in zip(ratios, amps)]


def biquad(x, b, a):
    y, x1, x2, y1, y2 = [], 0.0, 0.0, 0.0, 0.0
    for v in x:
        out = b[0] * v + b[1] * x1 + b[2] * x2 - a[1] * y1 - a[2] * y2
        x2, x1, y2, y1 = x1, v, y1, out
        y.append(out)
    return y


def butter2(fc, high):
    """2nd-order Butterworth by the bilinear transform (RBJ's cookbook)."""
    w = 2.0 * math.pi * fc / RATE
    alpha = math.sin(w) / math.sqrt(2.0)
    c = math.cos(w)
    if high:
        b = [(1 + c) / 2, -(1 + c), (1 + c) / 2]
    else:
        b = [(1 - c) / 2, 1 - c, (1 - c) / 2]
    a0 = 1 + alpha
    return [v / a0 for v in b], [1.0, -2 * c / a0, (1 - alpha) / a0]


def tap(modes, f0, rng, n):
    """The modes' decaying sines, at most n samples; a long ring (glass,
    metal) is faded out over its last 20 ms rather than cut."""
    x = [0.0] * n
    fade = int(0.02 * RATE)
    for ratio, amp, q in modes:
        f = f0 * ratio
        if f >= 0.45 * RATE:
            continue
        d, ph = math.pi * f / q, 2.0 * math.pi * rng.random()
        for i in range(n):
            e = math.exp(-d * i / RATE)
            if e < 1e-5:
                break
            if i >= n - fade:
                e *= 0.5 * (1.0 + math.cos(math.pi * (i - (n - fade)) / fade))
            x[i] += amp * e * math.sin(2.0 * math.pi * f * i / RATE + ph)
    return x


def make(kind, out, truth_path, n_taps, seed, snr_db):
    rng = random.Random(seed)
    ring_n = int(RING_S * RATE)
    spacing = 0.4 if kind in ("fruit", "phone") else 1.5
    n = int(round((PRE + spacing * (n_taps - 1)) * RATE)) + ring_n
    x = [0.0] * n
    w = int(0.04 * RATE)
    truths = []
    sigma = None
    for k in range(n_taps):
        modulus = math.exp(rng.uniform(math.log(E_MIN), math.log(E_MAX)))
        f0 = f_0s2(modulus)
        modes = fruit_modes(rng) if kind in ("fruit", "phone") else object_modes(kind, rng)
        t = tap(modes, f0, rng, ring_n)
        scale = 0.2 / math.sqrt(sum(v * v for v in t[:w]) / w)  # RMS 0.2 of full scale
        if sigma is None:
            sigma = 0.2 / math.sqrt(10.0 ** (snr_db / 10.0))
        i0 = int(round((PRE + spacing * k) * RATE))
        for j, v in enumerate(t):
            x[i0 + j] += scale * v
        truths.append({"onset_s": i0 / RATE, "f0_hz": f0, "q": modes[0][2],
                       "stiffness_factor": f0 * f0 * MASS ** (2.0 / 3.0)})
    x = [v + sigma * rng.gauss(0.0, 1.0) for v in x]
    if kind == "phone":
        x = biquad(biquad(x, *butter2(100.0, True)), *butter2(8000.0, False))
    with wave.open(out, "wb") as f:
        f.setnchannels(1)
        f.setsampwidth(2)
        f.setframerate(RATE)
        f.writeframes(b"".join(struct.pack("<h", max(-32767, min(32767, round(32767 * v))))
                               for v in x))
    with open(truth_path, "w") as f:
        json.dump({"set": kind, "taps": truths}, f)


def score(truth_path, result_path):
    truth = json.load(open(truth_path))
    strikes = json.load(open(result_path)).get("strikes", [])
    kind, taps = truth["set"], truth["taps"]
    graded = [s for s in strikes if s["reliable"] and s["grade_index"] > 0]
    not_fruit = sum("not_fruit" in s["flags"] for s in strikes)
    line = "%s taps %d strikes %d graded %d not_fruit %d" % (kind, len(taps), len(strikes),
                                                             len(graded), not_fruit)
    if kind in ("fruit", "phone"):
        ferr, kerr, conf = 0.0, 0.0, 1.0
        for s in graded:  # the tap it belongs to: the nearest onset before its stamp
            t = s["stamp_ns"] * 1e-9
            tr = min(taps, key=lambda p: abs(t - p["onset_s"]))
            ferr = max(ferr, abs(s["resonance_hz"] / tr["f0_hz"] - 1.0) * 100.0)
            kerr = max(kerr, abs(s["stiffness_factor_hz2_kg2_3"] / tr["stiffness_factor"] - 1.0)
                       * 100.0)
            conf = min(conf, s["mode_confidence"])
        line += " f0_err_max %.4f factor_err_max %.4f confidence_min %.2f" % (ferr, kerr, conf)
    print(line)


def main():
    a = sys.argv[1:]
    if len(a) >= 4 and a[0] == "make":
        opts = {"--n": 100, "--seed": 1, "--snr": 30.0}
        for i in range(4, len(a) - 1, 2):
            opts[a[i]] = type(opts[a[i]])(a[i + 1])
        make(a[1], a[2], a[3], opts["--n"], opts["--seed"], opts["--snr"])
    elif len(a) == 3 and a[0] == "score":
        score(a[1], a[2])
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
