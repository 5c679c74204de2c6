#!/usr/bin/env python3
"""A lab session made of the real impact-hammer captures of test/data, for the
capture_to_bag tests and the docs' examples (installed: `rosrun
acoustic_firmness capture_files.py OUT_DIR DATA_DIR`), written with Debian's
python3 alone (independently of the package's WAV reader and bag writer):

  force: 0.5 s of capture 4's quiet tail (a lead-in: the station's baseline
         tracker needs quiet before a strike; each capture starts only 20
         samples before its strike), then captures 5, 4, 5 (1 s each):
         3.5 s at 25.6 kHz, three strikes;
  audio: the response channels of the same captures, in the same order.

Written as (test/cli/wav_files.py):
  force16.wav   16-bit PCM (the wave module), full scale FORCE_FS_N
  audio32.wav   32-bit IEEE float WAV (header packed by hand)
  force.f32     raw float32 (the same samples as the captures)
  audio16s.wav  16-bit PCM stereo, the response in channel 1 (full scale
                AUDIO_FS), a sawtooth in channel 0
  apples.csv    one AppleEstimate 0.2 s before each strike (ids 11, 12, 13)
  expect.json   per strike, from the samples here: its onset [s from the
                force's start] (the first sample above 10 % of the peak,
                minus the samples the pulse takes to get there from its
                baseline, see onset()) and its peak over the local baseline [N]

Usage: capture_files.py OUT_DIR DATA_DIR"""
import json
import os
import struct
import sys

# wav_files: beside this file once installed, in test/cli in the source tree
_here = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [_here, os.path.join(_here, '..', 'cli')]
import wav_files as W  # noqa: E402

RATE = 25600
FORCE_FS_N = 100.0  # the captures peak at 88.9 N
AUDIO_FS = 512.0    # the responses peak near 500
LEAD_IN = RATE // 2
ORDER = (5, 4, 5)
APPLE_LEAD_S = 0.2


def onset(x, base, peak_k):
    """Index of the pulse's start: walking back from the peak to the last
    sample within 2 % of the peak over the baseline (the README's pulse
    width is counted at 2 %)."""
    level = base + 0.02 * (x[peak_k] - base)
    k = peak_k
    while k > 0 and x[k - 1] > level:
        k -= 1
    return k - 1  # the last sample at the baseline: the contact starts after it


def main():
    out, data = sys.argv[1], sys.argv[2]
    cap = {n: (W.read_f32('%s/hammer_capture_%d.force.f32' % (data, n)),
               W.read_f32('%s/hammer_capture_%d.response.f32' % (data, n))) for n in (4, 5)}
    force = list(cap[4][0][-LEAD_IN:])
    audio = list(cap[4][1][-LEAD_IN:])
    expect = []
    for n in ORDER:
        start = len(force)
        f = cap[n][0]
        peak_k = max(range(200), key=lambda k: f[k])
        base = sorted(f[2000:RATE])[(RATE - 2000) // 2]  # median of the quiet tail
        k0 = onset(f, base, peak_k)
        expect.append({'capture': n, 'onset_s': (start + k0) / RATE,
                       'peak_n': f[peak_k] - base})
        force += f
        audio += cap[n][1]
    W.write_pcm(out + '/force16.wav', RATE, [force], 16, FORCE_FS_N)
    W.write_float(out + '/audio32.wav', RATE, [audio], 32)
    saw = [0.25 * AUDIO_FS * ((k % 64) / 32.0 - 1.0) for k in range(len(audio))]
    W.write_pcm(out + '/audio16s.wav', RATE, [saw, audio], 16, AUDIO_FS)
    with open(out + '/force.f32', 'wb') as fh:
        fh.write(struct.pack('<%df' % len(force), *force))
    with open(out + '/apples.csv', 'w') as fh:
        fh.write('apple_id,stamp_s,mass_kg,equatorial_radius_m,strike_radius_m,'
                 'stem_axis_x,stem_axis_y,stem_axis_z,confidence\n')
        for k, e in enumerate(expect):
            e['apple_id'] = 11 + k
            e['apple_stamp_s'] = round(e['onset_s'] - APPLE_LEAD_S, 4)
            fh.write('%d,%.4f,0.175,0.037,0.04,1,0,0,0.9\n' % (e['apple_id'], e['apple_stamp_s']))
    json.dump({'rate_hz': RATE, 'samples': len(force), 'strikes': expect},
              open(out + '/expect.json', 'w'), indent=1)


if __name__ == '__main__':
    main()
