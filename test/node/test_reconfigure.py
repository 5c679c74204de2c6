#!/usr/bin/python3
"""rostest of firmness_node's dynamic_reconfigure server.

The description (acoustic_firmness/cfg/StationConfig, generated at build time
from the parameter table by src/cfg/reconfigure_cfg.c) is read back and every
parameter's type, default, minimum, maximum and choices compared with the
table's row as src/core/params/settings_table.c writes it (parsed here from the source),
so the two cannot drift. Then, on the running node: a lobe change reaches the
next apple's ExcitationBand (equal to firmness_model --lobe 2) and ~evaluate;
a modulus outside [modulus_min_pa, modulus_max_pa] is refused by the same
cross-check as at start-up (the old value stays, the reason is in
/diagnostics); a value beyond the table's range is refused with the
table's range (not clamped: the node's server sees the request as sent);
grade classes change, and a malformed spec is refused naming its token. The
exact request counts are test_reconfigure_refusals.py's."""

import math
import os
import re
import sys
import threading
import time
import unittest

import dynamic_reconfigure.client
import rospy
import rostest
from acoustic_firmness.cfg import StationConfig
from acoustic_firmness.srv import Evaluate, EvaluateRequest
from diagnostic_msgs.msg import DiagnosticArray
from std_msgs.msg import String

import station_common as sc

HERE = os.path.dirname(os.path.abspath(__file__))
SETTINGS_C = os.path.join(HERE, '..', '..', 'src', 'core', 'params', 'settings_table.c')


def table():
    """name -> (kind, default, range or choices) from the table's source."""
    text = open(SETTINGS_C).read()
    rows = {}
    for m in re.finditer(r'\b(NUM|WHOLE|CHOICE|STRING|BOOLEAN)\(\s*"(\w+)",\s*"((?:[^"\\]|\\.)*)",\s*'
                         r'(?:"((?:[^"\\]|\\.)*)"|(\d+))?', text):
        kind, name, default, third = m.group(1), m.group(2), m.group(3), m.group(4)
        rows[name] = (kind, default.replace('\\"', '"'), third)
    return rows


def interval(text):
    m = re.match(r'(?:0 or )?[\[(]([^,]+), ([^\])]+)[\])]', text)
    return float(m.group(1)), float(m.group(2))


class ReconfigureTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_reconfigure')
        cls.node = rospy.resolve_name(sc.NODE)
        cls.station = sc.Station()
        cls.station.wait_connected()
        cls.client = dynamic_reconfigure.client.Client(cls.node, timeout=30)
        rospy.wait_for_service(cls.node + '/evaluate', timeout=30)
        cls.evaluate = rospy.ServiceProxy(cls.node + '/evaluate', Evaluate)
        cls.rig = sc.rig_from_parameter()
        cls.lock = threading.Lock()
        cls.diag = {}
        cls.sub = rospy.Subscriber('/diagnostics', DiagnosticArray, cls._on_diag, queue_size=10)
        cls.next_id = 500

    @classmethod
    def _on_diag(cls, msg):
        values = sc.diag_values(msg, cls.node)
        if values:
            with cls.lock:
                cls.diag = values

    def diag_value(self, key, contains, timeout_s=5.0):
        end = time.time() + timeout_s
        while time.time() < end:
            with self.lock:
                value = self.diag.get(key, '')
            if contains in value:
                return value
            time.sleep(0.1)
        self.fail('/diagnostics %s: %r, expected to contain %r' % (key, value, contains))

    def band(self, **apple):
        ReconfigureTest.next_id += 1
        self.station.send(self.next_id, **apple)
        got = self.station.wait(('excitation_band',), self.next_id)
        return got['excitation_band'][0]

    def test_00_description_is_the_tables(self):
        rows = table()
        params = StationConfig.config_description['groups']
        found = {}

        def walk(group):
            for p in group['parameters']:
                found[p['name']] = p
            for g in group['groups']:
                walk(g)
        walk(StationConfig.config_description)
        self.assertEqual(len(found), 16)
        for name, p in found.items():
            kind, default, third = rows[name]
            if kind in ('NUM', 'WHOLE'):
                lo, hi = interval(third)
                self.assertEqual(p['type'], 'double' if kind == 'NUM' else 'int', name)
                self.assertEqual(float(p['default']), float(default), name)
                self.assertEqual((float(p['min']), float(p['max'])), (lo, hi), name)
            elif kind == 'CHOICE':
                self.assertEqual(p['type'], 'str', name)
                self.assertEqual(p['default'], default, name)
                words = [c['value'] for c in eval(p['edit_method'])['enum']]
                self.assertEqual(words, [w.strip() for w in third.split(',')], name)
            else:
                self.assertEqual(p['type'], 'str', name)
                self.assertEqual(p['default'], default.strip('"'), name)
            # The node started with the shipped YAML, which equals the table's defaults.
            self.assertEqual(self.client.get_configuration(timeout=10)[name], p['default'], name)
        del params

    def test_01_lobe_reaches_the_prediction_and_evaluate(self):
        self.assertEqual(self.band(strike_radius=0.040).lobe, 1)
        cfg = self.client.update_configuration({'lobe': 2})
        self.assertEqual(cfg['lobe'], 2)
        b = self.band(mass=0.160, strike_radius=0.045)
        ref = sc.firmness_model(**dict(sc.model_flags(0.160, 0.045, self.rig.hammer()), lobe=2))
        self.assertEqual(b.lobe, 2)
        self.assertTrue(math.isclose(b.band_low, ref['band_low_hz'], rel_tol=1e-8))
        self.assertTrue(math.isclose(b.band_high, ref['band_high_hz'], rel_tol=1e-8))
        self.assertEqual(self.evaluate(EvaluateRequest(mass=0.160, strike_radius=0.045)).lobe, 2)
        self.diag_value('reconfigure last change', '~lobe = 2')
        self.client.update_configuration({'lobe': 1})
        self.assertEqual(self.band(strike_radius=0.040).lobe, 1)

    def test_02_cross_check_refuses_as_at_startup(self):
        cfg = self.client.update_configuration({'modulus_nominal_pa': 1.5e7})
        self.assertEqual(cfg['modulus_nominal_pa'], 8.0e6)
        self.diag_value('reconfigure last refusal',
                        '~modulus_nominal_pa = 1.5e+07 must lie in [~modulus_min_pa, '
                        '~modulus_max_pa] = [2e+06, 1.2e+07] Pa')
        self.assertEqual(self.evaluate(EvaluateRequest(mass=0.175, strike_radius=0.04)).modulus, 8.0e6)
        # Within the range: taken, and ~evaluate runs with it.
        cfg = self.client.update_configuration({'modulus_nominal_pa': 6.0e6, 'strike_velocity_m_s': 1.1})
        self.assertEqual((cfg['modulus_nominal_pa'], cfg['strike_velocity_m_s']), (6.0e6, 1.1))
        ans = self.evaluate(EvaluateRequest(mass=0.175, strike_radius=0.04))
        ref = sc.firmness_model(**dict(sc.model_flags(0.175, 0.04, self.rig.hammer()), E2=6.0e6, v0=1.1))
        self.assertTrue(math.isclose(ans.contact_time, ref['contact_time_s'], rel_tol=1e-8))
        self.client.update_configuration({'modulus_nominal_pa': 8.0e6, 'strike_velocity_m_s': 1.4})

    def test_03_beyond_the_tables_range_is_refused(self):
        cfg = self.client.update_configuration({'measure_snr_threshold_db': 500.0})
        self.assertEqual(cfg['measure_snr_threshold_db'], 15.0)  # unchanged, not clamped to 100
        self.diag_value('reconfigure last refusal',
                        '~measure_snr_threshold_db = 500 is outside the accepted range '
                        '[-100, 100] dB')
        cfg = self.client.update_configuration({'measure_snr_threshold_db': 12.0})
        self.assertEqual(cfg['measure_snr_threshold_db'], 12.0)
        cfg = self.client.update_configuration({'measure_snr_threshold_db': 15.0})
        self.assertEqual(cfg['measure_snr_threshold_db'], 15.0)

    def test_04_grades(self):
        cfg = self.client.update_configuration({'grade_classes': 'a | 1.0e+5 | b'})
        self.assertEqual(cfg['grade_classes'], 'a | 1.0e+5 | b')
        self.diag_value('grade classes', 'a < 100000 <= b (stiffness_factor')
        cfg = self.client.update_configuration({'grade_classes': 'a | x | b'})
        self.assertEqual(cfg['grade_classes'], 'a | 1.0e+5 | b')
        self.diag_value('reconfigure last refusal',
                        "~grade_classes: boundary 'x' after class 'a' is not a number")
        cfg = self.client.update_configuration({'grade_quantity': 'fitted_modulus',
                                                'grade_classes': 'soft | 5.0e+6 | firm'})
        self.diag_value('grade classes', 'soft < 5e+06 <= firm (fitted_modulus, Pa)')

    def test_05_settings_snapshot_follows(self):
        """NS/settings (latched): one `name: value` line per row, each the
        node's parameter; after an accepted change, the new value; and
        NS/robot_description the URDF the node read (the parameter)."""
        def snapshot(want=None, timeout_s=10.0):
            end = time.time() + timeout_s
            while time.time() < end:
                msg = rospy.wait_for_message('settings', String, timeout=timeout_s)
                rows = dict(line.split(': ', 1) for line in msg.data.splitlines())
                if want is None or all(rows.get(k) == v for k, v in want.items()):
                    return rows
                time.sleep(0.1)
            self.fail('settings never showed %s: %s' % (want, rows))
        rows = snapshot()
        names = set(re.findall(r'\b(?:NUM|WHOLE|CHOICE|STRING|BOOLEAN|OPTIONAL_NUM)\(\s*"(\w+)"',
                               open(SETTINGS_C).read()))
        self.assertTrue(set(rows) <= names, set(rows) - names)
        self.assertGreater(len(rows), len(names) // 2)
        for name in ('modulus_factor', 'strike_velocity_m_s', 'measure_snr_threshold_db', 'lobe'):
            self.assertEqual(float(rows[name]), float(rospy.get_param(self.node + '/' + name)), name)
        self.client.update_configuration({'measure_snr_threshold_db': 13.5})
        snapshot({'measure_snr_threshold_db': '13.5'})
        self.client.update_configuration({'measure_snr_threshold_db': 15.0})
        snapshot({'measure_snr_threshold_db': '15'})
        urdf = rospy.wait_for_message('robot_description', String, timeout=10.0).data
        self.assertEqual(urdf, rospy.get_param(rospy.resolve_name('robot_description')))


if __name__ == '__main__':
    rostest.rosrun(sc.PKG, 'reconfigure', ReconfigureTest, sys.argv)
