#!/usr/bin/python3
"""rostest of firmness_node on the lab rig (config/rig.urdf): answers within
1 s with the AppleEstimate's id, stamp and frame; values equal to
firmness_model's for the same inputs; the strike geometry on the spheroid;
small-R2 and bad-field apples; markers; stream bookkeeping in /diagnostics."""

import math
import struct
import sys
import time
import unittest

import genpy

import rospy
import rostest
from acoustic_firmness.msg import SignalChunk
from diagnostic_msgs.msg import DiagnosticArray

import station_common as sc

ALL = ('excitation_band', 'strike_advice', 'reliability')
# The node and the CLI run the same core on the same inputs; JSON carries
# 10 significant digits.
RTOL = 1e-8
# The fast path against the ODE path (fastpath.h) [relative].
FAST_RTOL = 1e-3


class StationTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_station')
        cls.station = sc.Station()
        cls.connected = cls.station.wait_connected()
        cls.rig = sc.rig_from_parameter()
        cls.next_id = 100

    def new_id(self):
        StationTest.next_id += 1
        return StationTest.next_id

    def assertRel(self, actual, expected, what):
        self.assertTrue(math.isclose(actual, expected, rel_tol=RTOL, abs_tol=1e-12),
                        '%s: node %r, firmness_model %r' % (what, actual, expected))

    def ask(self, topics=ALL, **apple):
        apple_id = self.new_id()
        msg, _ = self.station.send(apple_id, **apple)
        got = self.station.wait(topics, apple_id)
        self.assertEqual(set(got), set(topics), 'apple %d: answers on %s only' % (apple_id, list(got)))
        return msg, {t: m for t, (m, _) in got.items()}

    @staticmethod
    def node_diag(done, timeout_s=5.0):
        """The node's latest /diagnostics values {key: value}, once done(values)
        holds or timeout_s has passed."""
        values = {}
        end = time.time() + timeout_s
        while time.time() < end and not done(values):
            arr = rospy.wait_for_message('/diagnostics', DiagnosticArray, timeout=5.0)
            values = sc.diag_values(arr, rospy.resolve_name(sc.NODE)) or values
        return values

    def test_01_node_up(self):
        self.assertTrue(self.connected, 'firmness_node did not connect to apple and its outputs')

    def test_02_answers_within_1s_echo_header(self):
        apple_id = self.new_id()
        msg, sent = self.station.send(apple_id, strike_radius=0.040)
        got = self.station.wait(ALL, apple_id, timeout_s=3.0)
        self.assertEqual(set(got), set(ALL))
        for topic, (answer, received) in got.items():
            self.assertLess(received - sent, sc.ANSWER_TIMEOUT_S, '%s came late' % topic)
            self.assertEqual(answer.apple_id, apple_id)
            self.assertEqual(answer.header.stamp, msg.header.stamp, '%s stamp' % topic)
            self.assertEqual(answer.header.frame_id, msg.header.frame_id, '%s frame' % topic)

    def test_03_values_equal_firmness_model(self):
        mass, r2 = 0.160, 0.045
        _, out = self.ask(mass=mass, strike_radius=r2)
        band, advice, rel = out['excitation_band'], out['strike_advice'], out['reliability']
        flags = sc.model_flags(mass, r2, self.rig.hammer())
        # The node predicts on the fast path: equal to the CLI's
        # fast path, and to its ODE path within the fast path's documented
        # accuracy (fastpath.h, 0.1 %).
        ref = sc.firmness_model_fast(**flags)
        ode = sc.firmness_model(**flags)
        for key in ('contact_time_s', 'peak_force_n', 'band_high_hz', 'resonance_hz',
                    'max_shear_stress_pa', 'yield_shear_stress_pa'):
            self.assertTrue(math.isclose(ref[key], ode[key], rel_tol=FAST_RTOL),
                            '%s: fast path %r, ODE path %r' % (key, ref[key], ode[key]))
        self.assertRel(band.contact_time, ref['contact_time_s'], 'contact_time')
        self.assertRel(band.peak_force, ref['peak_force_n'], 'peak_force')
        self.assertEqual(band.lobe, int(sc.param('lobe')))
        self.assertRel(band.band_low, ref['band_low_hz'], 'band_low')
        self.assertRel(band.band_high, ref['band_high_hz'], 'band_high')
        self.assertRel(band.resonance, ref['resonance_hz'], 'resonance')
        self.assertRel(band.excitation_at_resonance_db, ref['excitation_at_resonance_db'],
                       'excitation_at_resonance_db')
        self.assertRel(rel.max_shear_stress, ref['max_shear_stress_pa'], 'max_shear_stress')
        self.assertRel(rel.yield_shear_stress, ref['yield_shear_stress_pa'], 'yield_shear_stress')
        self.assertEqual(rel.excites_mode, ref['excites_mode'])
        self.assertEqual(rel.no_damage, ref['no_damage'])
        self.assertEqual(rel.reliable, ref['reliable'])
        self.assertEqual(rel.source, 'predicted')
        self.assertEqual(rel.reason == '', rel.reliable)
        self.assertEqual(advice.strike_radius, r2)
        # Same R2 search bracket as the CLI's in station.yaml: same root.
        if ref['min_strike_radius_m'] is None:
            self.assertEqual(advice.min_strike_radius, 0.0)
        else:
            self.assertRel(advice.min_strike_radius, ref['min_strike_radius_m'], 'min_strike_radius')
        # The resonance band: 0S2 at the ends of the firmness range.
        for field, modulus in (('resonance_low', 'modulus_min_pa'), ('resonance_high', 'modulus_max_pa')):
            flags['E2'] = float(sc.param(modulus))
            self.assertRel(getattr(band, field), sc.firmness_model(**flags)['resonance_hz'], field)

    def test_04_small_radius_rotate_unreliable(self):
        _, out = self.ask(strike_radius=0.008)
        advice, rel = out['strike_advice'], out['reliability']
        self.assertTrue(advice.rotate, advice.text)
        self.assertGreater(advice.min_strike_radius, 0.008)
        self.assertFalse(rel.reliable)
        self.assertNotEqual(rel.reason, '')
        self.assertIn('flatter', advice.text)
        self.assertAlmostEqual(math.hypot(advice.rotation_axis.x, advice.rotation_axis.y,
                                          advice.rotation_axis.z), 1.0, places=9)

    def check_bad(self, field, **apple):
        _, out = self.ask(topics=('reliability',), **apple)
        rel = out['reliability']
        self.assertFalse(rel.reliable)
        self.assertEqual(rel.source, 'predicted')
        self.assertIn(field, rel.reason)
        self.assertIn('accepted range', rel.reason)
        return rel

    def test_05_bad_fields(self):
        rel = self.check_bad('mass', mass=0.5)
        self.assertIn('0.5', rel.reason)
        self.check_bad('mass', mass=float('nan'))
        self.check_bad('equatorial_radius', equatorial_radius=-0.04)
        self.check_bad('strike_radius', strike_radius=-0.01)
        self.check_bad('stem_axis.y', stem_axis=(0.0, float('inf'), 1.0))
        self.check_bad('confidence', confidence=1.5)
        self.check_bad('aspect', mass=0.100, equatorial_radius=0.060)
        # The node is still there and answers the next good apple.
        self.ask(strike_radius=0.040)

    def test_06_spheroid_geometry(self):
        """R2 from the shape: 45 deg towards the stem, turned back to the equator."""
        frame = 'camera_optical_frame'
        d = self.rig.strike_direction_in(frame)
        n = [-x for x in d]
        # A stem axis at 45 deg from n, perpendicular component along any
        # direction orthogonal to n.
        perp = sc.unit([n[1] - n[2], n[2] - n[0], n[0] - n[1]])
        stem = [(n[i] + perp[i]) * 3.0 for i in range(3)]  # any length
        mass, a = 0.175, 0.040
        _, out = self.ask(mass=mass, equatorial_radius=a, stem_axis=stem, frame=frame)
        advice = out['strike_advice']
        c = sc.polar_semi_axis(mass, float(sc.param('density_kg_m3')), a)
        self.assertAlmostEqual(advice.strike_latitude, math.pi / 4, places=9)
        self.assertAlmostEqual(advice.strike_radius, sc.equivalent_radius(a, c, math.pi / 4), places=12)
        self.assertTrue(advice.rotate)
        self.assertAlmostEqual(advice.rotation_angle, -math.pi / 4, places=9)
        axis = [advice.rotation_axis.x, advice.rotation_axis.y, advice.rotation_axis.z]
        turned = sc.rotate(axis, advice.rotation_angle, sc.unit(stem))
        self.assertAlmostEqual(sum(turned[i] * n[i] for i in range(3)), 0.0, places=9)
        self.assertIn('towards the stem', advice.text)
        # On the equator: R2 = c, no rotation for latitude.
        _, out = self.ask(mass=mass, equatorial_radius=a, stem_axis=perp, frame=frame)
        advice = out['strike_advice']
        self.assertAlmostEqual(advice.strike_latitude, 0.0, places=12)
        self.assertAlmostEqual(advice.strike_radius, c, places=12)

    def test_07_stem_unknown_and_frame_unknown(self):
        _, out = self.ask(stem_axis=(0.0, 0.0, 0.0))
        self.assertEqual(out['strike_advice'].strike_latitude, 0.0)
        self.assertIn('stem axis unknown', out['strike_advice'].text)
        _, out = self.ask(frame='no_such_frame')
        rel = out['reliability']
        self.assertFalse(rel.reliable)
        self.assertIn("frame 'no_such_frame' does not exist in TF", rel.reason)
        self.assertEqual(out['strike_advice'].strike_radius, 0.040)  # the equatorial radius
        # A measured strike radius does not need the frame.
        _, out = self.ask(frame='no_such_frame', strike_radius=0.05)
        self.assertNotIn('does not exist in TF', out['reliability'].reason)

    def test_08_markers(self):
        apple_id = self.new_id()
        msg, _ = self.station.send(apple_id, strike_radius=0.008)
        self.station.wait(ALL, apple_id)
        end = time.time() + 2.0
        mine = []
        while time.time() < end and not mine:
            with self.station.lock:
                mine = [m for m in self.station.markers
                        if any(apple_id == int(k.text.split(':')[0].split()[-1])
                               for k in m.markers
                               if k.type == k.TEXT_VIEW_FACING and k.ns == 'firmness')]
            time.sleep(0.05)
        self.assertTrue(mine, 'no MarkerArray for apple %d' % apple_id)
        markers = mine[-1].markers
        self.assertEqual(len(markers), 5)
        for m in markers:
            self.assertEqual(m.header.stamp, msg.header.stamp)
            self.assertEqual(m.header.frame_id, msg.header.frame_id)
        arrows = [m for m in markers if m.type == m.ARROW and m.action == m.ADD]
        self.assertEqual(len(arrows), 2)  # hammer axis and rotation advice

    def test_09_stream_gaps_and_bad_chunks(self):
        force = rospy.Publisher('force', SignalChunk, queue_size=10)
        audio = rospy.Publisher('audio', SignalChunk, queue_size=10)
        end = time.time() + 10.0
        while time.time() < end and (force.get_num_connections() == 0 or audio.get_num_connections() == 0):
            time.sleep(0.05)

        def chunk(first, rate, unit, data):
            c = SignalChunk()
            c.header.stamp = rospy.Time(2000)
            c.first_sample, c.sample_rate, c.unit, c.data = first, rate, unit, data
            return c

        rate = float(sc.param('force_sample_rate_hz'))
        force.publish(chunk(0, rate, 'N', [0.0] * 100))
        force.publish(chunk(150, rate, 'N', [1.0] * 100))    # 50 lost
        force.publish(chunk(250, rate / 2, 'N', [1.0] * 10))  # wrong rate
        force.publish(chunk(250, rate, 'V', [1.0] * 10))      # wrong unit
        # Non-finite samples are refused as a counted span, the
        # chunk kept (3 chunks); an index overflow is its own reason.
        force.publish(chunk(250, rate, 'N', [1.0] * 3 + [float('nan')] * 5 + [float('inf')] * 2))
        force.publish(chunk(2 ** 64 - 5, rate, 'N', [1.0] * 10))  # first_sample + n overflows
        audio.publish(chunk(0, float(sc.param('audio_sample_rate_hz')), sc.param('audio_unit'), [0.0] * 10))
        want = {'force gaps': '1 (50 samples lost)',
                'force bad chunks': '3 (rate 1, unit 1, index overflow 1, malformed 0, oversized 0)',
                'force refused samples': '7 non-finite in 1 spans of 1 chunks',
                'force chunks': '3', 'audio chunks': '1'}
        values = self.node_diag(lambda v: all(v.get(k) == w for k, w in want.items()))
        for key, value in want.items():
            self.assertEqual(values.get(key), value, key)
        self.assertIn('URDF source', values)

    def test_10_malformed_chunk_dropped(self):
        """A SignalChunk whose data length claims more floats than its bytes
        hold (20 bytes can claim 16 GB, which roscpp's deserializer would
        allocate): dropped before deserializing, counted, the node alive."""

        class RawChunk(genpy.Message):
            """SignalChunk's type and md5sum on the wire, any bytes inside."""
            _type, _md5sum, _full_text = SignalChunk._type, SignalChunk._md5sum, SignalChunk._full_text
            _has_header = False
            __slots__ = ['raw']
            _slot_types = ['string']

            def __init__(self, raw=b''):
                self.raw = raw

            def serialize(self, buff):
                buff.write(self.raw)

        force = rospy.Publisher('force', RawChunk, queue_size=10)
        end = time.time() + 10.0
        while time.time() < end and force.get_num_connections() == 0:
            time.sleep(0.05)
        rate = float(sc.param('force_sample_rate_hz'))
        # seq, stamp, frame_id ''; first_sample, sample_rate; unit 'N'; data:
        # 2^30 floats claimed, 8 bytes present
        raw = struct.pack('<IIII', 0, 3000, 0, 0) + struct.pack('<Qd', 10 ** 6, rate) + \
            struct.pack('<I', 1) + b'N' + struct.pack('<I', 1 << 30) + bytes(8)
        for _ in range(2):
            force.publish(RawChunk(raw))
        values = self.node_diag(lambda v: v.get('malformed messages dropped') == '2')
        self.assertEqual(values.get('malformed messages dropped'), '2')
        self.ask(strike_radius=0.040, stamp=rospy.Time(2000))  # still answering (near the data)


if __name__ == '__main__':
    rostest.rosrun(sc.PKG, 'station', StationTest, sys.argv)
