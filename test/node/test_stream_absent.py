#!/usr/bin/python3
"""rostest of the stream-absent warning (src/core/lane/absent.h) on /diagnostics.

firmness_node runs with stream_absent_warn_s = 2 s (stream_absent.test) and,
at first, nothing publishes its force or audio. Its diagnostic must go WARN
with "no force and no audio chunk within 2.0 s of start" (the two streams'
state "no chunk yet"); while AppleEstimates arrive it is an ERROR, "apples
arriving, no strike can be measured: ..." (every strike on them is lost), and
WARN again once they stop for 2 s. (The boundary itself, to the nanosecond, is
test/core/test_absent.c's: this test starts after the node.) Then a publisher here sends the force in real
time (SignalChunk, 1000 samples every 20 ms, seeded noise of 0.02 N): the
warning names the audio alone. Then the audio too (960 samples every 20 ms at
48 kHz): the status is OK, "ok", and "stream absent check" reads "ok"."""

import random
import sys
import threading
import time
import unittest

import rospy
import rostest
from acoustic_firmness.msg import SignalChunk
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus

import station_common as sc

BOTH = 'no force and no audio chunk within 2.0 s of start'
AUDIO = 'no audio chunk within 2.0 s of start'
ERROR = 'apples arriving, no strike can be measured: ' + BOTH


class StreamAbsentTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_stream_absent')
        cls.node = rospy.resolve_name(sc.NODE)
        cls.lock = threading.Lock()
        cls.statuses = []  # (receive ROS time [s], level, message, values)
        cls.sub = rospy.Subscriber('/diagnostics', DiagnosticArray, cls._on_diag, queue_size=50)
        cls.stop = threading.Event()
        cls.streams = []

    @classmethod
    def tearDownClass(cls):
        cls.stop.set()
        for t in cls.streams:
            t.join(5.0)

    @classmethod
    def _on_diag(cls, msg):
        for s in msg.status:
            if s.hardware_id == cls.node:
                with cls.lock:
                    cls.statuses.append((rospy.get_time(), s.level, s.message,
                                         {kv.key: kv.value for kv in s.values}))

    def wait_status(self, level, message, timeout_s=20.0):
        """The first status (level, message) received from now on."""
        with self.lock:
            since = len(self.statuses)
        end = time.time() + timeout_s
        while time.time() < end and not rospy.is_shutdown():
            with self.lock:
                for st in self.statuses[since:]:
                    if st[1] == level and st[2] == message:
                        return st
            time.sleep(0.1)
        with self.lock:
            last = [(lvl, msg) for _, lvl, msg, _ in self.statuses[-5:]]
        self.fail('no status (%d, %r) within %g s; the last: %r' % (level, message, timeout_s, last))

    def stream(self, topic, rate_hz, unit, n):
        """Publishes topic in real time, n samples a chunk, until the test ends."""
        pub = rospy.Publisher(topic, SignalChunk, queue_size=100)
        rng = random.Random(7)

        def run():
            first, t0 = 0, None
            while not self.stop.is_set() and not rospy.is_shutdown():
                now = rospy.Time.now()
                if t0 is None:
                    t0 = now
                c = SignalChunk()
                c.header.stamp = t0 + rospy.Duration.from_sec(first / rate_hz)
                c.header.frame_id = topic
                c.first_sample, c.sample_rate, c.unit = first, rate_hz, unit
                c.data = [rng.gauss(0.0, 0.02) for _ in range(n)]
                pub.publish(c)
                first += n
                # the next chunk when its samples are due
                due = t0.to_sec() + first / rate_hz
                time.sleep(max(0.0, due - rospy.Time.now().to_sec()))
        t = threading.Thread(target=run, daemon=True)
        t.start()
        self.streams.append(t)

    def apples(self, seconds):
        """AppleEstimates every 0.3 s for seconds, in a thread of their own."""
        station = sc.Station()

        def run():
            end, k = time.time() + seconds, 1
            while time.time() < end and not rospy.is_shutdown():
                station.send(k, stamp=rospy.Time.now())
                k += 1
                time.sleep(0.3)
        t = threading.Thread(target=run, daemon=True)
        t.start()
        return t

    def test_1_both_absent_then_audio_then_ok(self):
        st = self.wait_status(DiagnosticStatus.WARN, BOTH)
        self.assertEqual(st[3]['stream absent check'], BOTH)
        self.assertEqual(st[3]['force state'], 'no chunk yet')
        self.assertEqual(st[3]['audio state'], 'no chunk yet')
        print('both absent: level %d, %r' % (st[1], st[2]))

        # Apples arriving while both streams are absent: ERROR, every strike lost;
        # back to WARN once they stop for stream_absent_warn_s.
        feeder = self.apples(6.0)
        st = self.wait_status(DiagnosticStatus.ERROR, ERROR)
        print('apples arriving: level %d, %r' % (st[1], st[2]))
        feeder.join(10.0)
        st = self.wait_status(DiagnosticStatus.WARN, BOTH)
        print('apples stopped: level %d, %r' % (st[1], st[2]))

        self.stream('force', float(sc.param('force_sample_rate_hz')), 'N', 1000)
        st = self.wait_status(DiagnosticStatus.WARN, AUDIO)
        self.assertEqual(st[3]['force state'], 'live')
        self.assertEqual(st[3]['audio state'], 'no chunk yet')
        print('force streaming: level %d, %r' % (st[1], st[2]))

        self.stream('audio', float(sc.param('audio_sample_rate_hz')), sc.param('audio_unit'), 960)
        st = self.wait_status(DiagnosticStatus.OK, 'ok')
        self.assertEqual(st[3]['stream absent check'], 'ok')
        self.assertEqual((st[3]['force state'], st[3]['audio state']), ('live', 'live'))
        print('both streaming: level %d, %r' % (st[1], st[2]))


if __name__ == '__main__':
    rostest.rosrun(sc.PKG, 'stream_absent', StreamAbsentTest, sys.argv)
