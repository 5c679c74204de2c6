#!/usr/bin/python3
"""rostest of firmness_node's start-up checks: every bad parameter stops the
node with a non-zero exit and a message naming the parameter, its value and
the accepted range; a missing or broken URDF is named; every hammer value
given as a parameter lets the node run without a URDF."""

import os
import signal
import subprocess
import sys
import time
import unittest

import rosparam
import rospkg
import rospy
import rostest
import roslib.packages

import station_common as sc

# The node checks everything before it subscribes: a refusal is quick [s].
REFUSAL_TIMEOUT_S = 20.0


class StartupTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_startup')
        pkg = rospkg.RosPack().get_path(sc.PKG)
        cls.defaults = {}
        for name in ('station.yaml', 'jonagold.yaml'):
            for params, _ in rosparam.load_file(os.path.join(pkg, 'config', name)):
                cls.defaults.update(params)
        cls.rig_xml = open(os.path.join(pkg, 'config', 'rig.urdf')).read()
        cls.exe = roslib.packages.find_node(sc.PKG, sc.NODE)[0]
        cls.lane = 0

    def start(self, changes=(), removed=(), robot_description=True):
        """Starts the node in a fresh namespace with the defaults changed."""
        StartupTest.lane += 1
        ns = '/startup%d' % StartupTest.lane
        params = dict(self.defaults)
        params.update(changes)
        for name in removed:
            del params[name]
        rosparam.upload_params(ns + '/' + sc.NODE, params)
        if robot_description:
            rospy.set_param(ns + '/robot_description',
                            robot_description if isinstance(robot_description, str) else self.rig_xml)
        return ns, subprocess.Popen([self.exe, '__ns:=' + ns, '__name:=' + sc.NODE],
                                    stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    def refused(self, *words, **kw):
        _, proc = self.start(**kw)
        try:
            _, err = proc.communicate(timeout=REFUSAL_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            proc.send_signal(signal.SIGINT)
            proc.communicate()
            self.fail('firmness_node kept running with %s' % kw)
        self.assertNotEqual(proc.returncode, 0)
        for word in words:
            self.assertIn(word, err)
        return err

    def test_bad_value(self):
        self.refused('strike_velocity_m_s', '-1', '[0.05, 10] m/s', changes={'strike_velocity_m_s': -1.0})
        # 1 nm/s lay inside the old (0, 10] and blocked the node at
        # 100 % CPU on the first apple; the physical range refuses it at once.
        self.refused('strike_velocity_m_s', '1e-09', '[0.05, 10] m/s',
                     changes={'strike_velocity_m_s': 1.0e-9})

    def test_bad_order(self):
        self.refused('modulus_nominal_pa', '1.5e+07', changes={'modulus_nominal_pa': 15e6})
        self.refused('r2_search_low_m', 'r2_search_high_m', changes={'r2_search_low_m': 0.6})

    def test_missing(self):
        self.refused('~lobe is missing', removed=('lobe',))

    def test_not_a_number(self):
        # The value is named too; YAML 1.1 reads 2.0e6 (no exponent sign) as a string.
        self.refused("~modulus_min_pa = '2.0e6' is not a number", '8.0e+6',
                     changes={'modulus_min_pa': '2.0e6'})

    def test_bad_choice(self):
        self.refused('damping_law', 'fancy', 'paper, exact, hu-guo', changes={'damping_law': 'fancy'})

    def test_bad_unit(self):
        self.refused('audio_unit', 'dB', changes={'audio_unit': 'dB'})

    def test_model_check(self):
        # [0.01, 1] passes the node's own table; the core refuses e < 0.05 with the exact law.
        self.refused('restitution', '0.01', '[0.05, 1]', changes={'restitution': 0.01})

    def test_no_urdf(self):
        self.refused('robot_description', "hammer's mass and tip radius", robot_description=False)

    def test_urdf_file_missing(self):
        self.refused('/no/such/rig.urdf', changes={'urdf_file': '/no/such/rig.urdf'})

    def test_urdf_without_hammer(self):
        self.refused("'s tip radius", 'hammer',
                     robot_description='<robot name="r"><link name="base"/></robot>',
                     changes={'hammer_mass_kg': 0.01})

    def test_runs_on_parameters_alone(self):
        ns, proc = self.start(changes={'hammer_mass_kg': 0.012, 'hammer_tip_radius_m': 0.0},
                              robot_description=False)
        try:
            from acoustic_firmness.msg import AppleEstimate, Reliability
            got = []
            sub = rospy.Subscriber(ns + '/reliability', Reliability, got.append)
            pub = rospy.Publisher(ns + '/apple', AppleEstimate, queue_size=1)
            end = time.time() + 20.0
            while time.time() < end and (pub.get_num_connections() == 0 or sub.get_num_connections() == 0):
                self.assertIsNone(proc.poll(), proc.stderr.read() if proc.poll() is not None else '')
                time.sleep(0.1)
            msg = AppleEstimate()
            msg.header.frame_id = 'camera_optical_frame'
            msg.apple_id, msg.mass, msg.equatorial_radius, msg.confidence = 5, 0.175, 0.04, 1.0
            pub.publish(msg)
            end = time.time() + 5.0
            while time.time() < end and not got:
                time.sleep(0.05)
            self.assertTrue(got)
            self.assertFalse(got[0].reliable)
            self.assertIn('hammer axis unknown (no URDF)', got[0].reason)
            self.assertEqual(rospy.get_param(ns + '/' + sc.NODE + '/hammer_mass_kg'), 0.012)
        finally:
            proc.send_signal(signal.SIGINT)
            proc.communicate(timeout=10.0)


if __name__ == '__main__':
    rostest.rosrun(sc.PKG, 'startup', StartupTest, sys.argv)
