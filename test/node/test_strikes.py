#!/usr/bin/python3
"""rostest of the measured strikes: a 100-strike bag made at test time by
strike_bag (force at 50 kHz, audio at 48 kHz, an AppleEstimate 0.2 s before
each strike; truth CSV beside it) is replayed with `rosbag play --clock` on
simulated time, faster than real time, through firmness_node. Exactly one
StrikeReport and one measured Reliability per strike, none lost; apple ids,
contact start, 0S2 resonance (1 %) and contact time (1 %) against the truth;
no chunk lost on the way (/diagnostics). Then a strike on a restarted stream
with no apple in sight: apple_id 0, NaN for the model-dependent figures and
the reason. And two refusals of bad strike parameters at start-up."""

import csv
import json
import math
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import unittest

import rosparam
import rospkg
import rospy
import rostest
from acoustic_firmness.msg import Reliability, SignalChunk, StrikeReport
from diagnostic_msgs.msg import DiagnosticArray

import station_common as sc

STRIKES = 100
SEED = 7
# Playback speed: the node keeps up at several times real time (the bag's
# 51.5 s take ~10 s); chunks must never be dropped (checked below).
RATE = 5.0
RESONANCE_RTOL = 0.01
# The report's contact time is the fitted model's (measure.h): 0.3 % RMS at
# 40 dB, 1 % is about 3 standard errors.
CONTACT_TIME_RTOL = 0.01
# The detector places the contact start within a fraction of a sample
# (strike.h: 0.2 sample RMS at 40 dB); the stamp must say the same time.
START_TOL_S = 5.0 / 50000.0


class StrikesTest(unittest.TestCase):

    refusals = 0

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_strikes')
        cls.tmp = tempfile.mkdtemp(prefix='af_strikes_')
        cls.bag = os.path.join(cls.tmp, 'strikes.bag')
        out = subprocess.run([sc.find('strike_bag'), '--strikes', str(STRIKES), '--seed', str(SEED),
                              '--out', cls.bag, '--ns', rospy.get_namespace().strip('/')],
                             check=True, capture_output=True, text=True)
        print(out.stdout.strip())
        with open(os.path.join(cls.tmp, 'strikes.truth.csv')) as f:
            cls.truth = {int(r['apple_id']): r for r in csv.DictReader(f)}
        cls.lock = threading.Lock()
        cls.reports, cls.measured, cls.diag = [], [], {}
        cls.subs = [rospy.Subscriber('strike_report', StrikeReport, cls._on_report, queue_size=1000),
                    rospy.Subscriber('reliability', Reliability, cls._on_reliability, queue_size=1000),
                    rospy.Subscriber('/diagnostics', DiagnosticArray, cls._on_diag, queue_size=100)]
        end = time.time() + 30.0
        while time.time() < end and not all(s.get_num_connections() > 0 for s in cls.subs[:2]):
            time.sleep(0.1)
        cls.played = cls._play()

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    @classmethod
    def _on_report(cls, msg):
        with cls.lock:
            cls.reports.append(msg)

    @classmethod
    def _on_reliability(cls, msg):
        if msg.source == 'measured':
            with cls.lock:
                cls.measured.append(msg)

    @classmethod
    def _on_diag(cls, msg):
        values = sc.diag_values(msg, rospy.resolve_name(sc.NODE))
        if values:
            with cls.lock:
                cls.diag = values

    @classmethod
    def _play(cls):
        """Replays the bag; then waits for the last reports (wall clock: the
        simulated clock stops with the bag)."""
        started = time.time()
        # rosbag play advertises "clock" relative to its namespace: rostest's
        # ROS_NAMESPACE (our lane) would make it /lane1/clock, which no node
        # hears. The bag's own topics are absolute.
        env = dict(os.environ)
        env.pop('ROS_NAMESPACE', None)
        subprocess.run(['rosbag', 'play', '--clock', '-q', '--delay=1', '--wait-for-subscribers', '--rate=%g' % RATE, cls.bag],
                       check=True, stdout=subprocess.DEVNULL, env=env)
        end = time.time() + 10.0
        while time.time() < end:
            with cls.lock:
                if len(cls.reports) >= STRIKES and len(cls.measured) >= STRIKES:
                    break
            time.sleep(0.05)
        time.sleep(1.0)  # anything extra would come now
        print('replay of %d strikes at %gx took %.1f s' % (STRIKES, RATE, time.time() - started))
        with cls.lock:
            return list(cls.reports), list(cls.measured), dict(cls.diag)

    def test_01_one_report_and_one_measured_reliability_per_strike(self):
        reports, measured, _ = self.played
        self.assertEqual(len(reports), STRIKES, 'StrikeReports')
        self.assertEqual(len(measured), STRIKES, 'measured Reliability messages')
        self.assertEqual(sorted(r.apple_id for r in reports), list(range(1, STRIKES + 1)))
        by_id = {r.apple_id: r for r in reports}
        for rel in measured:
            self.assertIn(rel.apple_id, by_id)
            rep = by_id[rel.apple_id]
            self.assertEqual(rel.header.stamp, rep.header.stamp)
            self.assertEqual(rel.header.frame_id, rep.header.frame_id)
            # The heard 0S2 is the evidence: excites_mode is reported, not required.
            self.assertEqual(rel.reliable, rel.no_damage and rel.reason == '',
                             'apple %d: %s' % (rel.apple_id, rel.reason))

    def test_02_against_the_truth(self):
        reports, _, _ = self.played
        res_err, tc_err, start_err = [], [], []
        for r in reports:
            t = self.truth[r.apple_id]
            self.assertEqual(r.header.frame_id, 'force_transducer')
            start = r.header.stamp.to_sec()
            start_err.append(start - float(t['contact_start_s']))
            res_err.append(r.resonance / float(t['resonance_hz']) - 1.0)
            tc_err.append(r.contact_time / float(t['contact_time_s']) - 1.0)
            self.assertFalse(r.double_hit or r.clipped or r.lost_samples, 'apple %d' % r.apple_id)
            for name in ('stiffness_factor', 'modulus_from_resonance', 'fitted_modulus',
                         'fitted_restitution', 'fit_residual', 'band_high', 'snr_db'):
                self.assertTrue(math.isfinite(getattr(r, name)), '%s of apple %d' % (name, r.apple_id))
            self.assertLess(abs(r.fitted_modulus / float(t['modulus_pa']) - 1.0), 0.05,
                            'fitted E2 of apple %d' % r.apple_id)

        def summary(errs):
            return 'mean %+.3g, rms %.3g, max |.| %.3g' % (
                sum(errs) / len(errs), math.sqrt(sum(e * e for e in errs) / len(errs)),
                max(abs(e) for e in errs))
        print('resonance relative error: ' + summary(res_err))
        print('contact time relative error: ' + summary(tc_err))
        print('contact start error [s]: ' + summary(start_err))
        for r, e in zip(reports, res_err):
            self.assertLess(abs(e), RESONANCE_RTOL, 'resonance of apple %d: %.4f Hz, truth %s Hz'
                            % (r.apple_id, r.resonance, self.truth[r.apple_id]['resonance_hz']))
        for r, e in zip(reports, tc_err):
            self.assertLess(abs(e), CONTACT_TIME_RTOL, 'contact time of apple %d: %.6g s, truth %s s'
                            % (r.apple_id, r.contact_time, self.truth[r.apple_id]['contact_time_s']))
        for r, e in zip(reports, start_err):
            self.assertLess(abs(e), START_TOL_S, 'contact start of apple %d: %+.2e s off'
                            % (r.apple_id, e))

    def test_02b_grades(self):
        """Every reliable strike has the class of the cultivar's grade_classes that
        its stiffness factor falls in (the truth's too, away from a boundary);
        every other strike is "ungraded" with the measured reason."""
        reports, measured, diag = self.played
        spec = [s.strip() for s in sc.param('grade_classes').split('|')]
        names, bounds = spec[0::2], [float(b) for b in spec[1::2]]
        self.assertEqual(sc.param('grade_quantity'), 'stiffness_factor')
        rel = {m.apple_id: m for m in measured}
        seen = {}
        for r in reports:
            m = rel[r.apple_id]
            if not m.reliable:
                self.assertEqual((r.grade_index, r.grade), (0, 'ungraded'), 'apple %d' % r.apple_id)
                self.assertEqual(r.grade_reason, 'not reliable: ' + m.reason)
                continue
            k = sum(1 for b in bounds if r.stiffness_factor >= b)
            self.assertEqual((r.grade_index, r.grade, r.grade_reason), (k + 1, names[k], ''),
                             'apple %d, S %.4g' % (r.apple_id, r.stiffness_factor))
            t = self.truth[r.apple_id]
            s_true = float(t['resonance_hz']) ** 2 * float(t['mass_kg']) ** (2.0 / 3.0)
            if all(abs(s_true / b - 1.0) > 0.02 for b in bounds):  # 0S2 within 1 %
                self.assertEqual(r.grade_index, 1 + sum(1 for b in bounds if s_true >= b),
                                 'apple %d: truth S %.4g' % (r.apple_id, s_true))
            seen[r.grade] = seen.get(r.grade, 0) + 1
        print('grades: %s' % seen)
        self.assertGreaterEqual(len(seen), 3, 'the bag spans 2-12 MPa: several classes')
        # /diagnostics counts them per class (its last report may predate the last strikes:
        # the simulated clock stops with the bag).
        counts = [int(part.rsplit(' ', 1)[1]) for part in diag['strikes per grade'].split(', ')]
        self.assertEqual(len(counts), len(names) + 1, diag['strikes per grade'])
        self.assertLessEqual(sum(counts), len(reports))
        self.assertGreaterEqual(sum(counts), len(reports) - 5)

    def test_03_nothing_lost_on_the_way(self):
        _, _, diag = self.played
        self.assertTrue(diag, 'no diagnostics from the node')
        for key in ('force gaps', 'audio gaps'):
            self.assertEqual(diag.get(key), '0 (0 samples lost)', key)
        for key in ('strike queue overflows', 'strikes without audio', 'strikes without apple',
                    'strike force samples lost'):
            self.assertEqual(diag.get(key), '0', key)

    def test_03a_modulus_factor_learned(self):
        # strike_bag's true modulus factor is 1 (its default): the median of
        # E(0S2) / fitted E2 over the reliable strikes must find it within 2 %;
        # apply is off, so the cultivar's 1 stays applied and nothing changes.
        reports, rels, diag = self.played
        reliable = sum(1 for r in rels if r.reliable)
        learned = float(diag['modulus factor learned'])
        n = int(diag['modulus factor learned strikes'].split(' ', 1)[0])
        print('learned modulus factor %.4f from %d reliable strikes (%d reliable reports); '
              'interval %s' % (learned, n, reliable, diag['modulus factor learned 95% interval']))
        self.assertLessEqual(abs(learned - 1.0), 0.02)
        self.assertLessEqual(n, reliable)
        self.assertGreaterEqual(n, min(reliable, 200) - 5)  # the last report may lag
        low, high = (float(x) for x in
                     diag['modulus factor learned 95% interval'].strip('[]').split(', '))
        self.assertTrue(low <= learned <= high, diag['modulus factor learned 95% interval'])
        self.assertTrue(diag['modulus factor applied'].startswith('1.0000 '),
                        diag['modulus factor applied'])
        self.assertEqual(diag['modulus factor changes'], '0')

    def test_03b_offline_report_judges_alike(self):
        """The same bag through firmness_report --json (the core lane
        offline, no ROS master: the lab's desk tool): for every strike the
        StrikeReport and Reliability fields, under the report's names that
        the table of fields maps them to, with the same values (every figure
        the same double, the grade included), as the node published."""
        cfg = os.path.join(rospkg.RosPack().get_path(sc.PKG), 'config')
        out = subprocess.run([sc.find('firmness_report'), self.bag, '--json',
                              '--ns', rospy.get_namespace().strip('/'),
                              '--config', os.path.join(cfg, 'station.yaml'),
                              '--cultivar', os.path.join(cfg, 'jonagold.yaml')],
                             check=True, capture_output=True, text=True).stdout
        report = json.loads(out)
        offline = {o['stamp_ns']: o for o in report['strikes']}
        self.assertEqual(len(offline), STRIKES)
        self.assertEqual(report['summary']['strikes'], STRIKES)
        with self.lock:
            reports = {r.header.stamp.to_nsec(): r for r in self.reports}
            measured = {m.header.stamp.to_nsec(): m for m in self.measured}
        # Every field of both messages in the report's field that the serializer's table
        # maps to it (firmness_report --fields --json, scripts/node_vs_report.py): the
        # same double (the report's digits read back exactly), NaN as null.
        sys.path.insert(0, os.path.join(rospkg.RosPack().get_path(sc.PKG), 'scripts'))
        import node_vs_report
        fields = node_vs_report.load_fields(sc.find('firmness_report'))
        bad = node_vs_report.check_mapping(fields, {'StrikeReport': StrikeReport.__slots__,
                                                   'Reliability': Reliability.__slots__})
        self.assertEqual(bad, [], 'the table of fields against the messages')
        worst = 0.0
        for stamp, o in sorted(offline.items()):
            r, m = reports.get(stamp), measured.get(stamp)
            self.assertIsNotNone(r, 'no node report at %d' % stamp)
            self.assertIsNotNone(m, 'no node Reliability at %d' % stamp)
            worst = max(worst, node_vs_report.compare_strike(stamp, o, r, m, bad, fields))
        self.assertEqual(bad, [], 'node and firmness_report differ')
        print('firmness_report vs node: %d strikes, same verdicts and reasons, worst relative '
              'difference %.3g' % (len(offline), worst))

    def test_04_strike_without_apple(self):
        """A strike on a restarted stream, stamped far from any apple."""
        force = rospy.Publisher('force', SignalChunk, queue_size=100)
        audio = rospy.Publisher('audio', SignalChunk, queue_size=100)
        end = time.time() + 10.0
        while time.time() < end and (force.get_num_connections() == 0 or audio.get_num_connections() == 0):
            time.sleep(0.05)
        fs, fa = float(sc.param('force_sample_rate_hz')), float(sc.param('audio_sample_rate_hz'))
        t0 = 1800000000.0  # no AppleEstimate near it
        strike_s, tc_s, peak_n = 0.1, 1.5e-3, 30.0

        def chunks(rate, unit, n, value):
            out = []
            for first in range(0, n, 1024):
                c = SignalChunk()
                c.header.stamp = rospy.Time.from_sec(t0 + first / rate)
                c.header.frame_id = 'force_transducer' if unit == 'N' else 'microphone'
                c.first_sample, c.sample_rate, c.unit = first, rate, unit
                c.data = [value(k / rate) for k in range(first, first + 1024)]
                out.append(c)
            return out

        def pulse(t):  # a half-sine contact on a quiet, slightly noisy line
            noise = 0.002 * math.sin(2.0 * math.pi * 1234.5 * t)
            u = t - strike_s
            return noise + (peak_n * math.sin(math.pi * u / tc_s) if 0.0 < u < tc_s else 0.0)

        with self.lock:
            before = len(self.reports)
        # The audio first: the strike finds its window already in the ring.
        # (and past the audio lag's search, audio_lag_max_s after it)
        for c in chunks(fa, sc.param('audio_unit'), int(0.7 * fa), lambda t: 0.001 * math.sin(7000.0 * t)):
            audio.publish(c)
        # The force goes on past apple_wait_s after the strike: the strike
        # waits that long (in the stream's own time: the simulated clock
        # stopped with the bag) for an estimate of its own.
        for c in chunks(fs, 'N', int((strike_s + float(sc.param('apple_wait_s')) + 0.1) * fs), pulse):
            force.publish(c)
        end = time.time() + 5.0
        while time.time() < end:
            with self.lock:
                if len(self.reports) > before and len(self.measured) > before:
                    break
            time.sleep(0.05)
        with self.lock:
            reports, measured = self.reports[before:], self.measured[before:]
        self.assertEqual(len(reports), 1)
        self.assertEqual(len(measured), 1)
        r, rel = reports[0], measured[0]
        self.assertEqual(r.apple_id, 0)
        self.assertAlmostEqual(r.header.stamp.to_sec(), t0 + strike_s, delta=START_TOL_S)
        self.assertAlmostEqual(r.contact_time, tc_s, delta=0.05 * tc_s)
        self.assertAlmostEqual(r.peak_force, peak_n, delta=0.02 * peak_n)
        for name in ('resonance', 'resonance_q', 'snr_db', 'stiffness_factor',
                     'modulus_from_resonance', 'fitted_modulus', 'fitted_restitution', 'fit_residual'):
            self.assertTrue(math.isnan(getattr(r, name)), name)
        self.assertTrue(math.isfinite(r.band_high), 'the band needs no apple')
        self.assertEqual(rel.apple_id, 0)
        self.assertFalse(rel.reliable)
        self.assertIn('no apple estimate stamped %g +- %g s before the strike'
                      % (float(sc.param('apple_transit_s')),
                         float(sc.param('apple_transit_tolerance_s'))), rel.reason)

    def _refused(self, changes, *words):
        pkg = rospkg.RosPack().get_path(sc.PKG)
        params = {}
        for name in ('station.yaml', 'jonagold.yaml'):
            for p, _ in rosparam.load_file(os.path.join(pkg, 'config', name)):
                params.update(p)
        for key, value in changes.items():
            if value is None:
                del params[key]
            else:
                params[key] = value
        StrikesTest.refusals += 1
        ns = '/strikes_refusal%d' % StrikesTest.refusals
        rosparam.upload_params(ns + '/' + sc.NODE, params)
        rospy.set_param(ns + '/robot_description',
                        open(os.path.join(pkg, 'config', 'rig.urdf')).read())
        proc = subprocess.Popen([sc.find(sc.NODE), '__ns:=' + ns, '__name:=' + sc.NODE],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            _, err = proc.communicate(timeout=20.0)
        except subprocess.TimeoutExpired:
            proc.send_signal(signal.SIGINT)
            proc.communicate()
            self.fail('firmness_node kept running with %s' % changes)
        self.assertNotEqual(proc.returncode, 0)
        for word in words:
            self.assertIn(word, err)

    def test_05_bad_strike_parameters_refused(self):
        self._refused({'strike_post_s': 0.003}, '~strike_post_s = 0.003', 'strike_double_hit_gap_s')
        self._refused({'measure_audio_window_s': None}, '~measure_audio_window_s is missing')
        self._refused({'strike_pending_size': 2.5}, '~strike_pending_size', 'whole number')


if __name__ == '__main__':
    rostest.rosrun(sc.PKG, 'strikes', StrikesTest, sys.argv)
