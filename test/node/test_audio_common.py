#!/usr/bin/python3
"""rostest of the audio_common input (~audio_input audio_common, channel 1).

The message classes are built at test time from audio_common_msgs' own .msg
files (test/node/audio_common_msgs, genpy's dynamic generation: genmsg's
md5sums), and checked against the shim's constants (src/shim/af_audio.h). A
strike_bag recording (force, audio at 48 kHz, apples) is published on
simulated time, the test driving /clock; its audio goes out as audio_common
would send it, phase by phase:

  A  AudioDataStamped, S16LE, stereo (the microphone on channel 1, quiet noise
     on channel 0): strikes measured, 0S2 within 1 % of the truth;
  C  audio_info with coding_format mp3, then a mono stream (channel 1 does not
     exist): every chunk refused, said in /diagnostics;
  D  a rate change: audio_info at 44100 Hz (the station expects 48 kHz): the
     stream restarts, the lane refuses the chunks (counted);
  E  back to 48 kHz, AudioDataStamped S24LE then S32LE stereo: strikes measured
     again after the restarts;
  B  (a node of its own) AudioData, no stamp, F32LE stereo: strikes measured
     with the stamps derived from the receive time; the jitter is reported;
  W  (a node each) a first publisher of the wrong type (std_msgs/String), a
     fork's AudioData (same name, another md5), the right md5 with another
     definition: every message refused, said in /diagnostics.

roscpp binds a generic subscription to the md5sum of the first publisher it
connects to, so each publisher type gets a node of its own here (started by
the test, as test_startup.py does; no URDF, the hammer from parameters).
Each run has its own stretch of simulated time (the bag's stamps shifted).
"""

import csv
import math
import os
import random
import re
import struct
import subprocess
import sys
import tempfile
import shutil
import signal
import threading
import time
import unittest

import genpy.dynamic
import rosbag
import roslib.packages
import rospy
import rosparam
import rostest
import std_msgs.msg
from acoustic_firmness.msg import AppleEstimate, SignalChunk, StrikeReport
from diagnostic_msgs.msg import DiagnosticArray
from rosgraph_msgs.msg import Clock

import station_common as sc

HERE = os.path.dirname(os.path.abspath(__file__))
MSG_DIR = os.path.join(HERE, 'audio_common_msgs', 'msg')
HEADER = os.path.join(HERE, '..', '..', 'src', 'shim', 'af_audio.h')
SEP = '\n' + '=' * 80 + '\n'
STRIKES = 14
PLAIN_STRIKES = 4
SEED = 11
SPEED = 4.0  # simulated seconds per wall second
RESONANCE_RTOL = 0.01


def definition(name):
    with open(os.path.join(MSG_DIR, name + '.msg')) as f:
        return f.read()


def classes():
    """audio_common_msgs classes from the .msg files (full text as genmsg writes it)."""
    header = 'MSG: std_msgs/Header\n' + std_msgs.msg.Header._full_text
    data = definition('AudioData')
    out = {}
    out.update(genpy.dynamic.generate_dynamic('audio_common_msgs/AudioData', data))
    out.update(genpy.dynamic.generate_dynamic(
        'audio_common_msgs/AudioDataStamped',
        definition('AudioDataStamped') + SEP + header + SEP + 'MSG: audio_common_msgs/AudioData\n' + data))
    out.update(genpy.dynamic.generate_dynamic('audio_common_msgs/AudioInfo', definition('AudioInfo')))
    # A fork's AudioData (same name, its own fields): another md5.
    fork = ('std_msgs/Header header\nstring format\nuint8 depth\nuint8 channels\nuint32 sample_rate\n'
            'uint8[] data\n' + SEP + header)
    out['fork'] = genpy.dynamic.generate_dynamic('audio_common_msgs/AudioData', fork)[
        'audio_common_msgs/AudioData']
    return out


def header_constants():
    with open(HEADER) as f:
        text = f.read()
    consts = {}
    for m in re.finditer(r'#define (AF_AUDIO_\w+)((?:[^\n]*\\\n)*[^\n]*)', text):
        value = ''.join(re.findall(r'"((?:[^"\\]|\\.)*)"', m.group(2)))
        consts[m.group(1)] = value.encode().decode('unicode_escape')
    return consts


def encode(fmt, frames):
    """frames: list of per-channel float lists in [-1, 1)."""
    n = len(frames[0])
    out = bytearray()
    for i in range(n):
        for ch in frames:
            x = max(-1.0, min(ch[i], 1.0 - 1e-9))
            if fmt == 'S16LE':
                out += struct.pack('<h', int(round(x * 32767)))
            elif fmt == 'S24LE':
                out += struct.pack('<i', int(round(x * 8388607)))[:3]
            elif fmt == 'S32LE':
                out += struct.pack('<i', int(round(x * 2147483647)))
            elif fmt == 'F32LE':
                out += struct.pack('<f', x)
    return bytes(out)


def node_params(ns):
    pkg = os.path.join(HERE, '..', '..')
    params = {}
    for name in ('station.yaml', 'jonagold.yaml'):
        for p, _ in rosparam.load_file(os.path.join(pkg, 'config', name)):
            params.update(p)
    params.update(audio_input='audio_common', audio_channel=1, audio_full_scale=2.0,
                  hammer_mass_kg=0.01, hammer_tip_radius_m=0.0, urdf_file='/nonexistent.urdf')
    rosparam.upload_params(ns + '/' + sc.NODE, params)


class Run:
    """One firmness_node of the test's own in namespace ns, its reports and diagnostics."""

    def __init__(self, ns):
        self.ns = ns
        node_params(ns)
        exe = roslib.packages.find_node(sc.PKG, sc.NODE)[0]
        self.proc = subprocess.Popen([exe, '__ns:=' + ns, '__name:=' + sc.NODE],
                                     stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        self.lock = threading.Lock()
        self.reports, self.diag = [], {}
        self.subs = [rospy.Subscriber(ns + '/strike_report', StrikeReport, self._report, queue_size=1000),
                     rospy.Subscriber('/diagnostics', DiagnosticArray, self._diag, queue_size=100)]
        end = time.time() + 20.0
        while time.time() < end and self.subs[0].get_num_connections() == 0:
            time.sleep(0.05)

    def _report(self, msg):
        with self.lock:
            self.reports.append(msg)

    def _diag(self, msg):
        values = sc.diag_values(msg, self.ns + '/' + sc.NODE)
        if values:
            with self.lock:
                self.diag = values

    def pub(self, name, klass, latch=False):
        p = rospy.Publisher(self.ns + '/' + name, klass, queue_size=10000, latch=latch)
        end = time.time() + 10.0
        while p.get_num_connections() == 0 and time.time() < end:
            time.sleep(0.05)
        return p

    def stop(self):
        for s in self.subs:
            s.unregister()
        self.proc.send_signal(signal.SIGINT)
        try:
            _, err = self.proc.communicate(timeout=20)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            _, err = self.proc.communicate()
        with self.lock:
            return list(self.reports), dict(self.diag), err


class AudioCommonTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_audio_common')
        cls.msgs = classes()
        cls.tmp = tempfile.mkdtemp(prefix='af_audio_common_')
        cls.clock = rospy.Publisher('/clock', Clock, queue_size=100)
        cls.offset_s = 0.0
        exe = roslib.packages.find_node(sc.PKG, 'strike_bag')[0]
        cls.bags, cls.truth = {}, {}
        for name, n in (('stamped', STRIKES), ('plain', PLAIN_STRIKES)):
            bag = os.path.join(cls.tmp, name + '.bag')
            subprocess.run([exe, '--strikes', str(n), '--seed', str(SEED), '--out', bag, '--ns', 'x'],
                           check=True, capture_output=True)
            with open(os.path.join(cls.tmp, name + '.truth.csv')) as f:
                cls.truth[name] = {int(r['apple_id']): r for r in csv.DictReader(f)}
            cls.bags[name] = bag
        cls.stamped = cls._play_stamped()
        cls.plain = cls._play_plain()
        cls.wrong = cls._play_wrong()

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    # --- publishing a bag --------------------------------------------------------------

    @classmethod
    def _replay(cls, run, name, audio_fn):
        """Publishes the bag's force and apples as they are and its audio through
        audio_fn(msg, t, x); the clock leads, each run in its own time stretch."""
        with rosbag.Bag(cls.bags[name]) as bag:
            msgs = list(bag.read_messages())
        shift = rospy.Duration(cls.offset_s)
        cls.offset_s += 100.0
        force, apple = run.pub('force', SignalChunk), run.pub('apple', AppleEstimate)
        peak = max(max(abs(x) for x in m.data) for tp, m, _ in msgs if tp.endswith('/audio'))
        scale = 0.5 / peak  # the microphone at half its full scale (~audio_full_scale 2.0)
        wall0, sim0 = time.time(), msgs[0][2].to_sec()
        for topic, msg, t in msgs:
            lag = (t.to_sec() - sim0) / SPEED - (time.time() - wall0)
            if lag > 0:
                time.sleep(lag)
            t = t + shift
            cls.clock.publish(Clock(clock=t))
            msg.header.stamp = msg.header.stamp + shift
            kind = topic.rsplit('/', 1)[1]
            if kind == 'force':
                force.publish(msg)
            elif kind == 'apple':
                apple.publish(msg)
            else:
                audio_fn(msg, t, [v * scale for v in msg.data])
        end_t = msgs[-1][2] + shift
        for k in range(1, 40):  # simulated time goes on: the last strikes are measured
            cls.clock.publish(Clock(clock=end_t + rospy.Duration(0.1 * k)))
            time.sleep(0.05)
        end = time.time() + 10.0
        while time.time() < end and len(run.reports) < len(cls.truth[name]):
            time.sleep(0.1)
        time.sleep(2.5)  # a diagnostics report after the last strike

    @classmethod
    def _play_stamped(cls):
        M = cls.msgs
        Data, Stamped, Info = (M['audio_common_msgs/AudioData'],
                               M['audio_common_msgs/AudioDataStamped'], M['audio_common_msgs/AudioInfo'])
        run = Run('/ac_stamped')
        info = run.pub('audio_info', Info, latch=True)
        audio = run.pub('audio', Stamped)
        strikes = sorted(float(r['contact_start_s']) for r in cls.truth['stamped'].values())
        starts = [s - 0.25 for s in strikes]
        plan = PLAN
        formats = {'A': ('S16LE', 2, 48000, 'wave'), 'C': ('S16LE', 2, 48000, 'mp3'),
                   'D': ('S16LE', 2, 44100, 'wave'), 'E24': ('S24LE', 2, 48000, 'wave'),
                   'E32': ('S32LE', 2, 48000, 'wave')}
        state = {'phase': None, 'mono': False}
        rng = random.Random(3)

        def send(msg, t, x):
            ts = msg.header.stamp.to_sec() - (cls.offset_s - 100.0)
            k = max([0] + [i for i, s in enumerate(starts) if ts >= s])
            phase = plan[k]
            if phase != state['phase']:
                # The chunks already sent go first: the info has a connection of its own.
                time.sleep(0.3)
                fmt, ch, rate, coding = formats[phase]
                info.publish(Info(channels=ch, sample_rate=rate, sample_format=fmt,
                                  bitrate=rate * ch * 16, coding_format=coding))
                state['phase'] = phase
                time.sleep(0.1)  # the format before the next chunk
            if phase == 'C' and not state['mono'] and ts > starts[plan.index('C')] + 0.6:
                time.sleep(0.3)
                info.publish(Info(channels=1, sample_rate=48000, sample_format='S16LE',
                                  bitrate=768000, coding_format='wave'))
                state['mono'] = True
                time.sleep(0.1)
            noise = [rng.gauss(0.0, 1e-4) for _ in x]
            fmt = formats[phase][0]
            chans = [x] if state['mono'] and phase == 'C' else [noise, x]
            audio.publish(Stamped(header=msg.header, audio=Data(data=encode(fmt, chans))))

        cls._replay(run, 'stamped', send)
        return run.stop()

    @classmethod
    def _play_plain(cls):
        M = cls.msgs
        Data, Info = M['audio_common_msgs/AudioData'], M['audio_common_msgs/AudioInfo']
        run = Run('/ac_plain')
        info = run.pub('audio_info', Info, latch=True)
        info.publish(Info(channels=2, sample_rate=48000, sample_format='F32LE', bitrate=3072000,
                          coding_format='wave'))
        audio = run.pub('audio', Data)
        rng = random.Random(4)

        def send(msg, t, x):
            noise = [rng.gauss(0.0, 1e-4) for _ in x]
            data = Data(data=encode('F32LE', [noise, x]))
            # The receive time is the node's stamp: the clock at the chunk's end
            # (as _replay published it) must be there before the chunk.
            time.sleep(0.005)
            audio.publish(data)

        cls._replay(run, 'plain', send)
        return run.stop()

    @classmethod
    def _play_wrong(cls):
        """A first publisher of each wrong kind, in a node each."""
        M = cls.msgs
        Data, Info = M['audio_common_msgs/AudioData'], M['audio_common_msgs/AudioInfo']
        wrong_definition = type('WrongDefinition', (Data,),
                                {'_full_text': 'uint8[] data\nuint8 extra\n'})
        kinds = (('string', std_msgs.msg.String, lambda: std_msgs.msg.String(data='not audio')),
                 ('fork', M['fork'], lambda: M['fork'](data=b'\0\0' * 64)),
                 ('definition', wrong_definition, lambda: wrong_definition(data=b'\0\0' * 64)))
        out = {}
        for name, klass, make in kinds:
            run = Run('/ac_wrong_' + name)
            info = run.pub('audio_info', Info, latch=True)
            info.publish(Info(channels=2, sample_rate=48000, sample_format='S16LE',
                              bitrate=1536000, coding_format='wave'))
            audio = run.pub('audio', klass)
            # Simulated time goes on (the diagnostics are on it).
            now = rospy.Time(1700000000 + int(cls.offset_s))
            cls.offset_s += 100.0
            for k in range(60):
                cls.clock.publish(Clock(clock=now + rospy.Duration(0.1 * k)))
                if k < 25:
                    audio.publish(make())
                time.sleep(0.05)
            audio.unregister()
            info.unregister()
            out[name] = run.stop()
        return out

    # --- the checks ----------------------------------------------------------------

    def test_00_shim_constants_are_genmsgs(self):
        c = header_constants()
        for name, key in (('AudioData', 'AF_AUDIO_DATA'), ('AudioDataStamped', 'AF_AUDIO_DATA_STAMPED'),
                          ('AudioInfo', 'AF_AUDIO_INFO')):
            klass = self.msgs['audio_common_msgs/' + name]
            self.assertEqual(c[key + '_TYPE'], 'audio_common_msgs/' + name)
            self.assertEqual(c[key + '_MD5'], klass._md5sum, name)
            self.assertEqual(c[key + '_DEFINITION'], definition(name), name)
        self.assertEqual(self.msgs['audio_common_msgs/AudioData']._md5sum,
                         'f43a8e1b362b75baa741461b46adc7e0')
        self.assertNotEqual(self.msgs['fork']._md5sum, c['AF_AUDIO_DATA_MD5'])

    def by_phase(self):
        reports, _, _ = self.stamped
        out = {}
        for r in reports:
            out.setdefault(PLAN[r.apple_id - 1][:1], []).append(r)
        return out

    def check_measured(self, reports, truth, what):
        for r in reports:
            f = float(truth[r.apple_id]['resonance_hz'])
            self.assertTrue(math.isfinite(r.resonance), 'apple %d (%s): no resonance' % (r.apple_id, what))
            self.assertLess(abs(r.resonance / f - 1.0), RESONANCE_RTOL,
                            'apple %d (%s): 0S2 %.2f Hz, truth %.2f Hz' % (r.apple_id, what, r.resonance, f))

    def test_01_every_strike_reported(self):
        reports, diag, err = self.stamped
        self.assertEqual(sorted(r.apple_id for r in reports), list(range(1, STRIKES + 1)), err[-2000:])
        reports, _, err = self.plain
        self.assertEqual(sorted(r.apple_id for r in reports), list(range(1, PLAIN_STRIKES + 1)),
                         err[-2000:])

    def test_02_stamped_s16le_stereo_channel_1(self):
        got = self.by_phase().get('A', [])
        self.assertEqual(len(got), PLAN.count('A'))
        self.check_measured(got, self.truth['stamped'], 'S16LE stamped')
        _, diag, _ = self.stamped
        self.assertEqual(diag.get('audio stamps (AudioDataStamped)'), 'header stamp = the first sample')

    def test_03_mp3_and_a_missing_channel_refused(self):
        got = self.by_phase().get('C', [])
        self.assertEqual(len(got), PLAN.count('C'))
        for r in got:
            self.assertTrue(math.isnan(r.resonance), 'apple %d measured from refused audio' % r.apple_id)
        _, diag, err = self.stamped
        self.assertIn("coding_format 'mp3' is not decoded", err)
        self.assertIn('~audio_channel is 1 but audio_info has 1 channel (0..0)', err)
        m = re.search(r'undecodable format (\d+)', diag.get('audio refused', ''))
        self.assertTrue(m and int(m.group(1)) > 20, diag.get('audio refused'))

    def test_04_rate_change_restarts_and_the_lane_refuses_it(self):
        for r in self.by_phase().get('D', []):
            self.assertTrue(math.isnan(r.resonance))
        _, diag, err = self.stamped
        self.assertIn('audio_info changed from 48000 Hz, S16LE, 1 channel, wave to 44100 Hz, S16LE, '
                      '2 channels, wave: a new sample rate, the audio stream restarts', err)
        self.assertIn('audio_info says 44100 Hz, the station expects 48000 Hz', err)
        m = re.search(r'restarts (\d+)', diag.get('audio stream', ''))
        self.assertTrue(m and int(m.group(1)) == 2, diag.get('audio stream'))  # ->D, ->E24
        # mp3, mono, S32LE: the same rate, the same sample clock (S24LE came with 48 kHz).
        m = re.search(r'format changes at the same rate (\d+)', diag.get('audio stream', ''))
        self.assertTrue(m and int(m.group(1)) == 3, diag.get('audio stream'))  # mp3, mono, S32LE
        self.assertIn('gaps 0 (0 samples lost)', diag.get('audio stream', ''))  # none in the stamps
        m = re.search(r'rate (\d+)', diag.get('audio bad chunks', ''))
        self.assertTrue(m and int(m.group(1)) > 20, diag.get('audio bad chunks'))

    def test_05_back_to_48_khz_s24le_and_s32le(self):
        got = self.by_phase().get('E', [])
        self.assertEqual(len(got), PLAN.count('E24') + PLAN.count('E32'))
        self.check_measured(got, self.truth['stamped'], 'S24LE/S32LE after the restarts')

    def test_06_unstamped_f32le_with_the_jitter_reported(self):
        reports, diag, _ = self.plain
        stamps = diag.get('audio stamps (AudioData)', '')
        print('AudioData stamps: ' + stamps)
        self.assertEqual(len(reports), PLAIN_STRIKES)
        self.check_measured(reports, self.truth['plain'], 'AudioData F32LE')
        m = re.search(r'RMS ([0-9.]+) ms, max ([0-9.]+) ms over (\d+) chunks', stamps)
        self.assertTrue(m, stamps)
        self.assertGreater(int(m.group(3)), 50)

    def test_07_wrong_type_md5_and_definition_refused(self):
        for name, want in (('string', 'carries std_msgs/String'),
                           ('fork', 'carries audio_common_msgs/AudioData (md5 '),
                           ('definition', "its definition differs from audio_common_msgs/AudioData's")):
            reports, diag, err = self.wrong[name]
            self.assertIn(want, diag.get('audio last problem', ''), name)
            m = re.search(r'wrong type/md5/definition (\d+)', diag.get('audio refused', ''))
            self.assertTrue(m and int(m.group(1)) >= 20, '%s: %s' % (name, diag.get('audio refused')))
            print('%s: %s' % (name, diag.get('audio last problem')))


PLAN = ['A'] * 4 + ['C'] * 3 + ['D'] * 2 + ['E24'] * 2 + ['E32'] * 3


if __name__ == '__main__':
    rostest.rosrun(sc.PKG, 'audio_common', AudioCommonTest, sys.argv)
