#!/usr/bin/python3
"""rostest of firmness_node with a 20 g hammer in the URDF: the hammer's mass
comes from robot_description, and the band equals firmness_model's with
--hammer-mass 0.020 (and differs from the 10 g hammer's)."""

import math
import sys
import unittest

import rospy
import rostest

import station_common as sc

RTOL = 1e-8


class HeavyHammerTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_heavy_hammer')
        cls.station = sc.Station()
        cls.connected = cls.station.wait_connected()
        cls.rig = sc.rig_from_parameter()

    def test_band_follows_hammer_mass(self):
        self.assertTrue(self.connected)
        self.assertEqual(self.rig.mass_kg, 0.020)  # the fixture, read without the shim
        mass, r2 = 0.175, 0.040
        self.station.send(1, mass=mass, strike_radius=r2)
        got = self.station.wait(('excitation_band', 'reliability'), 1)
        self.assertIn('excitation_band', got)
        band = got['excitation_band'][0]
        # The node predicts on the fast path: the CLI's fast path.
        heavy = sc.firmness_model_fast(**sc.model_flags(mass, r2, {'mass_kg': 0.020, 'tip_radius_m': 0.0}))
        light = sc.firmness_model(**sc.model_flags(mass, r2, {'mass_kg': 0.010, 'tip_radius_m': 0.0}))
        for field, key in (('contact_time', 'contact_time_s'), ('peak_force', 'peak_force_n'),
                           ('band_high', 'band_high_hz'), ('band_low', 'band_low_hz')):
            self.assertTrue(math.isclose(getattr(band, field), heavy[key], rel_tol=RTOL, abs_tol=1e-12),
                            '%s: node %r, firmness_model --hammer-mass 0.020 %r'
                            % (field, getattr(band, field), heavy[key]))
        # A heavier hammer stays longer on the fruit: a narrower main lobe.
        self.assertGreater(band.contact_time, light['contact_time_s'] * 1.2)
        self.assertLess(band.band_high, light['band_high_hz'] * 0.9)


if __name__ == '__main__':
    rostest.rosrun(sc.PKG, 'heavy_hammer', HeavyHammerTest, sys.argv)
