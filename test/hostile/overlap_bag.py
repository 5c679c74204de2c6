#!/usr/bin/env python3
"""A bag whose force chunks overlap: from a good bag (strike_bag),
every force SignalChunk that follows the previous one without a gap is
written with the previous chunk's last OVERLAP samples in front of its own
(first_sample and stamp moved back by as many samples), through the rosbag
Python API:

  overlap_bag.py GOOD.bag OUT.bag [OVERLAP [changed]]

changed: the first repeated sample of each chunk is altered by 1.0 (the head
no longer repeats what was sent: each such chunk is a restart). Prints the
number of force chunks and of repeated samples written."""
import sys

import rosbag
import rospy


def main():
    good, out = sys.argv[1], sys.argv[2]
    overlap = int(sys.argv[3]) if len(sys.argv) > 3 else 40
    changed = len(sys.argv) > 4 and sys.argv[4] == 'changed'
    end, tail = None, []  # the previous force chunk as sent: its end index, its last samples
    chunks = repeated = 0
    with rosbag.Bag(good) as src, rosbag.Bag(out, 'w') as dst:
        for topic, raw, t in src.read_messages(raw=True):
            if not topic.endswith('/force'):
                dst.write(topic, raw, t, raw=True)
                continue
            msg = raw[4]()
            msg.deserialize(raw[1])
            data = list(msg.data)
            next_end, next_tail = msg.first_sample + len(data), data[-overlap:]
            if end == msg.first_sample and tail:
                head = list(tail)
                if changed:
                    head[0] += 1.0
                msg.first_sample -= len(head)
                msg.header.stamp -= rospy.Duration.from_sec(len(head) / msg.sample_rate)
                msg.data = head + data
                repeated += len(head)
            end, tail = next_end, next_tail
            chunks += 1
            dst.write(topic, msg, t)
    print('%d force chunks, %d samples repeated' % (chunks, repeated))


if __name__ == '__main__':
    main()
