"""A /tf message of a layout seen before, decoded in place: its stamps and transforms read with
one numpy gather into the objects of the last message of that layout, not a new message.

naoqi_driver sends the same 84 transforms, in the same order with the same frame names, with
every joint state (src/converters/joint_state.cpp:207-265, 50 Hz): from one message to the
next only the stamps, the seq numbers and the 7 numbers of each transform change. genpy's
TFMessage.deserialize builds six objects per transform (0.5 ms a message on this machine), and
it was the largest part of reading a recording's /tf (docs/tf.md, "Memory and cost"). A layout
is learned from one message decoded by genpy: the byte offsets of its stamps and numbers and
the bytes of everything else (counts, lengths, frame names). A later message is decoded in
place only when it has the same length and those bytes are equal; otherwise genpy decodes it
(and it becomes the layout), so a changed tree is read exactly as before.

The message returned is the layout's own, overwritten by the next message of that layout: the
caller must copy what it keeps (the tree record keeps floats; tf2's set_transform copies).
ROS 1 wire format (genpy's, tf2_msgs/TFMessage): uint32 count; per transform uint32 seq,
uint32 secs, uint32 nsecs, string frame_id (uint32 length + bytes), string child_frame_id,
float64 x 3 (translation), float64 x 4 (rotation)."""
import struct
from typing import Any, Dict, Hashable, List, Optional, Tuple

import numpy as np

from ..sources import messages

_U32 = struct.Struct('<I')
MAX_LAYOUTS = 64         # a run's publishers and sizes of /tf are a handful: bounded anyway


class _Layout:
    """Where a message's stamps and numbers are, the bytes that must match, its objects."""

    def __init__(self, msg: Any, buff: bytes, stamps: List[int], numbers: List[int]) -> None:
        self.msg = msg
        self.size = len(buff)
        data = np.frombuffer(buff, np.uint8)
        variable = np.zeros(self.size, bool)
        self.stamp_at = _spans(stamps, 8)
        self.number_at = _spans(numbers, 56)
        variable[self.stamp_at] = True
        variable[self.number_at] = True
        for start in stamps:                 # seq: the uint32 before each stamp
            variable[start - 4:start] = True
        self.fixed_at = np.flatnonzero(~variable)
        self.fixed = data[self.fixed_at].copy()
        self.objects = [(t.header.stamp, t.transform.translation, t.transform.rotation)
                        for t in msg.transforms]

    def matches(self, data: np.ndarray) -> bool:
        return data.size == self.size and np.array_equal(data[self.fixed_at], self.fixed)

    def fill(self, data: np.ndarray) -> bool:
        """Overwrites the objects with `data`'s stamps and numbers; False when a stamp's nsecs
        is not below a second (genpy keeps such a value as it is: let genpy decode it)."""
        stamps = data[self.stamp_at].view('<u4').reshape(-1, 2)
        if stamps.size and int(stamps[:, 1].max()) >= 1000000000:
            return False
        numbers = data[self.number_at].view('<f8').reshape(-1, 7).tolist()
        for (stamp, p, q), (secs, nsecs), v in zip(self.objects, stamps.tolist(), numbers):
            stamp.secs, stamp.nsecs = secs, nsecs
            p.x, p.y, p.z = v[0], v[1], v[2]
            q.x, q.y, q.z, q.w = v[3], v[4], v[5], v[6]
        return True


def _spans(starts: List[int], width: int) -> np.ndarray:
    """Byte indices of `width` bytes from each start, in order."""
    if not starts:
        return np.zeros(0, np.intp)
    return (np.asarray(starts, np.intp)[:, None] + np.arange(width, dtype=np.intp)).ravel()


def _offsets(buff: bytes) -> Optional[Tuple[List[int], List[int]]]:
    """(the offset of each transform's stamp, of its 7 numbers) in a ROS 1 TFMessage; None
    when the bytes do not end where the last transform does."""
    try:
        (n,) = _U32.unpack_from(buff, 0)
        pos, stamps, numbers = 4, [], []
        for _ in range(n):
            stamps.append(pos + 4)
            pos += 12
            for _string in range(2):
                (length,) = _U32.unpack_from(buff, pos)
                pos += 4 + length
            numbers.append(pos)
            pos += 56
    except struct.error:
        return None
    return (stamps, numbers) if pos == len(buff) else None


class LayoutDecoder:
    """TFMessages of repeated layouts decoded in place (see the module docstring)."""

    def __init__(self, type_name: str) -> None:
        self.type_name = type_name
        self._layouts: Dict[Hashable, _Layout] = {}
        self.in_place = 0          # messages decoded in place
        self.learned = 0           # messages decoded by genpy (a new or changed layout)

    def decode(self, key: Hashable, buff: bytes) -> Any:
        """The message in `buff` (the layout's objects, or genpy's new message); raises what
        genpy raises on a broken message."""
        layout = self._layouts.get(key)
        if layout is not None:
            data = np.frombuffer(buff, np.uint8)
            if layout.matches(data) and layout.fill(data):
                self.in_place += 1
                return layout.msg
        msg = messages.message_class(self.type_name)().deserialize(buff)
        self.learned += 1
        found = _offsets(buff)
        if found is None or len(found[0]) != len(msg.transforms):
            self._layouts.pop(key, None)
            return msg
        if len(self._layouts) >= MAX_LAYOUTS:
            self._layouts.clear()
        self._layouts[key] = _Layout(msg, buff, *found)
        return msg
