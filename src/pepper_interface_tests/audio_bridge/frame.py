"""Wire format of the NAOqi audio bridge: one websocket binary message per NAOqi buffer.

A frame is a fixed 40-byte little-endian header followed by the int16 little-endian samples of
one NAOqi buffer, exactly as NAOqi delivered them (planar or interleaved, see ``FLAG_PLANAR``)::

    offset size field
     0     4    magic                b'PAU1'
     4     1    version              1
     5     1    flags                bit 0: 1 = planar (deinterleaved), 0 = interleaved
     6     2    channels             1..8
     8     4    samples_per_channel  1..16384
    12     4    sample_rate          Hz, 1..192000
    16     4    stream_id            random per capture process start (detects capture restarts)
    20     8    sequence             0, 1, 2 ... per buffer within a stream
    28     4    ts_sec               NAOqi timeStamp[0]
    32     4    ts_usec              NAOqi timeStamp[1]
    36     4    payload_bytes        = channels * samples_per_channel * 2
    40     ...  payload              int16 little-endian samples

This module is shared by the capture side, which may run on the robot under Python 2.7, and the
ROS side (Python 3): it uses ``struct`` only, no f-strings and no annotations, and works with
``str`` bytes on 2.7 and ``bytes``/``bytearray``/``memoryview`` on 3. Its signatures are type
comments, which mypy checks and Python 2.7 ignores.
"""
import collections
import struct

MYPY = False
if MYPY:    # read by mypy only: the robot's Python 2.7 has no typing module
    from typing import Union  # noqa: F401  # novm

MAGIC = b'PAU1'
VERSION = 1
FLAG_PLANAR = 0x01
KNOWN_FLAGS = FLAG_PLANAR

HEADER = struct.Struct('<4sBBHIIIQIII')
HEADER_SIZE = HEADER.size  # 40

MAX_CHANNELS = 8
MAX_SAMPLES_PER_CHANNEL = 16384
MAX_SAMPLE_RATE = 192000
MAX_PAYLOAD_BYTES = MAX_CHANNELS * MAX_SAMPLES_PER_CHANNEL * 2
MAX_FRAME_BYTES = HEADER_SIZE + MAX_PAYLOAD_BYTES

# HTTP header of the websocket handshake that carries the shared token, when one is configured.
TOKEN_HEADER = 'X-Pepper-Audio-Token'



class Frame(collections.namedtuple(
        'Frame', ['planar', 'channels', 'samples_per_channel', 'sample_rate', 'stream_id',
                  'sequence', 'ts_sec', 'ts_usec', 'payload'])):
    """One decoded NAOqi buffer; payload holds the raw int16 LE samples."""
    __slots__ = ()


class FrameError(ValueError):
    """A message that is not a valid frame. ``cause`` is a short stable key for counting."""

    def __init__(self, cause, detail):
        # type: (str, str) -> None
        ValueError.__init__(self, '%s: %s' % (cause, detail))
        self.cause = cause
        self.detail = detail


def _check_geometry(channels, samples_per_channel, sample_rate):
    # type: (int, int, int) -> None
    if not 1 <= channels <= MAX_CHANNELS:
        raise FrameError('bad channel count',
                         'channels=%d, expected 1..%d' % (channels, MAX_CHANNELS))
    if not 1 <= samples_per_channel <= MAX_SAMPLES_PER_CHANNEL:
        raise FrameError('oversized' if samples_per_channel > MAX_SAMPLES_PER_CHANNEL
                         else 'bad sample count',
                         'samples_per_channel=%d, expected 1..%d'
                         % (samples_per_channel, MAX_SAMPLES_PER_CHANNEL))
    if not 1 <= sample_rate <= MAX_SAMPLE_RATE:
        raise FrameError('bad sample rate',
                         'sample_rate=%d, expected 1..%d' % (sample_rate, MAX_SAMPLE_RATE))


def encode_frame(payload, channels, samples_per_channel, sample_rate, sequence,
                 ts_sec=0, ts_usec=0, planar=True, stream_id=0):
    # type: (Union[bytes, bytearray, memoryview], int, int, int, int, int, int, bool, int) -> bytes
    """Return the frame (bytes) for one buffer. ``payload`` is the raw int16 LE sample bytes."""
    # memoryview.tobytes(), not bytes(): on Python 2.7 bytes is str, and str(memoryview) is its
    # repr ('<memory at 0x...>'), not its contents
    payload = payload.tobytes() if isinstance(payload, memoryview) else bytes(payload)
    _check_geometry(channels, samples_per_channel, sample_rate)
    expected = channels * samples_per_channel * 2
    if len(payload) != expected:
        raise FrameError('length mismatch',
                         'payload has %d bytes, %d ch x %d samples x 2 = %d'
                         % (len(payload), channels, samples_per_channel, expected))
    flags = FLAG_PLANAR if planar else 0
    header = HEADER.pack(MAGIC, VERSION, flags, channels, samples_per_channel, sample_rate,
                         stream_id & 0xFFFFFFFF, sequence, ts_sec & 0xFFFFFFFF,
                         ts_usec & 0xFFFFFFFF, expected)
    return header + payload


def decode_frame(data):
    # type: (Union[bytes, bytearray, memoryview]) -> Frame
    """Parse and validate one message; return a Frame or raise FrameError with the reason."""
    if isinstance(data, memoryview):
        data = data.tobytes()
    elif isinstance(data, bytearray):
        data = bytes(data)
    if len(data) > MAX_FRAME_BYTES:
        raise FrameError('oversized', 'message of %d bytes, limit %d' % (len(data), MAX_FRAME_BYTES))
    if len(data) < HEADER_SIZE:
        if data[:4] != MAGIC[:len(data[:4])]:
            raise FrameError('bad magic', 'message does not start with %r' % MAGIC)
        raise FrameError('truncated', 'message of %d bytes, header needs %d'
                         % (len(data), HEADER_SIZE))
    (magic, version, flags, channels, samples, rate, stream_id, sequence, ts_sec, ts_usec,
     payload_bytes) = HEADER.unpack_from(data, 0)
    if magic != MAGIC:
        raise FrameError('bad magic', 'got %r, expected %r' % (magic, MAGIC))
    if version != VERSION:
        raise FrameError('bad version', 'version %d, this side speaks %d' % (version, VERSION))
    if flags & ~KNOWN_FLAGS:
        raise FrameError('bad flags', 'unknown flag bits 0x%02x' % (flags & ~KNOWN_FLAGS))
    _check_geometry(channels, samples, rate)
    expected = channels * samples * 2
    if payload_bytes != expected:
        raise FrameError('length mismatch', 'header says %d payload bytes, %d ch x %d samples '
                         'x 2 = %d' % (payload_bytes, channels, samples, expected))
    actual = len(data) - HEADER_SIZE
    if actual < expected:
        raise FrameError('truncated', 'payload has %d of %d bytes' % (actual, expected))
    if actual > expected:
        raise FrameError('length mismatch', 'payload has %d bytes, header says %d'
                         % (actual, expected))
    return Frame(bool(flags & FLAG_PLANAR), channels, samples, rate, stream_id, sequence,
                 ts_sec, ts_usec, data[HEADER_SIZE:])
