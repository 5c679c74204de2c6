"""WAV files for the tests, written with Debian's python3 alone, independently
of the package's reader (src/core/io/wav.c): integer PCM through the standard
library's `wave` module; IEEE float and WAVE_FORMAT_EXTENSIBLE, which `wave`
does not write, with a header packed here field by field after Microsoft's
RIFF/WAVE layout. Signals are lists of floats; integer PCM stores
x / full_scale rounded to the bit depth (8-bit unsigned, offset 128)."""
import math
import struct
import wave

SUBFORMAT_TAIL = bytes([0x00, 0x00, 0x00, 0x00, 0x10, 0x00, 0x80, 0x00, 0x00, 0xAA, 0x00, 0x38,
                        0x9B, 0x71])


def read_f32(path):
    raw = open(path, 'rb').read()
    return list(struct.unpack('<%df' % (len(raw) // 4), raw))


def _int_sample(x, full_scale, bits):
    top = 2 ** (bits - 1)
    v = int(math.floor(x / full_scale * top + 0.5))
    v = max(-top, min(top - 1, v))
    if bits == 8:
        return bytes([v + 128])
    return (v & (2 ** bits - 1)).to_bytes(bits // 8, 'little')


def _frames(channels, sample):
    n = len(channels[0])
    return b''.join(b''.join(sample(ch[k]) for ch in channels) for k in range(n))


def write_pcm(path, rate, channels, bits, full_scale):
    """Integer PCM (8, 16, 24 or 32 bit) through the wave module."""
    with wave.open(path, 'wb') as w:
        w.setnchannels(len(channels))
        w.setsampwidth(bits // 8)
        w.setframerate(int(rate))
        w.writeframes(_frames(channels, lambda x: _int_sample(x, full_scale, bits)))


def fmt_chunk(tag, nch, rate, bits, extensible_sub=None, valid_bits=None):
    align = nch * bits // 8
    body = struct.pack('<HHIIHH', tag, nch, rate, rate * align, align, bits)
    if extensible_sub is not None:
        body += struct.pack('<HHI', 22, valid_bits or bits, 0)
        body += struct.pack('<H', extensible_sub) + SUBFORMAT_TAIL
    return b'fmt ' + struct.pack('<I', len(body)) + body


def riff(chunks):
    body = b'WAVE' + b''.join(chunks)
    return b'RIFF' + struct.pack('<I', len(body)) + body


def data_chunk(payload):
    pad = b'\0' if len(payload) % 2 else b''
    return b'data' + struct.pack('<I', len(payload)) + payload + pad


def write_float(path, rate, channels, bits, extensible=False):
    """IEEE float (32 or 64 bit), tag 3 or extensible with the float GUID."""
    code = '<f' if bits == 32 else '<d'
    payload = _frames(channels, lambda x: struct.pack(code, x))
    fmt = (fmt_chunk(0xFFFE, len(channels), int(rate), bits, extensible_sub=3) if extensible
           else fmt_chunk(3, len(channels), int(rate), bits))
    open(path, 'wb').write(riff([fmt, data_chunk(payload)]))


def write_extensible_pcm(path, rate, channels, bits, full_scale, valid_bits=None):
    """Integer PCM in WAVE_FORMAT_EXTENSIBLE (a LIST chunk before the data, as
    recorders write). valid_bits < bits: the samples left-justified."""
    vb = valid_bits or bits

    def sample(x):  # the low (bits - vb) bits zero
        return b'\0' * ((bits - vb) // 8) + _int_sample(x, full_scale, vb)
    payload = _frames(channels, sample)
    info = b'LIST' + struct.pack('<I', 4 + 8 + 4) + b'INFO' + b'ISFT' + struct.pack('<I', 4) + b'py\0\0'
    open(path, 'wb').write(riff([fmt_chunk(0xFFFE, len(channels), int(rate), bits, 1, vb), info,
                                 data_chunk(payload)]))
