#!/usr/bin/python3
"""rostest (rates.test): diagnostic_aggregator, started by station.launch with
config/analyzers.yaml, groups the lane's diagnostics: /diagnostics_agg holds
"/Firmness station lane1", "/Firmness station lane1/Station node" and, under
it, the node's own status with its keys (strikes, grades, reconfigure,
evaluate), not STALE while it runs."""

import sys
import threading
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus


class AggregatorTest(unittest.TestCase):

    def test_lane_group(self):
        rospy.init_node('test_aggregator')
        got = {}
        lock = threading.Lock()

        def on_agg(msg):
            with lock:
                for s in msg.status:
                    got[s.name] = s

        sub = rospy.Subscriber('/diagnostics_agg', DiagnosticArray, on_agg, queue_size=10)
        end = time.time() + 40.0
        want = ('/Firmness station lane1', '/Firmness station lane1/Station node')

        def node_status():
            for name, s in got.items():
                if name.startswith(want[1] + '/') and 'firmness station' in name:
                    return s
            return None
        while time.time() < end:
            with lock:
                if all(w in got for w in want) and node_status() is not None:
                    break
            time.sleep(0.2)
        sub.unregister()
        with lock:
            self.assertIn(want[0], got, sorted(got))
            self.assertIn(want[1], got, sorted(got))
            node = node_status()
            self.assertIsNotNone(node, sorted(got))
            keys = {kv.key for kv in node.values}
            for key in ('strikes', 'strikes per grade', 'reconfigure', 'evaluate calls'):
                self.assertIn(key, keys)
            self.assertNotEqual(node.level, DiagnosticStatus.STALE)
            self.assertNotEqual(got[want[0]].level, DiagnosticStatus.STALE)
            print('%s: level %d, %s' % (node.name, node.level, node.message))


if __name__ == '__main__':
    rostest.rosrun('acoustic_firmness', 'aggregated_lane', AggregatorTest, sys.argv)
