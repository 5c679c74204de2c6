#!/usr/bin/python3
"""rostest: dynamic_reconfigure requests outside the parameter table's range.

Six requests through dynamic_reconfigure's own Python client (as rqt and
dynparam send them) to a fresh node: lobe 2 (taken), lobe 99 (outside [1, 8]),
measure_snr_threshold_db 500 (outside [-100, 100] dB), measure_snr_threshold_db
12 (taken), strike_velocity_m_s 20 (outside [0.05, 10] m/s), lobe 1 (taken).
Each refusal must: answer with the values still in force (not the table's end:
dynamic_reconfigure's own server would clamp 99 to 8 and 500 to 100), leave
the parameter server's value as it was, give one WARN line on /rosout naming
the parameter, value and range (on /rosout), and show the same line in /diagnostics as
"reconfigure last refusal". At the end /diagnostics reads "6 requests: 3
accepted, 3 refused" (the server's start is not a request)."""

import sys
import threading
import time
import unittest

import dynamic_reconfigure.client
import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray
from rosgraph_msgs.msg import Log

import station_common as sc

REQUESTS = [
    ({'lobe': 2}, None),
    ({'lobe': 99}, '~lobe = 99 is outside the accepted range [1, 8]'),
    ({'measure_snr_threshold_db': 500.0},
     '~measure_snr_threshold_db = 500 is outside the accepted range [-100, 100] dB'),
    ({'measure_snr_threshold_db': 12.0}, None),
    ({'strike_velocity_m_s': 20.0},
     '~strike_velocity_m_s = 20 is outside the accepted range [0.05, 10] m/s'),
    ({'lobe': 1}, None),
]


class RefusalTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_reconfigure_refusals')
        cls.node = rospy.resolve_name(sc.NODE)
        cls.lock = threading.Lock()
        cls.diag = {}
        cls.logs = []
        cls.subs = [rospy.Subscriber('/diagnostics', DiagnosticArray, cls._on_diag, queue_size=10),
                    rospy.Subscriber('/rosout', Log, cls._on_log, queue_size=100)]
        cls.client = dynamic_reconfigure.client.Client(cls.node, timeout=30)

    @classmethod
    def _on_diag(cls, msg):
        values = sc.diag_values(msg, cls.node)
        if values:
            with cls.lock:
                cls.diag = values

    @classmethod
    def _on_log(cls, msg):
        if msg.name == cls.node:
            with cls.lock:
                cls.logs.append((msg.level, msg.msg))

    def diag_value(self, key, want, timeout_s=5.0):
        end = time.time() + timeout_s
        value = ''
        while time.time() < end:
            with self.lock:
                value = self.diag.get(key, '')
            if value == want:
                return value
            time.sleep(0.1)
        self.fail('/diagnostics %s: %r, expected %r' % (key, value, want))

    def wait_log(self, text, timeout_s=5.0):
        end = time.time() + timeout_s
        while time.time() < end:
            with self.lock:
                for level, msg in self.logs:
                    if msg == text:
                        return level
            time.sleep(0.1)
        with self.lock:
            self.fail('no log line %r; got %r' % (text, [m for _, m in self.logs][-5:]))

    def test_six_requests(self):
        in_force = self.client.get_configuration(timeout=10)
        self.assertEqual((in_force['lobe'], in_force['measure_snr_threshold_db'],
                          in_force['strike_velocity_m_s']), (1, 15.0, 1.4))
        for values, refusal in REQUESTS:
            answer = self.client.update_configuration(values)
            name, value = next(iter(values.items()))
            if refusal is None:
                in_force[name] = value
                self.assertEqual(answer[name], value, name)
            else:
                # the old value, in the answer and on the parameter server
                self.assertEqual(answer[name], in_force[name], '%s = %r' % (name, value))
                self.assertEqual(rospy.get_param(self.node + '/' + name), in_force[name], name)
                self.assertEqual(self.wait_log('reconfigure refused: ' + refusal), Log.WARN)
                self.diag_value('reconfigure last refusal', refusal)
                print('refused: %s' % refusal)
            for key in ('lobe', 'measure_snr_threshold_db', 'strike_velocity_m_s'):
                self.assertEqual(answer[key], in_force[key], key)
        # The values in force at the end, on the parameter server.
        for key in ('lobe', 'measure_snr_threshold_db', 'strike_velocity_m_s'):
            self.assertEqual(rospy.get_param(self.node + '/' + key), in_force[key], key)
        self.assertEqual((in_force['lobe'], in_force['measure_snr_threshold_db']), (1, 12.0))
        print(self.diag_value('reconfigure', '6 requests: 3 accepted, 3 refused'))


if __name__ == '__main__':
    rostest.rosrun(sc.PKG, 'reconfigure_refusals', RefusalTest, sys.argv)
