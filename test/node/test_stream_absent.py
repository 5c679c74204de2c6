#!/usr/bin/python3
"""rostest of the stream-absent warning (src/core/lane/absent.h) on /diagnostics,
on the node's per-component tasks (src/node/station.c).

firmness_node runs with stream_absent_warn_s = 2 s (stream_absent.test) and,
at first, nothing publishes its force or audio. Its "force stream" and
"audio stream" tasks must go WARN with "no force and no audio chunk within
2.0 s of start" (each stream's state "no chunk yet"); while AppleEstimates
arrive both are an ERROR, "apples arriving, no strike can be measured: ..."
(every strike on them is lost), the "apple input" task OK, and WARN again
once they stop for 2 s. (The boundary itself, to the nanosecond, is
test/core/test_absent.c's: this test starts after the node.) Then a
publisher here sends the force in real time (SignalChunk, 1000 samples every
20 ms, seeded noise of 0.02 N): the force task goes OK "ok" (its rate, 50
chunks/s, within 50000 / 1024 Hz +- 10 % once the rate window holds only
streaming), the audio task still warns, naming the audio alone. Then the
audio too (960 samples every 20 ms at 48 kHz): every task of the node is OK,
each with the node's hardware_id, and "stream absent check" reads "ok"."""

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
        tasks = sc.diag_tasks(msg, cls.node)
        if tasks:
            with cls.lock:
                cls.statuses.append((rospy.get_time(), {
                    name: (s.level, s.message, {kv.key: kv.value for kv in s.values})
                    for name, s in tasks.items()}))

    def wait_status(self, task, level, message, timeout_s=30.0):
        """The first status (level, message) of task received from now on:
        (level, message, values), and every task of that report."""
        with self.lock:
            since = len(self.statuses)
        end = time.time() + timeout_s
        while time.time() < end and not rospy.is_shutdown():
            with self.lock:
                for _, tasks in self.statuses[since:]:
                    st = tasks.get(task)
                    if st and st[0] == level and st[1] == message:
                        return st, tasks
            time.sleep(0.1)
        with self.lock:
            last = [tasks.get(task, (None, None))[:2] for _, tasks in self.statuses[-5:]]
        self.fail('no status (%d, %r) of %r within %g s; the last: %r'
                  % (level, message, task, timeout_s, last))

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
        W, E, OK = DiagnosticStatus.WARN, DiagnosticStatus.ERROR, DiagnosticStatus.OK
        st, tasks = self.wait_status('force stream', W, BOTH)
        self.assertEqual(tasks['audio stream'][:2], (W, BOTH))
        self.assertEqual(st[2]['stream absent check'], BOTH)
        self.assertEqual(st[2]['force state'], 'no chunk yet')
        self.assertEqual(tasks['audio stream'][2]['audio state'], 'no chunk yet')
        self.assertEqual(sorted(tasks), sorted(sc.TASKS))
        print('both absent: %r' % {k: v[:2] for k, v in tasks.items()})

        # Apples arriving while both streams are absent: ERROR on both stream
        # tasks, every strike lost; back to WARN once they stop for
        # stream_absent_warn_s. The apples themselves are fine.
        feeder = self.apples(6.0)
        st, tasks = self.wait_status('force stream', E, ERROR)
        self.assertEqual(tasks['audio stream'][:2], (E, ERROR))
        self.assertEqual(tasks['apple input'][0], OK, tasks['apple input'][:2])
        self.assertEqual(tasks['detector'][0], OK, tasks['detector'][:2])
        print('apples arriving: %r' % {k: v[:2] for k, v in tasks.items()})
        feeder.join(10.0)
        st, tasks = self.wait_status('force stream', W, BOTH)
        print('apples stopped: level %d, %r' % st[:2])

        self.stream('force', float(sc.param('force_sample_rate_hz')), 'N', 1000)
        st, tasks = self.wait_status('force stream', OK, 'ok')
        self.assertEqual(st[2]['force state'], 'live')
        self.assertIn('(rate ok:', st[2]['force rate [1/s]'])
        self.assertEqual(tasks['audio stream'][:2], (W, AUDIO))
        self.assertEqual(tasks['audio stream'][2]['audio state'], 'no chunk yet')
        print('force streaming: force %r, audio %r; force rate %s, stamp delay %s'
              % (st[:2], tasks['audio stream'][:2], st[2]['force rate [1/s]'],
                 st[2]['force stamp delay [s]']))

        self.stream('audio', float(sc.param('audio_sample_rate_hz')), sc.param('audio_unit'), 960)
        st, tasks = self.wait_status('audio stream', OK, 'ok')
        self.assertEqual(st[2]['stream absent check'], 'ok')
        self.assertEqual(st[2]['audio state'], 'live')
        self.assertEqual(tasks['force stream'][:2], (OK, 'ok'))
        for name in sc.TASKS:
            self.assertEqual(tasks[name][0], OK, '%s: %r' % (name, tasks[name][:2]))
        print('both streaming: %r' % {k: v[:2] for k, v in tasks.items()})


if __name__ == '__main__':
    rostest.rosrun(sc.PKG, 'stream_absent', StreamAbsentTest, sys.argv)
