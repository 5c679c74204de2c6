#!/usr/bin/python3
"""A test helper node: makes a strike_bag recording (--strikes N, --seed S) in
a temporary folder and plays it with `rosbag play --clock` at --rate R on the
lane's topics, then removes it. Used by rates.test, where hztest measures the
node's output rates on the bag's simulated time."""

import argparse
import os
import shutil
import subprocess
import sys
import tempfile

import rospy
import roslib.packages


def main():
    argv = rospy.myargv(sys.argv)[1:]
    p = argparse.ArgumentParser()
    p.add_argument('--strikes', type=int, default=60)
    p.add_argument('--seed', type=int, default=5)
    p.add_argument('--rate', type=float, default=2.0)
    p.add_argument('--ns', default='lane1')
    args = p.parse_args(argv)
    tmp = tempfile.mkdtemp(prefix='af_replay_')
    try:
        bag = os.path.join(tmp, 'session.bag')
        exe = roslib.packages.find_node('acoustic_firmness', 'strike_bag')[0]
        subprocess.run([exe, '--strikes', str(args.strikes), '--seed', str(args.seed), '--out', bag,
                        '--ns', args.ns], check=True, stdout=subprocess.DEVNULL)
        # rosbag play advertises "clock" relative to its namespace: play from the root.
        env = dict(os.environ)
        env.pop('ROS_NAMESPACE', None)
        subprocess.run(['rosbag', 'play', '--clock', '-q', '--delay=2', '--wait-for-subscribers', '--rate=%g' % args.rate, bag],
                       check=True, stdout=subprocess.DEVNULL, env=env)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == '__main__':
    main()
