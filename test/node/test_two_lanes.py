#!/usr/bin/python3
"""rostest of two lanes under one master (two_lanes.launch): each lane's
robot_state_publisher prefixes its rig's frames (lane1/rig_base,
lane2/rig_base, ...), no frame is published twice on /tf_static, and each
lane's node answers an AppleEstimate in its own prefixed camera frame with a
known strike point (it finds its hammer's mount frame under its prefix),
while the unprefixed frame is unknown to both."""

import sys
import threading
import time
import unittest

import rospy
import rostest
from tf2_msgs.msg import TFMessage

import station_common as sc

LANES = ('lane1', 'lane2')
ALL = ('excitation_band', 'strike_advice', 'reliability')


class TwoLanesTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_two_lanes')
        cls.lock = threading.Lock()
        cls.static = []  # (parent, child) of every static transform received
        cls.sub = rospy.Subscriber('/tf_static', TFMessage, cls._on_static, queue_size=100)
        cls.stations = {lane: sc.Station('/' + lane) for lane in LANES}
        cls.connected = {lane: s.wait_connected(30.0) for lane, s in cls.stations.items()}

    @classmethod
    def _on_static(cls, msg):
        with cls.lock:
            cls.static.extend((t.header.frame_id, t.child_frame_id) for t in msg.transforms)

    def ask_when_known(self, lane, frame, apple_id, timeout_s=15.0):
        """Asks until the lane's node has the frame in its TF buffer."""
        end = time.time() + timeout_s
        while True:
            self.stations[lane].send(apple_id, frame=frame)
            got = self.stations[lane].wait(ALL, apple_id)
            text = got['strike_advice'][0].text if 'strike_advice' in got else ''
            if ('strike_advice' in got and 'strike point unknown' not in text) or time.time() > end:
                return got
            apple_id += 1000
            time.sleep(0.3)

    def test_01_both_lanes_up(self):
        self.assertEqual(self.connected, {lane: True for lane in LANES})

    def test_02_frames_unique_and_prefixed(self):
        end = time.time() + 15.0
        while time.time() < end:
            with self.lock:
                children = [c for _, c in self.static]
            if all(any(c.startswith(lane + '/') for c in children) for lane in LANES):
                break
            time.sleep(0.2)
        time.sleep(1.0)  # a late duplicate would come now
        with self.lock:
            pairs = list(self.static)
        children = [c for _, c in pairs]
        print('static frames: %s' % sorted(set(pairs)))
        dupes = sorted({c for c in children if children.count(c) > 1})
        self.assertEqual(dupes, [], 'frames published more than once on /tf_static')
        for parent, child in pairs:
            self.assertIn(child.split('/', 1)[0], LANES, 'unprefixed frame %s' % child)
            self.assertEqual(parent.split('/', 1)[0], child.split('/', 1)[0],
                             '%s -> %s crosses lanes' % (parent, child))
        for lane in LANES:
            self.assertIn(lane + '/rig_base', {p for p, _ in pairs})
            self.assertIn(lane + '/camera_optical_frame', children)

    def test_03_each_lane_answers_in_its_frames(self):
        for k, lane in enumerate(LANES):
            got = self.ask_when_known(lane, lane + '/camera_optical_frame', 100 + k)
            self.assertEqual(set(got), set(ALL), '%s answered on %s only' % (lane, list(got)))
            advice = got['strike_advice'][0]
            print('%s: %s' % (lane, advice.text))
            self.assertNotIn('unknown', advice.text)
            self.assertEqual(advice.header.frame_id, lane + '/camera_optical_frame')
            other = LANES[1 - k]
            self.assertNotIn(other, advice.text)

    def test_04_unprefixed_frame_unknown(self):
        self.stations['lane1'].send(300, frame='camera_optical_frame')
        got = self.stations['lane1'].wait(ALL, 300)
        self.assertIn("'camera_optical_frame' does not exist in TF", got['reliability'][0].reason)


if __name__ == '__main__':
    rostest.rosrun(sc.PKG, 'two_lanes', TwoLanesTest, sys.argv)
