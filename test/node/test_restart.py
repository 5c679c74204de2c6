#!/usr/bin/python3
"""rostest of a restart: a 24-strike bag (strike_bag, one strike
every 0.5 s, each apple's estimate 0.2 s before its strike) replayed at real
time on simulated time; after the 8th StrikeReport the node is killed
(SIGKILL, as a crash) and roslaunch respawns it (station.launch: respawn,
respawn_delay 1 s). Then:
 - every report, before and after, is for a true strike (contact start within
   1 ms) and names that strike's own apple, or none (apple_id 0, the reason
   saying so) when its estimate came while no node was up: never another
   apple's;
 - nothing from before the restart is reported by the new process: every
   report after the kill is for a strike after it;
 - the new process resumes: the strikes from 2 s after its subscriptions on
   are all reported, each against its own apple;
 - its /diagnostics say it restarted (node starts 2) and warn until its
   first strike."""

import csv
import os
import shutil
import signal
import subprocess
import tempfile
import threading
import time
import unittest
import xmlrpc.client

import rosgraph
import rospy
import rostest
from acoustic_firmness.msg import Reliability, StrikeReport
from diagnostic_msgs.msg import DiagnosticArray

import station_common as sc

STRIKES = 24
KILL_AFTER = 8


class RestartTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_restart')
        cls.tmp = tempfile.mkdtemp(prefix='af_restart_')
        bag = os.path.join(cls.tmp, 'restart.bag')
        subprocess.run([sc.find('strike_bag'), '--strikes', str(STRIKES), '--seed', '13', '--out', bag,
                        '--ns', rospy.get_namespace().strip('/')],
                       check=True, capture_output=True, text=True)
        with open(os.path.join(cls.tmp, 'restart.truth.csv')) as f:
            cls.truth = sorted((float(r['contact_start_s']), int(r['apple_id']))
                               for r in csv.DictReader(f))
        cls.lock = threading.Lock()
        cls.reports, cls.reasons, cls.diags = [], {}, []
        node = rospy.resolve_name(sc.NODE)
        rospy.Subscriber('strike_report', StrikeReport, cls._on_report, queue_size=1000)
        rospy.Subscriber('reliability', Reliability, cls._on_reliability, queue_size=1000)
        rospy.Subscriber('/diagnostics', DiagnosticArray,
                         lambda m: cls._on_diag(m, node), queue_size=100)
        cls.pid0 = cls._pid(node, None)
        env = dict(os.environ)
        env.pop('ROS_NAMESPACE', None)  # /clock, not /lane1/clock
        play = subprocess.Popen(['rosbag', 'play', '--clock', '-q', '--delay=1', '--wait-for-subscribers', bag],
                                stdout=subprocess.DEVNULL, env=env)
        end = time.time() + 60.0
        while time.time() < end:
            with cls.lock:
                if len(cls.reports) >= KILL_AFTER:
                    break
            time.sleep(0.01)
        os.kill(cls.pid0, signal.SIGKILL)
        cls.kill_stamp = rospy.get_time()  # the bag's clock at the kill
        with cls.lock:
            cls.n_before = len(cls.reports)
        cls.pid1 = cls._pid(node, cls.pid0)
        cls.up_stamp = rospy.get_time()  # the new process answers
        play.wait(timeout=60)
        time.sleep(3.0)
        with cls.lock:
            cls.final = list(cls.reports), dict(cls.reasons), list(cls.diags)
        shutil.rmtree(cls.tmp, ignore_errors=True)
        reports = cls.final[0]
        after = reports[cls.n_before:]
        print('restart: %d reports before the kill (bag time %.2f s), new process up at %.2f s; '
              '%d after it (%d without apple), %d of %d strikes not reported'
              % (cls.n_before, cls.kill_stamp - cls.truth[0][0], cls.up_stamp - cls.truth[0][0],
                 len(after), sum(1 for _, a, _ in after if a == 0),
                 STRIKES - len(reports), STRIKES))

    @classmethod
    def _pid(cls, node, other):
        master = rosgraph.Master('/test_restart')
        end = time.time() + 30.0
        while time.time() < end:
            try:
                _, _, pid = xmlrpc.client.ServerProxy(master.lookupNode(node)).getPid('/test_restart')
                if pid != other:
                    return pid
            except Exception:
                pass
            time.sleep(0.05)
        raise RuntimeError('%s did not come (back) up' % node)

    @classmethod
    def _on_report(cls, m):
        with cls.lock:
            cls.reports.append((m.header.stamp.to_sec(), m.apple_id, time.time()))

    @classmethod
    def _on_reliability(cls, m):
        if m.source == 'measured':
            with cls.lock:
                cls.reasons[round(m.header.stamp.to_sec(), 6)] = m.reason

    @classmethod
    def _on_diag(cls, m, node):
        # the restart is the node's own task's ("firmness station")
        s = sc.diag_tasks(m, node).get('firmness station')
        if s is not None:
            with cls.lock:
                cls.diags.append((s.level, s.message, sc.diag_values(m, node)))

    def truth_of(self, stamp):
        best = min(self.truth, key=lambda t: abs(t[0] - stamp))
        self.assertLess(abs(best[0] - stamp), 1e-3, 'a report at %.6f is no true strike' % stamp)
        return best[1]

    def test_01_every_report_names_its_own_apple_or_none(self):
        reports, reasons, _ = self.final
        for stamp, apple, _ in reports:
            true_apple = self.truth_of(stamp)
            if apple != true_apple:
                self.assertEqual(apple, 0, 'strike of apple %d judged against apple %d'
                                 % (true_apple, apple))
                self.assertIn('no apple', reasons.get(round(stamp, 6), ''))
        ids = [a for _, a, _ in reports if a != 0]
        self.assertEqual(len(ids), len(set(ids)), 'an apple reported twice: %s' % ids)

    def test_02_nothing_from_before_the_restart(self):
        reports, _, _ = self.final
        self.assertNotEqual(self.pid0, self.pid1)
        before = reports[:self.n_before]
        self.assertEqual([a for _, a, _ in before], list(range(1, self.n_before + 1)))
        after = reports[self.n_before:]
        self.assertGreater(len(after), 0, 'nothing reported after the restart')
        last_before = max(s for s, _, _ in before)
        for stamp, apple, _ in after:
            self.assertGreater(stamp, last_before, 'apple %d reported again' % apple)
            self.assertGreater(stamp, self.kill_stamp - 0.1,
                               'a strike from before the restart at %.3f' % stamp)

    def test_03_resumes_with_the_next_apples(self):
        reports, _, _ = self.final
        got = {round(s, 3): a for s, a, _ in reports}
        due = [(s, a) for s, a in self.truth if s > self.up_stamp + 2.0]
        self.assertGreater(len(due), 4, 'the bag ended too soon after the restart')
        for s, a in due:
            self.assertEqual(got.get(round(s, 3)), a, 'strike of apple %d at %.3f' % (a, s))

    def test_04_diagnostics_say_restarted(self):
        _, _, diags = self.final
        starts = [v.get('node starts', '') for _, _, v in diags]
        self.assertTrue(any(x.startswith('1 ') for x in starts), starts[:3])
        restarted = [(lvl, msg, v) for lvl, msg, v in diags if v.get('node starts', '').startswith('2 ')]
        self.assertTrue(restarted, 'no diagnostics from the restarted node: %s' % starts[-3:])
        self.assertIn('restarted', restarted[-1][2]['node starts'])
        # warned until its first strike, at least once
        self.assertTrue(any(lvl == 1 and 'restarted' in msg for lvl, msg, _ in restarted),
                        [m for _, m, _ in restarted][:5])


if __name__ == '__main__':
    rostest.rosrun(sc.PKG, 'restart', RestartTest)
