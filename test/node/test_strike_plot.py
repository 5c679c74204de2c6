#!/usr/bin/python3
"""rostest of ~strike_plot, the operators' live picture of the last strike: a
10-strike bag (strike_bag, seed 3) replayed with `rosbag play --clock` at 2x
through firmness_node. One sensor_msgs/Image per strike, rgb8 of
~strike_plot_width_px x ~strike_plot_height_px with step = 3 x width, header
= its StrikeReport's (contact start, force frame); each picture not blank
(the white page has the pulse's blue points and the audio spectrum's green
curve on it); the render time in /diagnostics. The first picture is written
to $AF_STRIKE_PLOT_PNG_DIR (when set, as PPM) to look at."""

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
from diagnostic_msgs.msg import DiagnosticArray
from sensor_msgs.msg import Image

import station_common as sc

STRIKES = 10
SEED = 3
RATE = 2.0


def near(pixel, colour, tol=60):
    return all(abs(a - b) < tol for a, b in zip(pixel, colour))


class StrikePlotTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_strike_plot')
        cls.tmp = tempfile.mkdtemp(prefix='af_strike_plot_')
        cls.bag = os.path.join(cls.tmp, 'strikes.bag')
        subprocess.run([sc.find('strike_bag'), '--strikes', str(STRIKES), '--seed', str(SEED),
                        '--out', cls.bag, '--ns', rospy.get_namespace().strip('/')],
                       check=True, capture_output=True, text=True)
        cls.lock = threading.Lock()
        cls.images, cls.reports, cls.diag = [], [], {}
        cls.subs = [rospy.Subscriber('strike_plot', Image, cls._on_image, queue_size=100),
                    rospy.Subscriber('strike_report', StrikeReport, cls._on_report,
                                     queue_size=100),
                    rospy.Subscriber('/diagnostics', DiagnosticArray, cls._on_diag,
                                     queue_size=100)]
        end = time.time() + 30.0
        while time.time() < end and not all(s.get_num_connections() > 0 for s in cls.subs[:2]):
            time.sleep(0.1)
        env = dict(os.environ)
        env.pop('ROS_NAMESPACE', None)  # /clock, not /lane1/clock
        subprocess.run(['rosbag', 'play', '--clock', '-q', '--delay=1', '--wait-for-subscribers', '--rate=%g' % RATE,
                        cls.bag], check=True, stdout=subprocess.DEVNULL, env=env)
        end = time.time() + 10.0
        while time.time() < end:
            with cls.lock:
                if len(cls.images) >= STRIKES and len(cls.reports) >= STRIKES:
                    break
            time.sleep(0.05)
        time.sleep(2.0)  # anything extra, and a diagnostic report, would come now

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    @classmethod
    def _on_image(cls, msg):
        with cls.lock:
            cls.images.append(msg)

    @classmethod
    def _on_report(cls, msg):
        with cls.lock:
            cls.reports.append(msg)

    @classmethod
    def _on_diag(cls, msg):
        values = sc.diag_values(msg, rospy.resolve_name(sc.NODE))
        if values:
            with cls.lock:
                cls.diag = values

    def test_01_one_image_per_strike(self):
        with self.lock:
            images, reports = list(self.images), list(self.reports)
        self.assertEqual(len(reports), STRIKES, 'StrikeReports')
        self.assertEqual(len(images), STRIKES, 'strike_plot images')
        self.assertEqual([i.header.stamp for i in images], [r.header.stamp for r in reports])
        for i, r in zip(images, reports):
            self.assertEqual(i.header.frame_id, r.header.frame_id)

    def test_02_size_and_encoding(self):
        w, h = int(sc.param('strike_plot_width_px')), int(sc.param('strike_plot_height_px'))
        with self.lock:
            images = list(self.images)
        self.assertTrue(images)
        for i in images:
            self.assertEqual((i.width, i.height, i.encoding, i.step), (w, h, 'rgb8', 3 * w))
            self.assertEqual(len(i.data), i.step * i.height)
            self.assertEqual(i.is_bigendian, 0)

    def test_03_not_blank(self):
        with self.lock:
            images = list(self.images)
        self.assertTrue(images)
        out = os.environ.get('AF_STRIKE_PLOT_PNG_DIR')
        for k, i in enumerate(images):
            d = i.data
            pixels = list(zip(d[0::3], d[1::3], d[2::3]))
            drawn = sum(1 for p in pixels if min(p) < 250)
            blue = sum(1 for p in pixels if near(p, (31, 119, 180)))
            green = sum(1 for p in pixels if near(p, (44, 160, 44)))
            self.assertGreater(drawn, len(pixels) // 50, 'image %d: %d pixels drawn' % (k, drawn))
            self.assertGreater(blue, 100, 'image %d: the pulse (blue)' % k)
            self.assertGreater(green, 100, 'image %d: the audio spectrum (green)' % k)
            if out and k == 0:
                with open(os.path.join(out, 'strike_plot.ppm'), 'wb') as f:
                    f.write(b'P6\n%d %d\n255\n' % (i.width, i.height) + bytes(d))

    def test_04_render_time_in_diagnostics(self):
        with self.lock:
            diag = dict(self.diag)
        self.assertTrue(diag, 'no diagnostics from the node')
        self.assertIn('strike plot render [ms]', diag)
        self.assertTrue(diag['strike plot images'].startswith('%d published of %d strikes'
                                                              % (STRIKES, STRIKES)),
                        diag['strike plot images'])
        print('strike plot: %s; render %s' % (diag['strike plot images'],
                                              diag['strike plot render [ms]']))


if __name__ == '__main__':
    rostest.rosrun(sc.PKG, 'strike_plot', StrikePlotTest)
