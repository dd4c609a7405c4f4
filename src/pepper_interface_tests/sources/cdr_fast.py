"""CDR -> ROS 1 wire bytes for the heavy messages (camera frames, microphone buffers, /tf) in one copy.

rosbags' cdr_to_ros1 (ros2types.Converter) sizes the message, allocates a zeroed buffer, copies
every field into it, and the result is copied once more into bytes: three passes over a 1 MB
frame, about 90 us each on this machine. Here the few fields before the payload are read with
struct and the ROS 1 bytes are the new prefix joined with a view of the payload: one copy.

Layouts (ROS 2: little-endian CDR after the 4-byte encapsulation header, every field aligned to
its size counted from the end of that header, strings with their NUL counted in the length;
ROS 1: packed, no alignment, strings without NUL, and std_msgs/Header leads with uint32 seq,
which the ROS 2 Header does not have and is written as 0, as cdr_to_ros1 writes it):
  sensor_msgs/msg/Image              header, uint32 height, width, string encoding,
                                     uint8 is_bigendian, uint32 step, uint8[] data
  naoqi_bridge_msgs/msg/AudioBuffer  header, uint16 frequency, uint8[] channel_map, int16[] data
                                     (ros-naoqi/naoqi_bridge_msgs2 msg/AudioBuffer.msg)
  tf2_msgs/msg/TFMessage             geometry_msgs/TransformStamped[] transforms: each a header,
                                     string child_frame_id, float64 x 3 (translation), x 4
                                     (rotation); 84 a message at 50 Hz from naoqi_driver, where
                                     rosbags' generic conversion cost twice the tree's own work

`raw` is bytes (sqlite3) or a view into an MCAP chunk (mcap_chunks.py): both slice, compare
and unpack alike, and the result is new bytes that hold no view.

Anything unusual (big-endian CDR, a length that runs past the buffer, a string without its NUL)
raises ValueError and the caller converts with rosbags instead, so a damaged message is judged
exactly as before. test/sources/test_cdr_fast.py checks the bytes against cdr_to_ros1's.
"""
import struct
from typing import Any, Callable, Dict, List, Optional, Tuple, Union

Chunk = Union[bytes, memoryview]

_U32 = struct.Struct('<I')
_U16 = struct.Struct('<H')
_SEQ0 = b'\x00\x00\x00\x00'


def _align(pos: int, n: int) -> int:
    """`pos` (an offset into the CDR buffer, whose payload starts at 4) aligned to n bytes."""
    return 4 + (pos - 4 + n - 1) // n * n


def _string(raw: Chunk, pos: int) -> Tuple[Chunk, int]:
    """(the string's bytes without NUL, the position after it) of the CDR string at `pos`."""
    pos = _align(pos, 4)
    (n,) = _U32.unpack_from(raw, pos)
    end = pos + 4 + n
    if n == 0 or end > len(raw) or raw[end - 1] != 0:
        raise ValueError('not a CDR string')
    return raw[pos + 4:end - 1], end


def _header(raw: Chunk, out: List[Chunk]) -> int:
    """Appends the ROS 1 std_msgs/Header to `out`; the position after the CDR one."""
    if len(raw) < 16 or raw[0:2] != b'\x00\x01':
        raise ValueError('not little-endian CDR')
    frame_id, pos = _string(raw, 12)
    out += [_SEQ0, raw[4:12], _U32.pack(len(frame_id)), frame_id]
    return pos


def _sequence(raw: Chunk, pos: int, item: int) -> Tuple[int, int, int]:
    """(element count, start of the elements, end) of the CDR sequence whose length is at `pos`."""
    pos = _align(pos, 4)
    (n,) = _U32.unpack_from(raw, pos)
    start = _align(pos + 4, item)
    end = start + n * item
    if end > len(raw):
        raise ValueError('sequence runs past the message')
    return n, start, end


def image(raw: Chunk) -> bytes:
    return bytes(Ros2Image(raw))


class Ros2Image:
    """A sensor_msgs/msg/Image read in place: the CDR bytes parsed once into the pieces of its
    ROS 1 bytes (a new prefix, the pixels a view), no copy until one is asked for (a minute of
    four VGA cameras was 2.7 GB of copies). message() is the genpy sensor_msgs/Image the camera
    checks decode from ROS 1 bytes, built from those pieces (seq 0, as cdr_to_ros1 writes it;
    text decoded as sensors/camera.py decodes it); bytes() are the ROS 1 bytes (image()), for a
    listener that deserializes with genpy. Raises ValueError (or struct.error) on anything
    unusual: the caller then converts with rosbags."""

    __slots__ = ('prefix', 'data')

    def __init__(self, raw: Chunk) -> None:
        out: List[Chunk] = []
        pos = _align(_header(raw, out), 4)
        sizes = raw[pos:pos + 8]                                  # height, width
        encoding, pos = _string(raw, pos + 8)
        if pos + 1 > len(raw):
            raise ValueError('short message')
        is_bigendian = raw[pos:pos + 1]
        pos = _align(pos + 1, 4)
        step = raw[pos:pos + 4]
        n, start, end = _sequence(raw, pos + 4, 1)
        if len(sizes) != 8 or len(step) != 4:
            raise ValueError('short message')
        # seq, stamp, len(frame_id), frame_id, sizes, len(encoding), encoding, is_bigendian, step, len(data)
        self.prefix = out + [sizes, _U32.pack(len(encoding)), encoding, is_bigendian, step, _U32.pack(n)]
        self.data = memoryview(raw)[start:end]

    def message(self) -> Any:
        from genpy import Time

        from .messages import message_class
        p = self.prefix
        msg = message_class('sensor_msgs/Image')()
        msg.header.seq = 0
        msg.header.stamp = Time(*struct.unpack('<2I', p[1]))
        msg.header.frame_id = bytes(p[3]).decode('utf-8', 'replace')
        msg.height, msg.width = struct.unpack('<2I', p[4])
        msg.encoding = bytes(p[6]).decode('utf-8', 'replace')
        msg.is_bigendian = p[7][0]
        (msg.step,) = _U32.unpack(p[8])
        msg.data = self.data
        return msg

    def __bytes__(self) -> bytes:
        return b''.join(self.prefix + [self.data])


def audio_buffer(raw: Chunk) -> bytes:
    out: List[Chunk] = []
    pos = _align(_header(raw, out), 2)
    frequency = raw[pos:pos + 2]
    n_map, map_start, map_end = _sequence(raw, pos + 2, 1)
    n, start, end = _sequence(raw, map_end, 2)
    if len(frequency) != 2:
        raise ValueError('short message')
    out += [frequency, _U32.pack(n_map), raw[map_start:map_end], _U32.pack(n), memoryview(raw)[start:end]]
    return b''.join(out)


def tf_message(raw: Chunk) -> bytes:
    """/tf: per transform its stamp, frame_id and child_frame_id, then its seven float64 (the
    translation and rotation, aligned to 8 in CDR, packed in ROS 1: the same bytes). A
    publisher sends the same frames in every message, only stamps and numbers change: the first
    message of a layout is converted field by field and leaves a byte map (_TfLayout); the next
    ones of the same size whose frame names are byte for byte the same are one numpy gather."""
    layout = _TF_LAYOUTS.get(len(raw))
    if layout is not None:
        out = layout.apply(raw)
        if out is not None:
            return out
    out, layout = _tf_fields(raw)
    if len(_TF_LAYOUTS) >= 16:
        _TF_LAYOUTS.clear()
    _TF_LAYOUTS[len(raw)] = layout
    return out


class _TfLayout:
    """A TFMessage layout: the first message's ROS 1 bytes as a template, where its stamps and
    numbers come from in the CDR bytes, and the CDR bytes that must match for the template to
    hold (the count, the frame names with their lengths and NULs)."""

    def __init__(self, converted: bytes, dst: List[int], src: List[int], fixed: List[int], raw: Chunk) -> None:
        import numpy as np
        self.template = np.frombuffer(converted, np.uint8)
        self.dst = np.array(dst, np.int64)
        self.src = np.array(src, np.int64)
        self.fixed = np.array(fixed, np.int64)
        self.fixed_bytes = np.frombuffer(raw, np.uint8)[self.fixed].copy()

    def apply(self, raw: Chunk) -> Optional[bytes]:
        import numpy as np
        data = np.frombuffer(raw, np.uint8)
        if raw[0:2] != b'\x00\x01' or not np.array_equal(data[self.fixed], self.fixed_bytes):
            return None
        out = self.template.copy()
        out[self.dst] = data[self.src]
        return out.tobytes()


_TF_LAYOUTS: Dict[int, _TfLayout] = {}


def _tf_fields(raw: Chunk) -> Tuple[bytes, _TfLayout]:
    """The conversion field by field, and the layout it followed."""
    if len(raw) < 8 or raw[0:2] != b'\x00\x01':
        raise ValueError('not little-endian CDR')
    (n,) = _U32.unpack_from(raw, 4)
    out: List[Chunk] = [raw[4:8]]
    dst: List[int] = []
    src: List[int] = []
    fixed = list(range(4, 8))
    pos, o = 8, 4               # o: the offset in the ROS 1 bytes
    for _ in range(n):
        stamp_at = _align(pos, 4)
        stamp = raw[stamp_at:stamp_at + 8]
        parent_at = stamp_at + 8
        parent, pos = _string(raw, parent_at)
        child_at = _align(pos, 4)
        child, pos = _string(raw, pos)
        numbers_at = _align(pos, 8)
        end = numbers_at + 56
        if end > len(raw) or len(stamp) != 8:
            raise ValueError('short message')
        out += [_SEQ0, stamp, _U32.pack(len(parent)), parent, _U32.pack(len(child)), child, raw[numbers_at:end]]
        fixed += list(range(parent_at, parent_at + 5 + len(parent)))     # length, name, NUL
        fixed += list(range(child_at, child_at + 5 + len(child)))
        dst += list(range(o + 4, o + 12))
        src += list(range(stamp_at, stamp_at + 8))
        o += 12 + 4 + len(parent) + 4 + len(child)
        dst += list(range(o, o + 56))
        src += list(range(numbers_at, end))
        o += 56
        pos = end
    converted = b''.join(out)
    return converted, _TfLayout(converted, dst, src, fixed, raw)


# ROS 2 type -> its direct conversion
CONVERTERS: Dict[str, Callable[[Chunk], bytes]] = {
    'sensor_msgs/msg/Image': image,
    'naoqi_bridge_msgs/msg/AudioBuffer': audio_buffer,
    'tf2_msgs/msg/TFMessage': tf_message,
}
# the types each conversion reads besides its own (their layouts must be the ones read here)
NESTED: Dict[str, Tuple[str, ...]] = {
    'tf2_msgs/msg/TFMessage': ('geometry_msgs/msg/TransformStamped', 'geometry_msgs/msg/Transform',
                               'geometry_msgs/msg/Vector3', 'geometry_msgs/msg/Quaternion'),
}
