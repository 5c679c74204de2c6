#!/usr/bin/python3
"""rostest of tap-only mode on digital silence: an 11-strike bag of
`strike_bag --tap-only` at 1 s spacing whose audio is made exact zeros with
the rosbag Python API (test/rig_faults/gate_bag.py) for the first 10 strikes
(10 s of zeros with their apples) and around the 11th but from 20 ms before
it (a noise gate opening onto the bag's noise), replayed on simulated time
through firmness_node with tap_only true. Exactly one StrikeReport: the 11th
apple's, stamped within 1 ms of its contact start."""

import csv
import os
import shutil
import subprocess
import tempfile
import threading
import time
import unittest

import rospy
import rostest
from acoustic_firmness.msg import StrikeReport

import station_common as sc

STRIKES = 11
SILENT = 10
SEED = 30
RATE = 5.0
GATE = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'rig_faults', 'gate_bag.py')


class TapOnlySilenceTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_tap_only_silence')
        cls.tmp = tempfile.mkdtemp(prefix='af_silence_')
        src = os.path.join(cls.tmp, 'tap.bag')
        cls.bag = os.path.join(cls.tmp, 'gated.bag')
        subprocess.run([sc.find('strike_bag'), '--strikes', str(STRIKES), '--seed', str(SEED),
                        '--spacing', '1.0', '--tap-only', '--out', src,
                        '--ns', rospy.get_namespace().strip('/')],
                       check=True, capture_output=True, text=True)
        truth_csv = os.path.join(cls.tmp, 'tap.truth.csv')
        subprocess.run(['/usr/bin/python3', GATE, src, truth_csv, cls.bag, '0.02', str(SILENT)],
                       check=True, capture_output=True, text=True)
        with open(truth_csv) as f:
            cls.truth = {int(r['apple_id']): r for r in csv.DictReader(f)}
        cls.lock = threading.Lock()
        cls.reports = []
        cls.sub = rospy.Subscriber('strike_report', StrikeReport, cls._on_report, queue_size=1000)
        end = time.time() + 30.0
        while time.time() < end and cls.sub.get_num_connections() == 0:
            time.sleep(0.1)
        sc.play(cls.bag, RATE)
        time.sleep(2.0)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    @classmethod
    def _on_report(cls, msg):
        with cls.lock:
            cls.reports.append(msg)

    def test_one_strike_after_silence(self):
        with self.lock:
            reports = list(self.reports)
        print('tap-only through the node, 10 s of exact zeros then one gated tap: %d reports, '
              'apples %s' % (len(reports), [r.apple_id for r in reports]))
        self.assertEqual([r.apple_id for r in reports], [STRIKES])
        t = self.truth[STRIKES]
        self.assertLess(abs(reports[0].header.stamp.to_sec() - float(t['contact_start_s'])), 0.001)


if __name__ == '__main__':
    rostest.rosrun(sc.PKG, 'tap_only_silence', TapOnlySilenceTest)
