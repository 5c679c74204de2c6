#!/usr/bin/python3
"""A noise gate written into strike_bag's bag with the rosbag Python API,
never by the station's own code:

  gate_bag.py IN.bag TRUTH.csv OUT.bag OPEN_S [SILENT_N]

every audio sample set to exactly 0.0 except from OPEN_S seconds before each
strike's contact start (the truth CSV's contact_start_s) to 0.25 s after it:
a recorder's gate that closes between taps and opens OPEN_S before each
(0: at the tap), as sound cards write digital silence. OPEN_S 'never': all
audio exact zeros. SILENT_N: the gate stays shut for the first SILENT_N
strikes (their apples pass in silence). A sample's time is the first audio chunk's stamp plus
its index over the chunk's sample_rate."""
import bisect
import csv
import sys

import rosbag


def main():
    src_path, truth_path, dst_path, open_arg = sys.argv[1:5]
    silent_n = int(sys.argv[5]) if len(sys.argv) > 5 else 0
    starts = sorted(float(r['contact_start_s']) for r in csv.DictReader(open(truth_path)))[silent_n:]
    spans = [] if open_arg == 'never' else [(s - float(open_arg), s + 0.25) for s in starts]
    opens = [a for a, _ in spans]
    with rosbag.Bag(src_path) as src, rosbag.Bag(dst_path, 'w') as dst:
        origin = None
        for topic, msg, t in src.read_messages():
            if topic.endswith('/audio'):
                if origin is None:  # the stamp of sample 0
                    origin = msg.header.stamp.to_sec() - msg.first_sample / msg.sample_rate
                data = list(msg.data)
                for k in range(len(data)):
                    ts = origin + (msg.first_sample + k) / msg.sample_rate
                    i = bisect.bisect_right(opens, ts) - 1
                    if i < 0 or ts >= spans[i][1]:
                        data[k] = 0.0
                msg.data = data
            dst.write(topic, msg, t)


if __name__ == '__main__':
    main()
