#!/usr/bin/python3
"""rostest of firmness_node's ~evaluate service (srv/Evaluate.srv): for given
apples and strikes the answer equals `firmness_model --json` for the same
inputs (the node's configured hammer from the URDF, criteria and cultivar),
the overrides replace the configured values, and bad requests are refused
with ok false and one line naming the field, its value and the accepted range
of its row of the parameter table, never a failed call."""

import math
import sys
import unittest

import rospy
import rostest
from acoustic_firmness.srv import Evaluate, EvaluateRequest

import station_common as sc

RTOL = 1e-8  # the same core on the same inputs; the CLI's JSON has 10 digits


class EvaluateTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_evaluate')
        name = rospy.resolve_name(sc.NODE) + '/evaluate'
        rospy.wait_for_service(name, timeout=30.0)
        cls.call = rospy.ServiceProxy(name, Evaluate)
        cls.rig = sc.rig_from_parameter()

    def assertRel(self, actual, expected, what):
        self.assertTrue(math.isclose(actual, expected, rel_tol=RTOL, abs_tol=1e-12),
                        '%s: service %r, firmness_model %r' % (what, actual, expected))

    def compare(self, req, flags):
        ans = self.call(req)
        self.assertTrue(ans.ok, ans.error)
        self.assertEqual(ans.error, '')
        ref = sc.firmness_model(**flags)
        for field, key in (('contact_time', 'contact_time_s'), ('peak_force', 'peak_force_n'),
                           ('max_deformation', 'max_deformation_m'),
                           ('delivered_restitution', 'delivered_restitution'),
                           ('band_low', 'band_low_hz'), ('band_high', 'band_high_hz'),
                           ('resonance', 'resonance_hz'),
                           ('excitation_at_resonance_db', 'excitation_at_resonance_db'),
                           ('max_contact_pressure', 'max_contact_pressure_pa'),
                           ('max_shear_stress', 'max_shear_stress_pa'),
                           ('yield_shear_stress', 'yield_shear_stress_pa')):
            self.assertRel(getattr(ans, field), ref[key], field)
        if ref['min_strike_radius_m'] is None:
            self.assertEqual(ans.min_strike_radius, 0.0)
        else:
            self.assertRel(ans.min_strike_radius, ref['min_strike_radius_m'], 'min_strike_radius')
        for flag in ('excites_mode', 'no_damage', 'reliable'):
            self.assertEqual(getattr(ans, flag), ref[flag], flag)
        self.assertEqual(ans.reason == '', ans.reliable)
        self.assertEqual(ans.lobe, int(sc.param('lobe')))
        # The 0S2 over the cultivar's firmness range, for this mass.
        for field, modulus in (('resonance_low', 'modulus_min_pa'),
                               ('resonance_high', 'modulus_max_pa')):
            low = sc.firmness_model(**dict(flags, E2=float(sc.param(modulus))))
            self.assertRel(getattr(ans, field), low['resonance_hz'], field)
        return ans

    def test_01_configured_values(self):
        req = EvaluateRequest(mass=0.160, strike_radius=0.045)
        ans = self.compare(req, sc.model_flags(0.160, 0.045, self.rig.hammer()))
        self.assertEqual(ans.modulus, float(sc.param('modulus_nominal_pa')))
        self.assertEqual(ans.restitution, float(sc.param('restitution')))
        self.assertEqual(ans.velocity, float(sc.param('strike_velocity_m_s')))
        self.assertEqual(ans.hammer_mass, self.rig.hammer()['mass_kg'])

    def test_02_the_papers_strike_is_reliable_a_small_radius_is_not(self):
        ans = self.compare(EvaluateRequest(mass=0.175, strike_radius=0.040),
                           sc.model_flags(0.175, 0.040, self.rig.hammer()))
        self.assertTrue(ans.reliable)
        ans = self.compare(EvaluateRequest(mass=0.175, strike_radius=0.010),
                           sc.model_flags(0.175, 0.010, self.rig.hammer()))
        self.assertFalse(ans.no_damage)
        self.assertIn('shear', ans.reason)

    def test_03_overrides(self):
        req = EvaluateRequest(mass=0.210, strike_radius=0.035, modulus=4.5e6, restitution=0.7,
                              velocity=1.1, hammer_mass=0.02)
        flags = sc.model_flags(0.210, 0.035, dict(self.rig.hammer(), mass_kg=0.02))
        flags.update(E2=4.5e6, e=0.7, v0=1.1)
        ans = self.compare(req, flags)
        self.assertEqual((ans.modulus, ans.restitution, ans.velocity, ans.hammer_mass),
                         (4.5e6, 0.7, 1.1, 0.02))

    def refused(self, req, want):
        ans = self.call(req)
        self.assertFalse(ans.ok)
        self.assertEqual(ans.error, want)
        self.assertTrue(math.isnan(ans.contact_time) and math.isnan(ans.resonance))
        self.assertFalse(ans.reliable)

    def test_04_refusals_name_the_field_and_the_tables_range(self):
        self.refused(EvaluateRequest(mass=0.0, strike_radius=0.04),
                     'mass is required (a number in [0.001, 10] kg, the range of ~mass_min_kg)')
        self.refused(EvaluateRequest(mass=20.0, strike_radius=0.04),
                     'mass = 20 is outside the accepted range [0.001, 10] kg (the range of '
                     '~mass_min_kg)')
        self.refused(EvaluateRequest(mass=0.175, strike_radius=0.0),
                     'strike_radius is required (a number in [0.0005, 1] m, the range of '
                     '~strike_radius_min_m)')
        self.refused(EvaluateRequest(mass=0.175, strike_radius=0.04, modulus=1e12),
                     'modulus = 1e+12 is outside the accepted range [1e5, 1e9] Pa (the range of '
                     '~modulus_nominal_pa)')
        self.refused(EvaluateRequest(mass=0.175, strike_radius=0.04, velocity=float('nan')),
                     'velocity = nan is outside the accepted range [0.05, 10] m/s (the range of '
                     '~strike_velocity_m_s)')
        self.refused(EvaluateRequest(mass=0.175, strike_radius=0.04, hammer_mass=-1.0),
                     'hammer_mass = -1 is outside the accepted range [0.0005, 1] kg (the range of '
                     '~hammer_mass_kg)')
        # In the table's range, outside the cultivar's (jonagold.yaml: mass_min_kg 0.1,
        # mass_max_kg 0.25) or the station's (strike_radius_max_m 0.5): refused as the
        # lane's prediction refuses such an apple, never answered "reliable".
        self.refused(EvaluateRequest(mass=0.5, strike_radius=0.04),
                     'the lane would refuse this apple: mass = 0.5 kg is outside the accepted '
                     'range [0.1, 0.25] kg')
        self.refused(EvaluateRequest(mass=0.05, strike_radius=0.04),
                     'the lane would refuse this apple: mass = 0.05 kg is outside the accepted '
                     'range [0.1, 0.25] kg')
        self.refused(EvaluateRequest(mass=0.175, strike_radius=0.8),
                     'the lane would refuse this apple: strike_radius = 0.8 m is outside the '
                     'accepted range 0 (unknown) or [0.002, 0.5] m')
        # In the table's range, refused by the model's own check (exact damping: e >= 0.05).
        ans = self.call(EvaluateRequest(mass=0.175, strike_radius=0.04, restitution=0.02))
        self.assertFalse(ans.ok)
        self.assertIn('impact.restitution = 0.02', ans.error)
        # The node is still there and answers.
        self.assertTrue(self.call(EvaluateRequest(mass=0.175, strike_radius=0.04)).ok)


if __name__ == '__main__':
    rostest.rosrun(sc.PKG, 'evaluate', EvaluateTest, sys.argv)
