#!/usr/bin/python3
"""rostest of the strike geometry through TF: an AppleEstimate in a camera
frame that exists only in TF (static transforms, not in the URDF) gets the
same strike latitude, R2, rotation advice and verdict as the same apple in
the URDF's camera_optical_frame (same pose); an unknown frame and a frame on
another TF tree get no silent default: the prediction says why its strike
point is unknown, naming the frame."""

import math
import sys
import time
import unittest

import rospy
import rostest

import station_common as sc

ALL = ('excitation_band', 'strike_advice', 'reliability')
URDF_FRAME, TF_FRAME = 'camera_optical_frame', 'calib_camera_optical'


class TfFrameTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_tf_frame')
        cls.station = sc.Station()
        cls.connected = cls.station.wait_connected()
        cls.next_id = 500

    def new_id(self):
        TfFrameTest.next_id += 1
        return TfFrameTest.next_id

    def ask(self, frame, **apple):
        apple_id = self.new_id()
        self.station.send(apple_id, frame=frame, **apple)
        got = self.station.wait(ALL, apple_id)
        self.assertEqual(set(got), set(ALL), 'apple %d in %s: answers on %s only'
                         % (apple_id, frame, list(got)))
        return {t: m for t, (m, _) in got.items()}

    def ask_when_known(self, frame, timeout_s=10.0, **apple):
        """The static transforms come from their own nodes: ask until the
        frame is in the node's TF buffer (a known strike point)."""
        end = time.time() + timeout_s
        while True:
            out = self.ask(frame, **apple)
            if 'strike point unknown' not in out['strike_advice'].text or time.time() > end:
                return out
            time.sleep(0.2)

    def test_01_node_up(self):
        self.assertTrue(self.connected, 'firmness_node did not connect')

    def test_02_tf_only_frame_equals_urdf_frame(self):
        for stem in ((1.0, 0.0, -1.0), (0.0, 1.0, 0.0), (0.3, -0.2, 1.0)):
            apple = dict(mass=0.175, equatorial_radius=0.040, stem_axis=stem)
            urdf = self.ask_when_known(URDF_FRAME, **apple)
            tf = self.ask_when_known(TF_FRAME, **apple)
            a, b = urdf['strike_advice'], tf['strike_advice']
            print('stem %s: latitude %.6f rad (URDF frame) / %.6f rad (TF-only frame); %s'
                  % (stem, a.strike_latitude, b.strike_latitude, b.text))
            self.assertNotIn('unknown', b.text)
            self.assertAlmostEqual(a.strike_latitude, b.strike_latitude, delta=1e-9)
            self.assertAlmostEqual(a.strike_radius, b.strike_radius, delta=1e-12)
            self.assertAlmostEqual(a.min_strike_radius, b.min_strike_radius, delta=1e-12)
            self.assertEqual(a.rotate, b.rotate)
            self.assertAlmostEqual(a.rotation_angle, b.rotation_angle, delta=1e-9)
            for k in ('x', 'y', 'z'):
                self.assertAlmostEqual(getattr(a.rotation_axis, k), getattr(b.rotation_axis, k),
                                       delta=1e-9)
            self.assertEqual(a.text.replace(URDF_FRAME, TF_FRAME).split(':', 1)[1],
                             b.text.split(':', 1)[1])
            ra, rb = urdf['reliability'], tf['reliability']
            self.assertEqual((ra.reliable, ra.excites_mode, ra.no_damage, ra.reason),
                             (rb.reliable, rb.excites_mode, rb.no_damage, rb.reason))
            self.assertAlmostEqual(urdf['excitation_band'].band_high,
                                   tf['excitation_band'].band_high, delta=1e-9)

    def test_03_known_latitude(self):
        """The rig strikes along +z of camera_optical_frame: a stem tilted
        45 degrees towards the camera gives latitude pi/4 in either frame."""
        b = self.ask_when_known(TF_FRAME, stem_axis=(1.0, 0.0, -1.0))['strike_advice']
        self.assertAlmostEqual(b.strike_latitude, math.pi / 4, delta=1e-9)
        self.assertTrue(b.rotate)

    def test_04_unknown_frame_says_why(self):
        out = self.ask('no_such_camera')
        rel, adv = out['reliability'], out['strike_advice']
        self.assertFalse(rel.reliable)
        self.assertIn("frame 'no_such_camera' does not exist in TF", rel.reason)
        self.assertIn("'no_such_camera' does not exist in TF", adv.text)
        self.assertIn('strike point unknown', adv.text)
        self.assertEqual(adv.strike_latitude, 0.0)

    def test_05_frame_on_another_tree_says_why(self):
        out = self.ask_when_known('lonely_camera', timeout_s=3.0)
        rel = out['reliability']
        self.assertFalse(rel.reliable)
        self.assertIn("'lonely_camera' and 'rig_base' are not connected in TF", rel.reason)


if __name__ == '__main__':
    rostest.rosrun(sc.PKG, 'tf_frame', TfFrameTest)
