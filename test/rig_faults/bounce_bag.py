#!/usr/bin/python3
"""A hammer that bounces inside the contact, written into strike_bag's bag
with the rosbag Python API: at each strike of the truth CSV, a second
impact shaped like the first (the force above the baseline over the
contact, scaled by FRACTION) starts DELAY_S after the contact start.

  bounce_bag.py IN.bag TRUTH.csv OUT.bag DELAY_S FRACTION [EVERY]

EVERY: only every EVERY-th strike bounces (default 1: all), from the 9th on,
so that the hammer's first clean strikes set its reference."""
import csv
import sys

import rosbag


def main():
    src, truth, dst = sys.argv[1], sys.argv[2], sys.argv[3]
    delay_s, fraction = float(sys.argv[4]), float(sys.argv[5])
    every = int(sys.argv[6]) if len(sys.argv) > 6 else 1
    starts = [float(r['contact_start_s']) for r in csv.DictReader(open(truth))]
    with rosbag.Bag(src) as b:
        msgs = list(b.read_messages())
    force = [m for m in msgs if m.topic.endswith('/force')]
    first0, stamp0 = force[0].message.first_sample, force[0].message.header.stamp.to_sec()
    rate = force[0].message.sample_rate
    x = []
    for m in force:
        x.extend(m.message.data)
    bounced = 0
    for k, s in enumerate(starts):
        if k < 8 or (k - 8) % every:
            continue
        i0 = int(round((s - stamp0) * rate)) - first0
        base = sum(x[i0 - 200:i0 - 20]) / 180.0
        span = int(0.004 * rate)  # longer than any contact
        pulse = [max(0.0, v - base) for v in x[i0:i0 + span]]
        d = int(round(delay_s * rate))
        for j, v in enumerate(pulse):
            x[i0 + d + j] += fraction * v
        bounced += 1
    at = 0
    with rosbag.Bag(dst, 'w') as out:
        for m in msgs:
            msg = m.message
            if m.topic.endswith('/force'):
                n = len(msg.data)
                msg.data = x[at:at + n]
                at += n
            out.write(m.topic, msg, m.timestamp)
    print('bounced %d strikes' % bounced)


if __name__ == '__main__':
    main()
