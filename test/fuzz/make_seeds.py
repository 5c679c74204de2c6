#!/usr/bin/python3
"""Writes the seed corpus of the libFuzzer harnesses (test/fuzz/<name>/seed_*):
small valid inputs of each kind, so that fuzzing starts from inputs that reach
deep (a strike, a ringing mode, accepted flags, the shipped YAML, a bag and
messages with chunks and an apple). Deterministic; the files are committed.
Usage (after a build, for the message classes):
  source devel/setup.bash; /usr/bin/python3 test/fuzz/make_seeds.py"""

import io
import math
import os
import random
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def put(name, seed, data):
    d = os.path.join(HERE, name)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, 'seed_' + seed), 'wb') as f:
        f.write(data)


def pulse(fs, tc=1.4e-3, peak=35.0):
    """A Hertz-like sin^1.5 pulse of contact time tc [s] at fs [Hz]."""
    n = int(tc * fs) + 1
    return [peak * math.sin(math.pi * k / fs / tc) ** 1.5 if k / fs < tc else 0.0 for k in range(n)]


def mode(fs, n, f0=680.0, q=30.0, amp=1.0, rnd=None):
    return [amp * math.exp(-math.pi * f0 / q * k / fs) * math.cos(2 * math.pi * f0 * k / fs) +
            (rnd.gauss(0, 0.01) if rnd else 0.0) for k in range(n)]


def strike_seeds():
    # head: rate 50 kHz (3), no threshold byte; first index; then chunks:
    # kind 0 (int16 samples), n, scale, samples
    rnd = random.Random(1)
    scale = 0.01  # N per count
    x = [rnd.gauss(0, 0.02) for _ in range(2000)]
    p = pulse(50000.0)
    for k, v in enumerate(p):
        x[1200 + k] += v
    out = bytearray([3]) + struct.pack('<H', 0)
    for c in range(0, len(x), 500):
        part = x[c:c + 500]
        out += bytes([0]) + struct.pack('<H', len(part)) + struct.pack('<H', int(scale / 0.01 * 65535))
        out += b''.join(struct.pack('<h', max(-32768, min(32767, int(round(v / scale))))) for v in part)
    out += bytes([0xff])
    put('strike', 'pulse', bytes(out))
    # a gap and a restart
    put('strike', 'gap', bytes(out[:300]) + bytes([0x30]) + struct.pack('<HH', 4, 65535) +
        struct.pack('<Q', 1 << 40) + bytes(out[300:]))


def response_seeds():
    rnd = random.Random(2)
    for k, fs in enumerate((25600.0, 44100.0, 48000.0)):
        n = int(0.04 * fs)
        a = mode(fs, n, rnd=rnd)
        scale = 1.0 / 30000.0
        lo, hi = 300.0 / (0.5 * fs) * 65535, 1300.0 / (0.5 * fs) * 65535
        f_lo = 1.0 + (0.5 * fs - 1.0) * lo / 65535
        hi_u = (1300.0 - f_lo) / (0.5 * fs - f_lo) * 65535
        out = bytearray([k]) + struct.pack('<HH', int(lo), int(hi_u)) + struct.pack('<H', n)
        out += struct.pack('<H', int(scale * 65535))
        out += b''.join(struct.pack('<h', int(round(v / scale))) for v in a)
        put('response', 'mode_%d' % int(fs), bytes(out))


def cli_seeds():
    put('cli', 'default', b'\x01')
    put('cli', 'flags', b'\0'.join([b'--E2', b'8e6', b'--R2', b'0.04', b'--e', b'0.6',
                                      b'--damping', b'exact', b'--lobe', b'1']))
    put('cli', 'paper', b'\0'.join([b'--profile', b'paper', b'--hammer-mass', b'0.02',
                                      b'--v0', b'1.0', b'--gravity', b'0']))
    put('cli', 'set', b'\0'.join([b'strike_velocity_m_s=1.4', b'modulus_min_pa=2e6', b'lobe=2']))
    put('cli', 'hammer', b'\0'.join([b'--hammer-E', b'4e7', b'--hammer-radius', b'0.005',
                                       b'--hammer-nu', b'0.3', b'--nu2', b'0.3']))


def yaml_seeds():
    for name in ('station.yaml', 'jonagold.yaml'):
        with open(os.path.join(ROOT, 'config', name), 'rb') as f:
            put('yaml', name.split('.')[0], f.read())
    # The byte-level edge cases of the reader, accepted and refused:
    # each starts from the shipped cultivar so that fuzzing mutates around a
    # file that otherwise reads.
    with open(os.path.join(ROOT, 'config', 'jonagold.yaml'), 'rb') as f:
        cultivar = f.read()
    lines = cultivar.split(b'\n')
    put('yaml', 'crlf', cultivar.replace(b'\n', b'\r\n'))
    put('yaml', 'bom', b'\xef\xbb\xbf' + cultivar)
    put('yaml', 'bom_crlf', b'\xef\xbb\xbf' + cultivar.replace(b'\n', b'\r\n'))
    put('yaml', 'lone_cr', b'\r'.join(lines))
    put('yaml', 'cr_at_end', b'lobe: 2\r')
    put('yaml', 'nul_in_value', b'mass_max_kg: 0.3\0junk\n')
    put('yaml', 'nul_before_key', b'\0bogus_key: 5\n')
    put('yaml', 'nul_line', cultivar + b'\0' * 64 + b'\n')
    put('yaml', 'long_line_1023', b'#' + b'x' * 1022 + b'\n' + cultivar)
    put('yaml', 'long_line_1024', b'#' + b'x' * 1023 + b'\n' + cultivar)
    put('yaml', 'long_value', b"cultivar: '" + b'G' * 2000 + b"'\n")
    put('yaml', 'duplicate_key', cultivar + lines[-2] + b'\n' if lines[-1] == b'' else cultivar)
    put('yaml', 'no_final_newline', cultivar.rstrip(b'\n'))


def messages():
    """(force chunks, audio chunks, apple) as message objects."""
    from acoustic_firmness.msg import AppleEstimate, SignalChunk
    import rospy
    rnd = random.Random(3)
    force = [0.3 + rnd.gauss(0, 0.02) for _ in range(3000)]
    for k, v in enumerate(pulse(50000.0)):
        force[1500 + k] += v
    audio = [rnd.gauss(0, 0.001) for _ in range(2880)]
    for k, v in enumerate(mode(48000.0, 1400)):
        audio[1440 + k] += v
    t0 = 1700000000.0

    def chunks(x, fs, unit):
        out = []
        for c in range(0, len(x), 1024):
            m = SignalChunk()
            m.header.stamp = rospy.Time.from_sec(t0 + c / fs)
            m.header.frame_id = 'force_sensor' if unit == 'N' else 'microphone'
            m.first_sample = c
            m.sample_rate = fs
            m.unit = unit
            m.data = x[c:c + 1024]
            out.append(m)
        return out

    a = AppleEstimate()
    a.header.stamp = rospy.Time.from_sec(t0)
    a.header.frame_id = 'camera_optical_frame'
    a.apple_id, a.mass, a.equatorial_radius, a.strike_radius = 1, 0.175, 0.04, 0.04
    a.stem_axis.x, a.confidence = 1.0, 0.9
    return chunks(force, 50000.0, 'N'), chunks(audio, 48000.0, 'Pa'), a


def serialized(m):
    b = io.BytesIO()
    m.serialize(b)
    return b.getvalue()


def msgs_seeds():
    force, audio, apple = messages()
    out = bytearray()

    def rec(kind, m):
        s = serialized(m)
        return bytes([kind]) + struct.pack('<H', len(s)) + s
    out += rec(2, apple)
    for f, a in zip(force, audio):
        out += rec(0, f) + rec(1, a)
    put('msgs', 'strike', bytes(out))
    put('msgs', 'apple', rec(2, apple))


def bag_seeds():
    import rosbag
    force, audio, apple = messages()
    path = os.path.join(HERE, 'bag', 'seed_small')
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with rosbag.Bag(path, 'w') as bag:
        bag.write('/lane1/apple', apple, apple.header.stamp)
        for f, a in zip(force[:2], audio[:2]):
            bag.write('/lane1/force', f, f.header.stamp)
            bag.write('/lane1/audio', a, a.header.stamp)


def analyze_seeds():
    rnd = random.Random(4)
    fs = 25600.0
    n = int(0.06 * fs)
    force = [0.3 + rnd.gauss(0, 0.02) for _ in range(n)]
    for k, v in enumerate(pulse(fs)):
        force[200 + k] += v
    audio = [rnd.gauss(0, 0.001) for _ in range(n)]
    for k, v in enumerate(mode(fs, n - 220)):
        audio[220 + k] += v
    f = struct.pack('<%df' % n, *force)
    a = struct.pack('<%df' % n, *audio)
    # head: rates 25600/25600 (0, 0), split at 8/17 of the rest: force 8/17 of it
    body = f + a
    head = 7 << 4  # (7 + 1) / 17 of the body: force part
    # pad so that the split falls exactly between force and audio
    pad = len(f) * 17 // 8 - len(body)
    body = f + a + bytes(max(0, pad))
    put('analyze', 'strike', bytes([head]) + body)


class LaneProgram:
    """An input of fuzz_lane (its header says the encoding), written from
    its own description of the bytes, not from the harness's code."""
    LENGTHS = [0, 1, 2, 17, 64, 100, 256, 480, 512, 1000, 1024, 1024, 2048, 4096]
    FORCE_HZ, AUDIO_HZ = 50000.0, 48000.0

    def __init__(self, lane, single_apple=False, late_epoch=False, noise=1):
        self.out = bytearray([lane | (4 if single_apple else 0) | (8 if late_epoch else 0) | noise << 4])
        self.next = {True: 0, False: 0}  # the next index of the force, the audio

    def chunk(self, force, n=1024, event=None, src=0, rate=0, stamp=0, index=0, args=b''):
        """event: (position byte, amplitude byte, shape byte); args: the
        rate, index and stamp bytes the op bits ask for, in that order; src:
        the source byte's other bits."""
        op = (0 if force else 1) | rate << 2 | stamp << 4 | index << 6
        k = self.LENGTHS.index(n) if n in self.LENGTHS else n  # 14, 15: the ring, past it
        self.out += bytes([op, k]) + args + bytes([src | (4 if event else 0)])
        if event:
            self.out += bytes(event)
        if index == 0 and k < 14:
            self.next[force] += n

    def apple(self, apple_id, when=128, mass=80, eqr=100, r2=120, conf=249, stem=0x15, direction=0):
        self.out += bytes([2, apple_id, when, mass, eqr, r2, conf, stem, direction])

    def clock(self, sub, args=b''):
        self.out += bytes([3 | sub << 2]) + args

    def stream_until(self, t_s, strike_s=None, apples=()):
        """Both streams in 1024-sample chunks in time order up to t_s, a
        strike (a pulse and its ring) at strike_s, apples (id, at_s)."""
        apples = list(apples)
        while True:
            tf, ta = self.next[True] / self.FORCE_HZ, self.next[False] / self.AUDIO_HZ
            t = min(tf, ta)
            if t >= t_s:
                return
            while apples and apples[0][1] <= t:
                self.apple(apples.pop(0)[0])
            force = tf <= ta
            fs = self.FORCE_HZ if force else self.AUDIO_HZ
            i0 = self.next[force]
            event = None
            if strike_s is not None and i0 <= strike_s * fs < i0 + 1024:
                pos = int((strike_s * fs - i0) * 256 / 1024)
                event = (pos, 140, 198) if force else (pos, 100, 48)  # 35 N, 1.4 ms; 1 Pa, 680 Hz
            self.chunk(force, event=event)


def lane_seeds():
    # The node: apples on a line (the transit match: the strike at 0.05 s takes
    # the estimate stamped 0.2 s before it, not the one stamped at 0.03 s).
    p = LaneProgram(0, late_epoch=True)
    p.apple(1, when=128 - 15)
    p.stream_until(0.1, strike_s=0.05, apples=[(2, 0.03)])
    put('lane', 'node_strike', bytes(p.out))
    # A desk tool: one apple for the recording.
    p = LaneProgram(0, single_apple=True)
    p.apple(7)
    p.stream_until(0.1, strike_s=0.05)
    put('lane', 'desk_strike', bytes(p.out))
    # A microphone-only rig: the strike from the audio onset.
    p = LaneProgram(1, single_apple=True, noise=0)
    p.apple(9)
    p.next[True] = 10 ** 9  # no force: every chunk is audio
    p.stream_until(0.1, strike_s=0.05)
    put('lane', 'tap_only', bytes(p.out))
    # A force in V, and what a sender gets wrong: a gap, jitter, a clock step,
    # NaN and inf, a restart, a duplicate, a raw float32 chunk, a wrong rate,
    # a wrong unit, a long frame id, an oversized chunk, implausible apples.
    p = LaneProgram(2, noise=2)
    p.stream_until(0.04)
    p.chunk(True, index=1, args=bytes([0x40, 0x00]))                  # a gap of 64 samples
    p.chunk(True, stamp=1, args=bytes([0x90]))                        # jitter
    p.chunk(True, stamp=2, args=bytes([0x10, 0x00]))                  # a step of 16 s
    p.chunk(True, index=2, args=bytes([0x00, 0x04]))                  # back 1024: a duplicate
    p.chunk(True, src=1 << 3)                                         # NaN (position, run)
    p.out += bytes([0x40, 0x20])
    p.chunk(True, src=2 << 3)                                         # inf
    p.out += bytes([0x80, 0x01])
    p.chunk(True, index=3, args=struct.pack('<Q', 5))                 # a restart at index 5
    # raw float32: the scale byte (unused for float32), then the samples
    p.chunk(False, n=17, src=3)
    p.out += bytes([128]) + struct.pack('<17f', *([0.5] * 14 + [float('nan'), float('inf'), -1e38]))
    p.chunk(True, rate=3, args=bytes([2]))                            # rate NaN
    p.chunk(False, src=2 << 5)                                        # unit 'furlong'
    p.chunk(True, src=0x80)                                           # a long frame id
    p.chunk(True, n=15)                                               # past the ring: refused
    p.apple(0)                                                        # the "no apple" id
    p.apple(4, mass=252)                                              # NaN mass
    p.apple(255, when=255)                                            # any id, any stamp
    p.out += struct.pack('<I', 0xFFFFFFFF) + struct.pack('<II', 4000000000, 999999999)
    p.clock(0, struct.pack('<H', 30000))                              # poll 300 ms later
    p.clock(1, bytes([0xC0]))                                         # the clock 0.64 s behind
    p.clock(2, bytes([3]))                                            # refused on the wire
    p.clock(3, struct.pack('<II', 12, 5))                             # the clock back to 12 s
    put('lane', 'volts_faults', bytes(p.out))


def wav_seeds():
    # head byte: channel (bits 0-1; 0 = not given), a rate flag (bit 2);
    # then the file: each WAV kind the reader accepts, a LIST before the
    # data, a padded RIFF, and headers whose sizes lie.
    sys.path.insert(0, os.path.join(ROOT, 'test', 'cli'))
    import tempfile
    import wav_files as wf
    fs = 8000
    tone = [0.5 * math.sin(2 * math.pi * 440.0 * k / fs) for k in range(64)]
    two = [tone, [-x for x in tone]]
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, 'x.wav')
        for name, write in (('pcm16', lambda: wf.write_pcm(path, fs, [tone], 16, 1.0)),
                            ('pcm8_stereo', lambda: wf.write_pcm(path, fs, two, 8, 1.0)),
                            ('pcm24', lambda: wf.write_pcm(path, fs, [tone], 24, 1.0)),
                            ('pcm32', lambda: wf.write_pcm(path, fs, two, 32, 1.0)),
                            ('float32', lambda: wf.write_float(path, fs, [tone], 32)),
                            ('float64_ext', lambda: wf.write_float(path, fs, two, 64, True)),
                            ('ext_pcm24in32',
                             lambda: wf.write_extensible_pcm(path, fs, [tone], 32, 1.0, 24))):
            write()
            body = open(path, 'rb').read()
            put('wav', name, bytes([1 if 'stereo' in name else 0]) + body)
        wf.write_pcm(path, fs, [tone], 16, 1.0)
        body = open(path, 'rb').read()
    put('wav', 'padded', bytes([0]) + body + bytes(7))
    put('wav', 'riff_size_lies', bytes([0]) + body[:4] + struct.pack('<I', 1 << 30) + body[8:])
    data_at = body.index(b'data')
    put('wav', 'data_size_lies',
        bytes([0]) + body[:data_at + 4] + struct.pack('<I', 0xFFFFFFF0) + body[data_at + 8:])
    put('wav', 'rate_flag', bytes([4]) + body)
    put('wav', 'raw_f32', bytes([4]) + struct.pack('<64f', *tone))
    put('wav', 'flac', bytes([0]) + b'fLaC' + bytes(40))


if __name__ == '__main__':
    wav_seeds()
    strike_seeds()
    response_seeds()
    cli_seeds()
    yaml_seeds()
    analyze_seeds()
    lane_seeds()
    try:
        msgs_seeds()
        bag_seeds()
    except ImportError as e:
        sys.exit('make_seeds: %s (source devel/setup.bash first)' % e)
