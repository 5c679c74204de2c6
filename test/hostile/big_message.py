#!/usr/bin/python3
"""The node's peak RSS around very long SignalChunks ("the node
stays within 256 MiB whatever message arrives"), and its stream after them.

  big_message.py [SAMPLES [REPEAT]]     (default 100000000 samples: 400 MB; 2)

Starts its own roscore on a free port and a firmness_node with the shipped
YAML and the rig URDF (as test/node/test_wire_cap.py does), waits for the
subscription and reads the node's VmHWM and VmRSS (/proc/PID/status). Then
REPEAT times: publishes one force SignalChunk of SAMPLES samples (built here
as bytes, struct), waits until /diagnostics counts it among the "messages
too long to read" (af_wire_guard.h: roscpp never reads it), then publishes
small good chunks (1000 samples, the index running on) until the node's
"force chunks" count takes them: the connection was made again. Reads VmHWM
and VmRSS again. One line per figure; exit 1 when a wait ends unmet or the
node's VmHWM exceeds 256 MiB (AF_SANITIZED=1: not checked, ASan's shadow
memory). Needs the devel space sourced. ctest: hostile_big_message."""

import os
import re
import signal
import socket
import struct
import subprocess
import sys
import time


def free_port():
    with socket.socket() as s:
        s.bind(('127.0.0.1', 0))
        return s.getsockname()[1]


def status_kib(pid, key):
    with open('/proc/%d/status' % pid) as f:
        return int(re.search(key + r':\s+(\d+) kB', f.read()).group(1))


def chunk_bytes(n, unit, rate, first=0):
    """A SignalChunk serialized by hand: header (seq, stamp, frame_id),
    first_sample, sample_rate, unit, data (length prefix + n float32 zeros)."""
    frame, u = b'hammer', unit.encode()
    head = struct.pack('<III', 0, 100, 0) + struct.pack('<I', len(frame)) + frame
    body = struct.pack('<Qd', first, rate) + struct.pack('<I', len(u)) + u
    return head + body + struct.pack('<I', n) + bytes(4 * n)


def main():
    samples = int(sys.argv[1]) if len(sys.argv) > 1 else 100000000
    repeat = int(sys.argv[2]) if len(sys.argv) > 2 else 2
    port = free_port()
    os.environ['ROS_MASTER_URI'] = 'http://127.0.0.1:%d' % port
    core = subprocess.Popen(['roscore', '-p', str(port)], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, preexec_fn=os.setsid)
    node = None
    try:
        import rosgraph
        end = time.time() + 30
        while time.time() < end and not rosgraph.is_master_online():
            time.sleep(0.2)
        import rosparam
        import rospkg
        import rospy
        import roslib.packages
        from acoustic_firmness.msg import SignalChunk
        from diagnostic_msgs.msg import DiagnosticArray

        class Raw(SignalChunk):
            __slots__ = ['raw']

            def __init__(self, raw):
                super().__init__()
                self.raw = raw

            def serialize(self, buff):
                buff.write(self.raw)

        rospy.init_node('big_message', disable_signals=True)
        ns, name, pkg = '/big', 'firmness_node', 'acoustic_firmness'
        path = rospkg.RosPack().get_path(pkg)
        params = {}
        for f in ('station.yaml', 'jonagold.yaml'):
            for p, _ in rosparam.load_file(os.path.join(path, 'config', f)):
                params.update(p)
        rosparam.upload_params(ns + '/' + name, params)
        rospy.set_param(ns + '/robot_description',
                        open(os.path.join(path, 'config', 'rig.urdf')).read())
        exe = roslib.packages.find_node(pkg, name)[0]
        node = subprocess.Popen([exe, '__ns:=' + ns, '__name:=' + name],
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        diag = {}
        rospy.Subscriber('/diagnostics', DiagnosticArray,
                         lambda m: diag.update({kv.key: kv.value for s in m.status
                                                for kv in s.values}))
        pub = rospy.Publisher(ns + '/force', SignalChunk, queue_size=2)
        end = time.time() + 30
        while time.time() < end and pub.get_num_connections() == 0:
            time.sleep(0.1)
        if pub.get_num_connections() == 0:
            print('big_message: the node never subscribed to %s/force' % ns)
            return 1
        time.sleep(1.0)
        print('before: VmHWM %.1f MiB, VmRSS %.1f MiB' %
              (status_kib(node.pid, 'VmHWM') / 1024, status_kib(node.pid, 'VmRSS') / 1024))
        unit, rate = params.get('force_unit', 'N'), params['force_sample_rate_hz']
        raw = Raw(chunk_bytes(samples, unit, rate))
        print('message: %d samples, %d bytes (%.1f MiB)' % (samples, len(raw.raw),
                                                            len(raw.raw) / 2**20))

        def wait(what, test, bound_s, poke=None):
            end = time.time() + bound_s
            while time.time() < end and not test():
                if poke:
                    poke()
                time.sleep(0.2)
            if not test():
                print('big_message: %s not seen within %g s' % (what, bound_s))
                return False
            return True

        def count(key):
            return int(diag.get(key, '0').split()[0])

        first = 0
        for k in range(1, repeat + 1):
            pub.publish(raw)
            if not wait('long message %d counted' % k,
                        lambda: count('messages too long to read') >= k, 60):
                return 1
            good = count('force chunks')

            def send_good():
                nonlocal first
                pub.publish(Raw(chunk_bytes(1000, unit, rate, first)))
                first += 1000

            if not wait('a good chunk after message %d' % k,
                        lambda: count('force chunks') > good, 30, send_good):
                return 1
        time.sleep(0.5)
        hwm = status_kib(node.pid, 'VmHWM') / 1024
        print('after:  VmHWM %.1f MiB, VmRSS %.1f MiB' %
              (hwm, status_kib(node.pid, 'VmRSS') / 1024))
        for key in ('messages too long to read', 'force chunks', 'force bad chunks'):
            print('%s: %s' % (key, diag.get(key, '(none)')))
        if os.environ.get('AF_SANITIZED', '0') != '1' and hwm > 256:
            print('big_message: the node peaked at %.1f MiB, above 256 MiB' % hwm)
            return 1
        return 0
    finally:
        if node is not None:
            node.send_signal(signal.SIGINT)
            try:
                node.wait(timeout=20)
            except subprocess.TimeoutExpired:
                node.kill()
                node.wait()
        os.killpg(core.pid, signal.SIGINT)
        core.wait(timeout=30)


if __name__ == '__main__':
    sys.exit(main())
