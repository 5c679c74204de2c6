#!/usr/bin/python3
"""A rig's faults written into a good bag (strike_bag's) with the rosbag
Python API, never by the station's own code:

  edit_bag.py IN.bag OUT.bag EDIT [EDIT...]

  apple_shift=S       every AppleEstimate's stamp (and bag time) moved by S
                      seconds: a camera that stamps at publish time (S > 0)
  apple_bogus=T       one AppleEstimate more, apple_id 9999, stamped T s
                      (4294967295: a clock far off), written first
  audio_shift=S       every audio chunk's stamp moved by S seconds: a sound
                      card whose capture stamps late
  force_step=T,S      every force chunk stamped after T s (bag-relative)
                      moved by S seconds: a step in the DAQ's clock
  audio_clip=L        audio samples clipped at +-L, in the chunk's unit (the
                      microphone's gain too high)
  audio_stamp_rate=R  every audio chunk stamped as if sampled at R Hz (the
                      first chunk's stamp + first_sample / R) while its
                      sample_rate still says the true rate
  force_frozen=T      every force chunk after T s stamped as the last one
                      before T (a driver whose stamps froze)
  index_offset=N      N added to every chunk's first_sample, both streams (a
                      DAQ whose sample counter has run long: 2^53, 2^63)
"""
import sys

import genpy
import rosbag


def parse(edits):
    out = {}
    for e in edits:
        name, _, value = e.partition('=')
        out[name] = [int(value)] if name == 'index_offset' else [float(v) for v in value.split(',')]
    return out


def shifted(stamp, s):
    return genpy.Time.from_sec(stamp.to_sec() + s) if s else stamp


def main():
    src_path, dst_path, edits = sys.argv[1], sys.argv[2], parse(sys.argv[3:])
    with rosbag.Bag(src_path) as src, rosbag.Bag(dst_path, 'w') as dst:
        t0 = src.get_start_time()
        first = True
        audio0 = frozen = None
        for topic, msg, t in src.read_messages():
            if first and 'apple_bogus' in edits and topic.endswith('/apple'):
                bogus = msg.__class__()
                bogus.header.stamp = genpy.Time(int(edits['apple_bogus'][0]), 0)
                bogus.header.frame_id = msg.header.frame_id
                bogus.apple_id = 9999
                bogus.mass, bogus.equatorial_radius = msg.mass, msg.equatorial_radius
                bogus.strike_radius, bogus.stem_axis = msg.strike_radius, msg.stem_axis
                bogus.confidence = msg.confidence
                dst.write(topic, bogus, t)
                first = False
            if topic.endswith('/apple') and 'apple_shift' in edits:
                s = edits['apple_shift'][0]
                msg.header.stamp = shifted(msg.header.stamp, s)
                t = shifted(t, s)
            elif topic.endswith('/audio'):
                if 'audio_stamp_rate' in edits:
                    if audio0 is None:
                        audio0 = (msg.header.stamp.to_sec(), msg.first_sample)
                    msg.header.stamp = genpy.Time.from_sec(
                        audio0[0] + (msg.first_sample - audio0[1]) / edits['audio_stamp_rate'][0])
                if 'audio_shift' in edits:
                    msg.header.stamp = shifted(msg.header.stamp, edits['audio_shift'][0])
                if 'audio_clip' in edits:
                    lim = edits['audio_clip'][0]
                    msg.data = [max(-lim, min(lim, x)) for x in msg.data]
            elif topic.endswith('/force') and 'force_step' in edits:
                at, s = edits['force_step']
                if msg.header.stamp.to_sec() - t0 > at:
                    msg.header.stamp = shifted(msg.header.stamp, s)
            elif topic.endswith('/force') and 'force_frozen' in edits:
                if msg.header.stamp.to_sec() - t0 <= edits['force_frozen'][0]:
                    frozen = msg.header.stamp
                else:
                    msg.header.stamp = frozen
            if 'index_offset' in edits and not topic.endswith('/apple'):
                msg.first_sample += edits['index_offset'][0]
            dst.write(topic, msg, t)


if __name__ == '__main__':
    main()
