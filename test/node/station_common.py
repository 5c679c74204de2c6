"""Helpers of the node's rostests: drive firmness_node with AppleEstimates,
collect its answers, and compute the expected values independently of the
node: the model through the firmness_model CLI, the strike direction from
the rig's URDF by a small forward-kinematics of its fixed joints."""

import csv
import io
import json
import math
import os
import subprocess
import threading
import time
import xml.etree.ElementTree as ET

import rosgraph
import rospy
import roslib.packages
from acoustic_firmness.msg import (AppleEstimate, ExcitationBand, Reliability,
                                   StrikeAdvice)
from rosgraph_msgs.msg import Clock
from visualization_msgs.msg import MarkerArray

PKG = 'acoustic_firmness'
NODE = 'firmness_node'
# Every answer must arrive within this long after the AppleEstimate [s].
ANSWER_TIMEOUT_S = 1.0


# The node's diagnostic tasks (src/node/station.c), each its own status named
# "<node>: <task>" with the node's hardware_id, all in one /diagnostics array.
TASKS = ('firmness station', 'force stream', 'audio stream', 'apple input', 'detector',
         'attribution and clocks', 'hammer health', 'modulus factor')


def diag_tasks(msg, node):
    """{task: DiagnosticStatus} of node (its resolved name = its hardware_id)
    in one /diagnostics array."""
    return {s.name.split(': ', 1)[-1]: s for s in msg.status if s.hardware_id == node}


def diag_values(msg, node):
    """Every {key: value} of node's tasks in one /diagnostics array, merged
    (a key names one figure, whichever task carries it); {} when none."""
    values = {}
    for s in diag_tasks(msg, node).values():
        values.update({kv.key: kv.value for kv in s.values})
    return values


def param(name):
    """A private parameter of the node under test (lane namespace = ours)."""
    return rospy.get_param(rospy.resolve_name(NODE) + '/' + name)


def firmness_model(**flags):
    """Runs the firmness_model CLI with --flag value pairs, returns its JSON."""
    exe = roslib.packages.find_node(PKG, 'firmness_model')
    if not exe:
        raise RuntimeError('firmness_model not found')
    args = [exe[0]]
    for key, value in flags.items():
        args += ['--' + key.replace('_', '-'), repr(value) if isinstance(value, float) else str(value)]
    args.append('--json')
    out = subprocess.run(args, check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def firmness_model_fast(**flags):
    """The strike of firmness_model(**flags) on the fast path (fastpath.h), as
    the node predicts it: `firmness_model sweep` over the one value
    of R2, its CSV row with firmness_model's JSON keys (no R2_min: None)."""
    exe = roslib.packages.find_node(PKG, 'firmness_model')
    if not exe:
        raise RuntimeError('firmness_model not found')
    flags = dict(flags)
    r2 = repr(flags.pop('R2'))
    args = [exe[0], 'sweep', '--param', 'R2', '--from', r2, '--to', r2, '--steps', '1']
    for key, value in flags.items():
        args += ['--' + key.replace('_', '-'), repr(value) if isinstance(value, float) else str(value)]
    out = subprocess.run(args, check=True, capture_output=True, text=True).stdout
    row = next(csv.DictReader(io.StringIO(out)))
    ref = {}
    for key, value in row.items():
        if key in ('excites_mode', 'no_damage', 'reliable'):
            ref[key] = bool(int(value))
        else:
            ref[key] = None if value == 'nan' else float(value)
    return ref


def model_flags(mass_kg, r2_m, hammer):
    """CLI flags for the node's configuration and one apple; hammer from the URDF."""
    return dict(E2=float(param('modulus_nominal_pa')), nu2=float(param('fruit_poisson')),
                R2=r2_m, e=float(param('restitution')), mass=mass_kg,
                density=float(param('density_kg_m3')), hammer_mass=hammer['mass_kg'],
                v0=float(param('strike_velocity_m_s')),
                hammer_E=float(param('hammer_modulus_pa')),
                hammer_nu=float(param('hammer_poisson')),
                hammer_radius=hammer['tip_radius_m'], gravity=float(param('gravity_m_s2')),
                damping=param('damping_law'), lobe=int(param('lobe')),
                band_level=param('band_level'), shear_ratio=param('shear_ratio'),
                yield_ratio=float(param('yield_ratio')),
                modulus_factor=float(param('modulus_factor')))


# --- the URDF, read without the shim --------------------------------------------

def _rpy_matrix(r, p, y):
    """URDF rpy: R = Rz(y) Ry(p) Rx(r), row-major 3x3 as nested lists."""
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return [[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr]]


def _matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def _matvec(a, v):
    return [sum(a[i][k] * v[k] for k in range(3)) for i in range(3)]


def _transpose(a):
    return [[a[j][i] for j in range(3)] for i in range(3)]


def _floats(text, default):
    return [float(x) for x in text.split()] if text else default


class Rig:
    """Hammer mass, tip radius and strike axis, and link rotations, from URDF XML."""

    def __init__(self, xml, hammer_link='hammer'):
        robot = ET.fromstring(xml)
        self.parent = {}  # child link -> (parent link, rotation child -> parent, joint element)
        for joint in robot.findall('joint'):
            origin = joint.find('origin')
            rpy = _floats(origin.get('rpy') if origin is not None else None, [0.0, 0.0, 0.0])
            self.parent[joint.find('child').get('link')] = (
                joint.find('parent').get('link'), _rpy_matrix(*rpy), joint)
        link = next(l for l in robot.findall('link') if l.get('name') == hammer_link)
        self.mass_kg = float(link.find('inertial/mass').get('value'))
        sphere = link.find('collision/geometry/sphere')
        self.tip_radius_m = float(sphere.get('radius')) if sphere is not None else 0.0
        joint = self.parent[hammer_link][2]
        axis = _floats(joint.find('axis').get('xyz') if joint.find('axis') is not None else None,
                       [1.0, 0.0, 0.0])
        # The axis is given in the joint's (= the hammer's) frame.
        self.strike_axis_root = _matvec(self.rotation_to_root(hammer_link), axis)

    def hammer(self):
        return {'mass_kg': self.mass_kg, 'tip_radius_m': self.tip_radius_m}

    def rotation_to_root(self, link):
        r = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
        while link in self.parent:
            link, rot, _ = self.parent[link]
            r = _matmul(rot, r)
        return r

    def strike_direction_in(self, frame):
        """The unit strike direction expressed in frame."""
        return _matvec(_transpose(self.rotation_to_root(frame)), self.strike_axis_root)


def rig_from_parameter():
    return Rig(rospy.get_param(rospy.resolve_name('robot_description')), param('hammer_link'))


# --- spheroid geometry, the textbook way ----------------------------------------

def polar_semi_axis(mass_kg, density, a):
    return 3.0 * mass_kg / (4.0 * math.pi * density * a * a)


def equivalent_radius(a, c, phi):
    w2 = (a * math.cos(phi)) ** 2 + (c * math.sin(phi)) ** 2
    meridional = a * a * c * c / w2 ** 1.5
    transverse = a * a / math.sqrt(w2)
    return math.sqrt(meridional * transverse)


def rotate(axis, angle, v):
    """Rodrigues."""
    c, s = math.cos(angle), math.sin(angle)
    kv = sum(axis[i] * v[i] for i in range(3))
    kxv = [axis[1] * v[2] - axis[2] * v[1], axis[2] * v[0] - axis[0] * v[2],
           axis[0] * v[1] - axis[1] * v[0]]
    return [v[i] * c + kxv[i] * s + axis[i] * kv * (1 - c) for i in range(3)]


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


# --- talking to the node ----------------------------------------------------------

class Station:
    """Publishes AppleEstimates on `apple` and collects the answers by apple_id."""

    TOPICS = (('excitation_band', ExcitationBand), ('strike_advice', StrikeAdvice),
              ('reliability', Reliability))

    def __init__(self, ns=''):
        """ns: the lane's namespace ('/lane2'); '' = the test's own."""
        self.lock = threading.Lock()
        self.answers = {}  # (topic, apple_id) -> (msg, receive wall time)
        self.markers = []
        at = (ns.rstrip('/') + '/') if ns else ''
        self.subs = [rospy.Subscriber(at + t, cls, self._store, callback_args=t)
                     for t, cls in self.TOPICS]
        self.subs.append(rospy.Subscriber(at + 'markers', MarkerArray, self._store_markers))
        self.pub = rospy.Publisher(at + 'apple', AppleEstimate, queue_size=10)

    def _store(self, msg, topic):
        with self.lock:
            self.answers[(topic, msg.apple_id)] = (msg, time.time())

    def _store_markers(self, msg):
        with self.lock:
            self.markers.append(msg)

    def wait_connected(self, timeout_s=20.0):
        """True when the node subscribes to apple and publishes to us."""
        end = time.time() + timeout_s
        while time.time() < end and not rospy.is_shutdown():
            if self.pub.get_num_connections() > 0 and all(s.get_num_connections() > 0 for s in self.subs):
                return True
            time.sleep(0.1)
        return False

    def send(self, apple_id, mass=0.175, equatorial_radius=0.040, strike_radius=0.0,
             stem_axis=(1.0, 0.0, 0.0), confidence=0.9, frame='camera_optical_frame',
             stamp=None):
        msg = AppleEstimate()
        msg.header.stamp = stamp if stamp is not None else rospy.Time(1000 + apple_id, 250)
        msg.header.frame_id = frame
        msg.apple_id = apple_id
        msg.mass = mass
        msg.equatorial_radius = equatorial_radius
        msg.strike_radius = strike_radius
        msg.stem_axis.x, msg.stem_axis.y, msg.stem_axis.z = stem_axis
        msg.confidence = confidence
        sent = time.time()
        self.pub.publish(msg)
        return msg, sent

    def wait(self, topics, apple_id, timeout_s=5.0):
        """The answers on topics for apple_id: {topic: (msg, latency_s)}, or those that came."""
        end = time.time() + timeout_s
        while time.time() < end:
            with self.lock:
                got = {t: self.answers.get((t, apple_id)) for t in topics}
            if all(got.values()):
                return got
            time.sleep(0.01)
        return {t: v for t, v in got.items() if v}


def find(exe):
    """The path of one of the package's executables (rosrun's lookup)."""
    path = roslib.packages.find_node(PKG, exe)
    if not path:
        raise RuntimeError('%s not found (built?)' % exe)
    return path[0]


def play(bag, rate=None):
    """Replays bag with `rosbag play --clock` on simulated time, once the
    node subscribes. rosbag play advertises "clock" relative to its
    namespace: rostest's ROS_NAMESPACE (the lane) would make it /lane1/clock,
    which no node hears, so it is dropped; the bag's own topics are
    absolute."""
    env = dict(os.environ)
    env.pop('ROS_NAMESPACE', None)
    cmd = ['rosbag', 'play', '--clock', '-q', '--delay=1', '--wait-for-subscribers']
    if rate is not None:
        cmd.append('--rate=%g' % rate)
    subprocess.run(cmd + [bag], check=True, stdout=subprocess.DEVNULL, env=env)


def wait_connected(pub, timeout=20.0):
    """Waits until every subscriber the master lists for pub's topic (this
    node's own included) has connected to pub, up to timeout seconds: a new
    publisher's subscribers connect to it asynchronously after it is
    advertised. True when they all did."""
    master = rosgraph.Master(rospy.get_name())
    end = time.time() + timeout
    while time.time() < end:
        subs = dict(master.getSystemState()[1]).get(pub.resolved_name, [])
        if subs and pub.get_num_connections() >= len(subs):
            return True
        time.sleep(0.02)
    return False


def clock_on(seconds, until=None):
    """Runs simulated time on after a replay: /clock from the test's last
    sim time, in steps of 0.1 s every 0.05 s of wall time, for `seconds` of
    sim time, or until `until()` is true. A node on simulated time does
    nothing time-driven once rosbag play stops its clock, so a /diagnostics
    tick due after the last strike would never come (the node's status at
    1 Hz of ROS time may fall before the last strike's report)."""
    pub = rospy.Publisher('/clock', Clock, queue_size=10)
    wait_connected(pub)
    t = rospy.get_rostime()
    for k in range(1, int(round(seconds / 0.1)) + 1):
        if until is not None and until():
            break
        pub.publish(Clock(clock=t + rospy.Duration(0.1 * k)))
        time.sleep(0.05)
    pub.unregister()
