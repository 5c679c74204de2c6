#!/usr/bin/python3
"""One replay of a strike bag through a fresh station node, measured (the
worker of scripts/load.sh and scripts/soak.sh; run with the devel space
sourced and a master up, use_sim_time set).

Starts station.launch (its own roslaunch, stopped by PID), replays the bag
with `rosbag play --clock -r RATE`, and reports, against the bag's truth CSV
(strike_bag): every StrikeReport matched to a true strike by its contact
start (within 1 ms), with the apple it was judged against; lost strikes (no
report), misattributed ones (another apple, or none), which of those the
node flagged itself (the measured Reliability's reason: no apple, doubtful
match, no audio) and its /diagnostics counters (queue overflows, late
estimates, stream gaps); the node's RSS every second; the latency from the
moment the strike's last needed sample was published (the end of its audio
window, mapped from bag time to wall time through the /clock the player
publishes) to the StrikeReport's arrival; and from the moment it became
decidable (its window in, and its apple settled: the next apple's estimate,
or apple_wait_s, whichever is first: the lane holds a strike until then, so
that a late estimate cannot make it judged against the wrong apple). Prints one line and writes the
figures as JSON.

  load_replay.py BAG TRUTH_CSV RATE OUT_JSON [--ns lane1] [--timeout S]
"""

import argparse
import csv
import json
import os
import signal
import subprocess
import sys
import threading
import time
import xmlrpc.client

import rosgraph
import rospy
from acoustic_firmness.msg import Reliability, StrikeReport
from diagnostic_msgs.msg import DiagnosticArray
from rosgraph_msgs.msg import Clock


# strike_bag publishes each apple's estimate this long before its strike [s]
LEAD_S = 0.2


def percentile(xs, p):
    if not xs:
        return float('nan')
    s = sorted(xs)
    k = (len(s) - 1) * p / 100.0
    i = int(k)
    j = min(i + 1, len(s) - 1)
    return s[i] + (s[j] - s[i]) * (k - i)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('bag')
    ap.add_argument('truth')
    ap.add_argument('rate', type=float)
    ap.add_argument('out')
    ap.add_argument('--ns', default='lane1')
    ap.add_argument('--timeout', type=float, default=0.0,
                    help='wall seconds after the bag ends to wait at most for the last reports '
                         '(default 120; the wait ends 3 s after the last report)')
    ap.add_argument('--rss-every', type=float, default=1.0)
    a = ap.parse_args()

    truth = list(csv.DictReader(open(a.truth)))
    starts = sorted((float(t['contact_start_s']), int(t['apple_id'])) for t in truth)
    node = '/%s/firmness_node' % a.ns
    rospy.init_node('load_replay', disable_signals=True)
    delay = float(rospy.get_param('~audio_delay', 0.0005))
    lock = threading.Lock()
    reports, reasons, clock = [], {}, []
    diag = {}

    def on_report(m):
        t = time.time()
        with lock:
            reports.append((m.header.stamp.to_sec(), m.apple_id, t))

    def on_rel(m):
        if m.source == 'measured':
            with lock:
                reasons[round(m.header.stamp.to_sec(), 6)] = m.reason

    def on_clock(m):
        t = time.time()
        with lock:
            clock.append((m.clock.to_sec(), t))

    def on_diag(m):
        for s in m.status:
            if s.hardware_id == node or s.name.endswith(node.lstrip('/')) or node in s.name:
                with lock:
                    diag.clear()
                    diag.update({kv.key: kv.value for kv in s.values})
                    diag['_level'] = s.level
                    diag['_message'] = s.message

    rospy.Subscriber('/%s/strike_report' % a.ns, StrikeReport, on_report, queue_size=10000,
                     tcp_nodelay=True)
    rospy.Subscriber('/%s/reliability' % a.ns, Reliability, on_rel, queue_size=10000)
    rospy.Subscriber('/clock', Clock, on_clock, queue_size=10000)
    rospy.Subscriber('/diagnostics', DiagnosticArray, on_diag, queue_size=100)

    env = dict(os.environ)
    env.pop('ROS_NAMESPACE', None)
    launch = subprocess.Popen(['roslaunch', 'acoustic_firmness', 'station.launch', 'ns:=' + a.ns],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env,
                              start_new_session=True)
    player = None
    try:
        master = rosgraph.Master('/load_replay')
        pid = None
        end = time.time() + 60.0
        while time.time() < end and pid is None:
            try:
                _, _, pid = xmlrpc.client.ServerProxy(master.lookupNode(node)).getPid('/load_replay')
            except Exception:
                time.sleep(0.2)
        if pid is None:
            sys.exit('load_replay: %s did not come up' % node)
        delay = rospy.get_param(node + '/measure_audio_delay_s')
        window = rospy.get_param(node + '/measure_audio_window_s')
        apple_wait = rospy.get_param(node + '/apple_wait_s')
        # the node subscribes before the first message: wait for its topics
        time.sleep(2.0)

        def rss_kb():
            with open('/proc/%d/status' % pid) as f:
                for line in f:
                    if line.startswith('VmRSS:'):
                        return int(line.split()[1])
            return 0

        rss = [(0.0, rss_kb())]
        w0 = time.time()
        player = subprocess.Popen(['rosbag', 'play', '--clock', '-q', '--delay=2', '--wait-for-subscribers', '-r', repr(a.rate), a.bag],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env,
                                  start_new_session=True)
        nxt = w0 + a.rss_every
        while player.poll() is None:
            now = time.time()
            if now >= nxt:
                rss.append((now - w0, rss_kb()))
                nxt += a.rss_every
            time.sleep(0.05)
        wall = time.time() - w0
        # the last strikes (their audio windows, the node's time-outs) and,
        # when the node fell behind, its backlog: until no report has come for
        # 3 s (at most --timeout, default 120 s)
        end = time.time() + (a.timeout if a.timeout > 0 else 120.0)
        last, since = -1, time.time()
        while time.time() < end:
            with lock:
                n = len(reports)
            if n != last:
                last, since = n, time.time()
            elif time.time() - since >= (1.0 if n >= len(starts) else 3.0):
                break
            time.sleep(0.2)
        rss.append((time.time() - w0, rss_kb()))
        time.sleep(1.2)  # one more /diagnostics
    finally:
        for p in (player, launch):
            if p is not None and p.poll() is None:
                os.killpg(p.pid, signal.SIGINT)
                try:
                    p.wait(timeout=15)
                except subprocess.TimeoutExpired:
                    os.killpg(p.pid, signal.SIGKILL)
                    p.wait()

    with lock:
        reps = list(reports)
        rs = dict(reasons)
        clk = list(clock)
        dg = dict(diag)

    # bag time -> wall time through the published clock (piecewise linear)
    clk.sort()

    def wall_at(t):
        if not clk:
            return float('nan')
        lo, hi = 0, len(clk) - 1
        if t <= clk[0][0]:
            return clk[0][1] - (clk[0][0] - t) / a.rate
        if t >= clk[-1][0]:
            return clk[-1][1] + (t - clk[-1][0]) / a.rate
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if clk[mid][0] <= t:
                lo = mid
            else:
                hi = mid
        (t0, w0_), (t1, w1) = clk[lo], clk[hi]
        return w0_ + (w1 - w0_) * (t - t0) / (t1 - t0) if t1 > t0 else w0_

    import bisect
    tstarts = [s for s, _ in starts]
    matched, lost, wrong, extra = {}, [], [], []
    flagged_wrong, lat, lat_decided = 0, [], []
    for stamp, apple, t_rx in reps:
        i = bisect.bisect_left(tstarts, stamp)
        best = None
        for j in (i - 1, i):
            if 0 <= j < len(tstarts) and abs(tstarts[j] - stamp) < 1e-3:
                best = j
        if best is None:
            extra.append((stamp, apple))
            continue
        matched[best] = apple
        true_apple = starts[best][1]
        reason = rs.get(round(stamp, 6), '')
        if apple != true_apple:
            flagged = apple == 0 or 'doubt' in reason or 'already struck' in reason
            wrong.append({'t': stamp, 'apple': apple, 'truth': true_apple, 'reason': reason,
                          'flagged': flagged})
            flagged_wrong += flagged
        window_end = stamp + delay + window
        lat.append(1e3 * (t_rx - wall_at(window_end)))
        # decidable: its audio window is in, and its apple is settled: the
        # next estimate (strike_bag: 0.2 s before the next strike) or the
        # apple wait, whichever comes first
        nxt = starts[best + 1][0] - LEAD_S if best + 1 < len(starts) else float('inf')
        decided = max(window_end, min(nxt, stamp + apple_wait))
        lat_decided.append(1e3 * (t_rx - wall_at(decided)))
    for j, (s, apple) in enumerate(starts):
        if j not in matched:
            lost.append({'t': s, 'truth': apple})
    n_audio = sum(1 for st, _, _ in reps if 'audio' in rs.get(round(st, 6), ''))
    doubtful = sum(1 for r in rs.values() if 'already struck' in r or 'doubt' in r)
    # achieved replay rate: bag seconds per wall second of the clock
    rate_ach = ((clk[-1][0] - clk[0][0]) / (clk[-1][1] - clk[0][1])
                if len(clk) > 1 and clk[-1][1] > clk[0][1] else float('nan'))
    warm = [kb for t, kb in rss if t >= 10.0] or [kb for _, kb in rss]
    res = {
        'rate': a.rate, 'achieved_rate': rate_ach, 'wall_s': wall, 'strikes': len(starts),
        'reports': len(reps), 'matched': len(matched), 'lost': len(lost), 'misattributed': len(wrong),
        'misattributed_flagged': flagged_wrong, 'extra_reports': len(extra),
        'reports_doubtful': doubtful, 'reports_without_audio': n_audio,
        'lost_list': lost[:20], 'wrong_list': wrong[:20],
        'unflagged_list': [w for w in wrong if not w['flagged']],
        'rss_kb': rss, 'rss_after_warmup_kb': warm[0], 'rss_end_kb': rss[-1][1],
        'rss_max_kb': max(kb for _, kb in rss), 'rss_growth_after_warmup_kb': warm[-1] - warm[0],
        'latency_ms': {'p50': percentile(lat, 50), 'p99': percentile(lat, 99),
                       'max': max(lat) if lat else float('nan'), 'n': len(lat)},
        'latency_decided_ms': {'p50': percentile(lat_decided, 50),
                               'p99': percentile(lat_decided, 99),
                               'max': max(lat_decided) if lat_decided else float('nan')},
        'diagnostics': dg,
    }
    with open(a.out, 'w') as f:
        json.dump(res, f, indent=1)
    L, D = res['latency_ms'], res['latency_decided_ms']
    print('rate %gx (achieved %.1fx, %.0f s wall): %d strikes, %d reports, %d lost, %d misattributed '
          '(%d of them flagged), %d extra; doubtful %d, without audio %d; diagnostics: queue overflows '
          '%s, late estimates %s, force gaps %s, audio gaps %s, doubtful %s, without apple %s; '
          'RSS %.1f MB after warm-up, %+.2f MB to the end (max %.1f); latency p50 %.1f ms, '
          'p99 %.1f ms, max %.1f ms (from decidable: p50 %.1f, p99 %.1f, max %.1f ms)'
          % (a.rate, rate_ach, wall, len(starts), len(reps), len(lost), len(wrong), flagged_wrong,
             len(extra), doubtful, n_audio, dg.get('strike queue overflows', '?'),
             dg.get('apple estimates after their strike', '?').split(' ')[0],
             dg.get('force gaps', '?'), dg.get('audio gaps', '?'),
             dg.get('strikes with a doubtful apple match', '?'),
             dg.get('strikes without apple', '?'),
             res['rss_after_warmup_kb'] / 1024.0, res['rss_growth_after_warmup_kb'] / 1024.0,
             res['rss_max_kb'] / 1024.0, L['p50'], L['p99'], L['max'], D['p50'], D['p99'],
             D['max']))
    sys.stdout.flush()


if __name__ == '__main__':
    main()
