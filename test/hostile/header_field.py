#!/usr/bin/env python3
"""A copy of a bag whose file-header record holds one field more:
the bag reader reuses rosbag::Bag objects; a bag naming an encryptor must be
refused as before, and must not leave that encryptor to the next bag):

  header_field.py GOOD.bag OUT.bag NAME=VALUE

The field is written after the record's others, its bytes taken from the
record's padding, so that every offset in the file stays (the bag format
2.0: "#ROSBAG V2.0\\n", then the file-header record: header length, the
fields each as length + "name=value", data length, padding)."""
import struct
import sys


def main():
    good, out, field = sys.argv[1], sys.argv[2], sys.argv[3].encode()
    b = open(good, 'rb').read()
    at = len(b'#ROSBAG V2.0\n')
    assert b[:at] == b'#ROSBAG V2.0\n', 'not a bag 2.0'
    (header_len,) = struct.unpack_from('<I', b, at)
    fields_end = at + 4 + header_len
    (data_len,) = struct.unpack_from('<I', b, fields_end)
    add = 4 + len(field)
    assert data_len >= add, 'no room in the padding'
    new = (b[:at] + struct.pack('<I', header_len + add) + b[at + 4:fields_end] +
           struct.pack('<I', len(field)) + field + struct.pack('<I', data_len - add) +
           b' ' * (data_len - add) + b[fields_end + 4 + data_len:])
    assert len(new) == len(b)
    open(out, 'wb').write(new)


if __name__ == '__main__':
    main()
