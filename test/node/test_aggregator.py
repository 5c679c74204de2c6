#!/usr/bin/python3
"""rostest (rates.test): diagnostic_aggregator, started by station.launch with
config/analyzers.yaml, groups the lane's diagnostics on a healthy replay:
/diagnostics_agg holds "/Firmness station lane1" and its groups "Station
node", "Inputs", "Strikes" and "Hammer", each with the node's component tasks
(src/node/station.c) under it, every one with the node's hardware_id and not
STALE while it runs; the detector's and the node's keys (strikes, grades,
reconfigure, evaluate) in their own tasks. While the bag plays, the inputs
(force stream, audio stream, apple input: state, rate, stamps), the detector
and the node are OK."""

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
        lane = '/Firmness station lane1'
        groups = {'Station node': ['firmness station'],
                  'Inputs': ['force stream', 'audio stream', 'apple input'],
                  'Strikes': ['detector', 'attribution and clocks'],
                  'Hammer': ['hammer health', 'modulus factor']}
        healthy = ['firmness station', 'force stream', 'audio stream', 'apple input', 'detector']

        def task(name):
            """The aggregated status of the node's task name, or None."""
            for group, tasks in groups.items():
                if name in tasks:
                    for full, s in got.items():
                        if full.startswith('%s/%s/' % (lane, group)) and full.endswith(name):
                            return s
            return None

        def ready():
            if lane not in got or any(lane + '/' + g not in got for g in groups):
                return False
            if any(task(n) is None for ts in groups.values() for n in ts):
                return False
            strikes = {kv.key: kv.value for kv in task('detector').values}.get('strikes', '0')
            return int(strikes) > 0 and all(task(n).level == DiagnosticStatus.OK for n in healthy)

        end = time.time() + 60.0
        while time.time() < end and not rospy.is_shutdown():
            with lock:
                if ready():
                    break
            time.sleep(0.2)
        sub.unregister()
        with lock:
            self.assertIn(lane, got, sorted(got))
            for group, tasks in groups.items():
                self.assertIn(lane + '/' + group, got, sorted(got))
                for name in tasks:
                    s = task(name)
                    self.assertIsNotNone(s, '%s: %s' % (name, sorted(got)))
                    self.assertNotEqual(s.level, DiagnosticStatus.STALE, name)
                    self.assertEqual(s.hardware_id, '/lane1/firmness_node', name)
                    print('%s: level %d, %s' % (s.name, s.level, s.message))
            keys = {kv.key for kv in task('detector').values}
            for key in ('strikes', 'strikes per grade', 'strike detector'):
                self.assertIn(key, keys)
            keys = {kv.key for kv in task('firmness station').values}
            for key in ('reconfigure', 'evaluate calls', 'node starts'):
                self.assertIn(key, keys)
            keys = {kv.key for kv in task('force stream').values}
            for key in ('force rate [1/s]', 'force stamp delay [s]', 'force state'):
                self.assertIn(key, keys)
            for name in healthy:
                self.assertEqual(task(name).level, DiagnosticStatus.OK,
                                 '%s: %s' % (name, task(name).message))
            self.assertNotEqual(got[lane].level, DiagnosticStatus.STALE)


if __name__ == '__main__':
    rostest.rosrun('acoustic_firmness', 'aggregated_lane', AggregatorTest, sys.argv)
