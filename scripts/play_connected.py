#!/usr/bin/env python3
"""Replays a bag with rosbag play once its subscribers are connected.

  /usr/bin/python3 scripts/play_connected.py [--wait NODE]... [--timeout S] [--name NAME]
      -- [rosbag play options] BAG...

`rosbag play --wait-for-subscribers` waits for one subscriber per topic; a
second subscriber that connects later misses the first messages. This starts
`rosbag play --pause` (node NAME, default /af_play), then waits, without a
fixed sleep, until
  - every NODE given with --wait is registered with the master as a
    subscriber of every topic the player publishes (/clock aside), and
  - every subscriber the master lists for those topics (the --wait nodes and
    any other) has its connection to the player open (the player's own
    getBusInfo),
then starts the playback as its keyboard control does: a space on its
standard input (a pipe here; the pause_playback service would need
std_srvs' Python messages, which the package does not depend on).
Prints "play_connected: playing" when it does. Exit status: rosbag play's;
2 on a bad argument, 1 when the subscribers are not connected within S
seconds (default 60; what is missing is printed) or the player ended early.
The ROS master is ROS_MASTER_URI's.
"""
import argparse
import os
import subprocess
import sys
import time
import xmlrpc.client

import rosgraph


def parse():
    p = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    p.add_argument('--wait', action='append', default=[], metavar='NODE',
                   help='a node that must subscribe to every topic of the bag first')
    p.add_argument('--timeout', type=float, default=60.0, metavar='S',
                   help='seconds to wait for the connections (default 60)')
    p.add_argument('--name', default='/af_play', help='the player node name (default /af_play)')
    p.add_argument('play', nargs=argparse.REMAINDER, help='-- then rosbag play arguments')
    a = p.parse_args()
    if a.play and a.play[0] == '--':
        a.play = a.play[1:]
    if not a.play:
        p.error('no rosbag play arguments (after --)')
    return a


def missing(master, name, wait):
    """What is not ready yet, one phrase each; [] when every subscriber is connected."""
    pubs, subs, _ = master.getSystemState()
    topics = sorted(t for t, nodes in pubs if name in nodes and t not in ('/clock', '/rosout'))
    if not topics:
        return ['the player %s has advertised no topic' % name]
    subscribers = {t: set(nodes) for t, nodes in subs}
    connected = {}
    try:
        code, _, bus = xmlrpc.client.ServerProxy(master.lookupNode(name)).getBusInfo('/af_play_connected')
    except Exception as e:  # the player is not up yet
        return ['the player %s: %s' % (name, e)]
    if code != 1:
        return ['the player %s gave no bus information' % name]
    for info in bus:
        # [connection id, destination caller id, direction, transport, topic, connected, ...]
        if len(info) >= 6 and info[2] == 'o' and info[5]:
            connected.setdefault(info[4], set()).add(info[1])
    out = []
    for t in topics:
        for n in wait:
            if n not in subscribers.get(t, set()):
                out.append('%s not subscribed to %s' % (n, t))
        for n in sorted(subscribers.get(t, set()) - connected.get(t, set())):
            out.append('%s not connected to %s' % (n, t))
    return out


def main():
    a = parse()
    name = a.name if a.name.startswith('/') else '/' + a.name
    master = rosgraph.Master('/af_play_connected')
    env = dict(os.environ)
    env.pop('ROS_NAMESPACE', None)
    player = subprocess.Popen(['rosbag', 'play', '--pause'] + a.play + ['__name:=' + name.lstrip('/')],
                              stdin=subprocess.PIPE, env=env)
    try:
        end = time.time() + a.timeout
        left = ['nothing checked']
        while time.time() < end and player.poll() is None:
            try:
                left = missing(master, name, a.wait)
            except (rosgraph.MasterException, OSError) as e:
                left = ['the master: %s' % e]
            if not left:
                break
            time.sleep(0.05)
        if player.poll() is not None:
            print('play_connected: rosbag play ended (%d) before playing' % player.returncode,
                  file=sys.stderr)
            return player.returncode or 1
        if left:
            print('play_connected: not ready after %g s: %s' % (a.timeout, '; '.join(left)),
                  file=sys.stderr)
            player.terminate()
            player.wait()
            return 1
        player.stdin.write(b' ')
        player.stdin.flush()
        print('play_connected: playing', flush=True)
        return player.wait()
    finally:
        if player.poll() is None:
            player.terminate()
            player.wait()


if __name__ == '__main__':
    sys.exit(main())
