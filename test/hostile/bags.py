#!/usr/bin/env python3
"""Hostile bags for test/hostile/test_data.sh, made from a good bag (strike_bag)
with the rosbag Python API (never by hand-editing a file):

  bags.py GOOD.bag OUT_DIR [BIG_SAMPLES [big]]   (big: big_chunk.bag alone)

  string_on_force.bag  a std_msgs/String on the force topic, among the chunks
  chunk_on_apple.bag   the first force SignalChunk written on the apple topic too
                       (its own connection, of type SignalChunk)
  duplicates.bag       every force chunk written twice
  same_stamp.bag       every AppleEstimate followed by a second, another id,
                       at the same stamp
  big_chunk.bag        one force SignalChunk of BIG_SAMPLES zero samples
                       (default 2^24: 64 MiB), beyond any ring
  overflow.bag         one force chunk more at first_sample 2^64 - 5
  empty_chunk.bag      a message of 0 bytes on the force topic (SignalChunk's
                       connection)
  md5_mismatch.bag     the force topic's connection under another md5sum (a
                       SignalChunk of another definition)
  nul_unit.bag         the first force chunk's unit "N\\0x" (a NUL inside)
"""
import struct
import sys

import rosbag
from std_msgs.msg import String


def copy(good, out, edit):
    with rosbag.Bag(good) as src, rosbag.Bag(out, 'w') as dst:
        for topic, raw, t in src.read_messages(raw=True):
            edit(dst, topic, raw, t)


def plain(dst, topic, raw, t):
    dst.write(topic, raw, t, raw=True)


def message(raw):
    """The message of a raw (kind, data, md5, pos, cls) record."""
    msg = raw[4]()
    msg.deserialize(raw[1])
    return msg


def first_force(state, key, topic):
    """True once: for the first force message seen under this key."""
    if not topic.endswith('/force') or state.get(key):
        return False
    state[key] = True
    return True


def main():
    good, out = sys.argv[1], sys.argv[2]
    big = int(sys.argv[3]) if len(sys.argv) > 3 else 1 << 24
    state = {}
    only_big = len(sys.argv) > 4 and sys.argv[4] == 'big'

    def string_on_force(dst, topic, raw, t):
        plain(dst, topic, raw, t)
        if first_force(state, 'string', topic):
            dst.write(topic, String(data='not a chunk'), t)

    def chunk_on_apple(dst, topic, raw, t):
        plain(dst, topic, raw, t)
        if first_force(state, 'chunk_on_apple', topic):
            state['first_chunk'] = (raw, t)
        if topic.endswith('/apple') and 'first_chunk' in state:
            # A second connection on the apple topic, of type SignalChunk, as a
            # recorder makes when two publishers of two types share a topic.
            # rosbag's Python writer keeps one connection per topic: its map
            # is set aside for this one message.
            chunk, t0 = state.pop('first_chunk')
            kept = dst._topic_connections.pop(topic)
            dst.write(topic, chunk, t0, raw=True)
            dst._topic_connections[topic] = kept

    def duplicates(dst, topic, raw, t):
        plain(dst, topic, raw, t)
        if topic.endswith('/force'):
            plain(dst, topic, raw, t)

    def same_stamp(dst, topic, raw, t):
        plain(dst, topic, raw, t)
        if topic.endswith('/apple'):
            msg = message(raw)
            msg.apple_id += 1000
            dst.write(topic, msg, t)

    if not only_big:
        copy(good, out + '/string_on_force.bag', string_on_force)
        copy(good, out + '/chunk_on_apple.bag', chunk_on_apple)
        copy(good, out + '/duplicates.bag', duplicates)
        copy(good, out + '/same_stamp.bag', same_stamp)

    def overflow(dst, topic, raw, t):
        plain(dst, topic, raw, t)
        if first_force(state, 'overflow', topic):
            msg = message(raw)
            msg.first_sample = 2 ** 64 - 5
            dst.write(topic, msg, t)

    def empty_chunk(dst, topic, raw, t):
        plain(dst, topic, raw, t)
        if first_force(state, 'empty', topic):
            kind, data, md5, pos, cls = raw
            dst.write(topic, (kind, b'', md5, pos, cls), t, raw=True)

    def md5_mismatch(dst, topic, raw, t):
        if topic.endswith('/force'):
            kind, data, md5, pos, cls = raw
            raw = (kind, data, '0123456789abcdef0123456789abcdef', pos, cls)
        plain(dst, topic, raw, t)

    def nul_unit(dst, topic, raw, t):
        if not first_force(state, 'nul_unit', topic):
            plain(dst, topic, raw, t)
            return
        msg = message(raw)
        msg.unit = msg.unit + '\0x'
        dst.write(topic, msg, t)

    if not only_big:
        copy(good, out + '/overflow.bag', overflow)
        copy(good, out + '/empty_chunk.bag', empty_chunk)
        copy(good, out + '/md5_mismatch.bag', md5_mismatch)
        copy(good, out + '/nul_unit.bag', nul_unit)

    def big_chunk(dst, topic, raw, t):
        plain(dst, topic, raw, t)
        if first_force(state, 'big', topic):
            kind, data, md5, pos, cls = raw
            msg = message(raw)
            msg.first_sample += 10 ** 9  # far ahead: refused before the ring sees it
            msg.data = [0.0] * 0
            buf = __import__('io').BytesIO()
            msg.serialize(buf)
            ser = buf.getvalue()
            # The empty data's length prefix (the last 4 bytes) replaced by
            # BIG_SAMPLES zero samples.
            ser = ser[:-4] + struct.pack('<I', big) + bytes(4 * big)
            dst.write(topic, (kind, ser, md5, pos, cls), t, raw=True)
    copy(good, out + '/big_chunk.bag', big_chunk)


if __name__ == '__main__':
    main()
