#!/usr/bin/python3
"""rostest of tap-only mode: a 30-strike bag of `strike_bag
--tap-only` (audio and AppleEstimates, no force topic; its truth CSV beside
it) replayed on simulated time through firmness_node with tap_only true.
The node subscribes to no force topic; exactly one StrikeReport per strike,
stamped within 1 ms of the truth's contact start (the audio onset), its 0S2
within 0.5 % and its stiffness factor within 1 % of the truth, every pulse
figure NaN, tap_only and judged_from_model set; /diagnostics says the input
mode."""

import csv
import math
import os
import shutil
import subprocess
import tempfile
import threading
import time
import unittest

import rosgraph
import rospy
import rostest
from acoustic_firmness.msg import StrikeReport
from diagnostic_msgs.msg import DiagnosticArray

import station_common as sc

STRIKES = 30
SEED = 19
RATE = 5.0


class TapOnlyTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_tap_only')
        cls.tmp = tempfile.mkdtemp(prefix='af_tap_')
        cls.bag = os.path.join(cls.tmp, 'tap.bag')
        subprocess.run([sc.find('strike_bag'), '--strikes', str(STRIKES), '--seed', str(SEED),
                        '--spacing', '0.3', '--tap-only', '--out', cls.bag,
                        '--ns', rospy.get_namespace().strip('/')],
                       check=True, capture_output=True, text=True)
        with open(os.path.join(cls.tmp, 'tap.truth.csv')) as f:
            cls.truth = {int(r['apple_id']): r for r in csv.DictReader(f)}
        cls.lock = threading.Lock()
        cls.reports, cls.diag = [], {}
        cls.subs = [rospy.Subscriber('strike_report', StrikeReport, cls._on_report, queue_size=1000),
                    rospy.Subscriber('/diagnostics', DiagnosticArray, cls._on_diag, queue_size=100)]
        end = time.time() + 30.0
        while time.time() < end and cls.subs[0].get_num_connections() == 0:
            time.sleep(0.1)
        sc.play(cls.bag, RATE)
        end = time.time() + 10.0
        while time.time() < end:
            with cls.lock:
                if len(cls.reports) >= STRIKES and cls.diag:
                    break
            time.sleep(0.05)
        time.sleep(1.0)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    @classmethod
    def _on_report(cls, msg):
        with cls.lock:
            cls.reports.append(msg)

    @classmethod
    def _on_diag(cls, msg):
        values = sc.diag_values(msg, rospy.resolve_name(sc.NODE))
        if values:
            with cls.lock:
                cls.diag = values

    def test_01_no_force_subscription(self):
        _, subscribers, _ = rosgraph.Master('/test_tap_only').getSystemState()
        node = rospy.resolve_name(sc.NODE)
        force = rospy.resolve_name('force')
        subscribed = [t for t, nodes in subscribers if node in nodes]
        self.assertNotIn(force, subscribed)
        self.assertIn(rospy.resolve_name('audio'), subscribed)
        self.assertIn('tap_only', self.diag.get('input mode', ''))

    def test_02_against_the_truth(self):
        with self.lock:
            reports = list(self.reports)
        self.assertEqual(sorted(r.apple_id for r in reports), list(range(1, STRIKES + 1)))
        worst_f = worst_sf = worst_t = 0.0
        for r in reports:
            t = self.truth[r.apple_id]
            f_true, m = float(t['resonance_hz']), float(t['mass_kg'])
            worst_f = max(worst_f, abs(r.resonance / f_true - 1.0))
            worst_sf = max(worst_sf, abs(r.stiffness_factor / (f_true ** 2 * m ** (2.0 / 3.0)) - 1.0))
            worst_t = max(worst_t, abs(r.header.stamp.to_sec() - float(t['contact_start_s'])))
            self.assertEqual(r.header.frame_id, 'microphone')
            self.assertTrue(r.tap_only, 'apple %d' % r.apple_id)
            self.assertEqual(r.judged_from_model, 'shear judged from the model only')
            for name in ('contact_time', 'peak_force', 'impulse', 'fitted_modulus'):
                self.assertTrue(math.isnan(getattr(r, name)), '%s of apple %d' % (name, r.apple_id))
        print('tap-only through the node: %d strikes, worst 0S2 %.3f %%, stiffness factor %.3f %%, '
              'onset %.3f ms' % (len(reports), 100 * worst_f, 100 * worst_sf, 1e3 * worst_t))
        self.assertLess(worst_f, 0.005)
        self.assertLess(worst_sf, 0.01)
        self.assertLess(worst_t, 0.001)


if __name__ == '__main__':
    rostest.rosrun(sc.PKG, 'tap_only', TapOnlyTest)
