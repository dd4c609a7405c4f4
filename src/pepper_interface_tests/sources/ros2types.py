"""ROS 2 message types for reading a rosbag2 recording with no ROS 2 installed (rosbags' typestore),
and the conversion of each CDR message into the ROS 1 message the checks already read.

Where a type's definition comes from, latest first (a later source replaces an earlier one):
  1. the standard ROS 2 types shipped with rosbags (std_msgs, sensor_msgs, nav_msgs, ...);
  2. this package's own msg/ files (every .msg there, read generically: a new file is picked up),
     registered under this package's name and under the names the drivers publish them as
     (naoqi_bridge_msgs, naoqi_driver), and naoqi_bridge_msgs/AudioBuffer of naoqi_driver2;
  3. the definitions stored in the recording itself (MCAP always embeds them; sqlite3 from Iron
     on does, Humble's does not).
A topic whose type is in none of them cannot be read: `problems` names it.

Conversion: rosbags' cdr_to_ros1 writes each message in ROS 1 wire format: a ROS 2 Header
(stamp sec/nanosec, frame_id) becomes a ROS 1 Header with seq 0, builtin_interfaces/Time the ROS 1
time (same two 32-bit words). The checks then decode it with the ROS 1 classes, exactly as a
message out of a ROS 1 bag.
"""
import os
from typing import Any, Dict, Iterable, List, Optional, Tuple

from . import naoqi_msgs

# naoqi_bridge_msgs/msg/AudioBuffer.msg of ros-naoqi/naoqi_bridge_msgs2 (ROS 2: the field is
# `channel_map`; naoqi_driver2 src/event/audio.cpp:173-176 fills it). Same layout as the ROS 1
# message: converted, it decodes with naoqi_msgs.AUDIO_BUFFER_DEFINITION's class (channelMap).
AUDIO_BUFFER_DEFINITION_ROS2 = """std_msgs/Header header
uint16 frequency
uint8 CHANNEL_FRONT_LEFT=0
uint8 CHANNEL_FRONT_CENTER=1
uint8 CHANNEL_FRONT_RIGHT=2
uint8 CHANNEL_REAR_LEFT=3
uint8 CHANNEL_REAR_CENTER=4
uint8 CHANNEL_REAR_RIGHT=5
uint8 CHANNEL_SURROUND_LEFT=6
uint8 CHANNEL_SURROUND_RIGHT=7
uint8 CHANNEL_SUBWOOFER=8
uint8 CHANNEL_LFE=9
uint8[] channel_map
int16[] data
"""

# ROS 1 definitions this package already knows, used for the converted message instead of one
# generated from the ROS 2 definition (same wire layout, the field names the checks read)
ROS1_DEFINITIONS = {naoqi_msgs.AUDIO_BUFFER_TYPE: naoqi_msgs.AUDIO_BUFFER_DEFINITION}

# the packages this package's msg/ files are published as by the drivers
MSG_PACKAGES = ('pepper_interface_tests', 'naoqi_bridge_msgs', 'naoqi_driver')


def ros1_name(ros2_type: str) -> str:
    """'sensor_msgs/msg/LaserScan' -> 'sensor_msgs/LaserScan' (a ROS 1 name is returned as is)."""
    parts = ros2_type.split('/')
    if len(parts) == 3 and parts[1] == 'msg':
        return parts[0] + '/' + parts[2]
    return ros2_type


def package_msg_types(msg_dir: str) -> Dict[str, Any]:
    """Field definitions of every msg/*.msg of this package (and naoqi_driver2's AudioBuffer),
    under each of MSG_PACKAGES; a file that cannot be parsed is left out."""
    from rosbags.typesys import get_types_from_msg
    types: Dict[str, Any] = dict(get_types_from_msg(AUDIO_BUFFER_DEFINITION_ROS2,
                                                    'naoqi_bridge_msgs/msg/AudioBuffer'))
    names = sorted(f for f in os.listdir(msg_dir) if f.endswith('.msg')) if os.path.isdir(msg_dir) else []
    for name in names:
        try:
            with open(os.path.join(msg_dir, name), encoding='utf-8') as f:
                text = f.read()
        except (OSError, UnicodeDecodeError):
            continue
        for pkg in MSG_PACKAGES:
            try:
                types.update(get_types_from_msg(text, '%s/msg/%s' % (pkg, name[:-4])))
            except Exception:  # noqa: BLE001  (a malformed .msg: that type stays unknown)
                break
    return types


def recording_types(msgtype: str, msgdef: Any) -> Dict[str, Any]:
    """Field definitions stored in the recording for one connection ({} when it has none);
    raises on a definition rosbags cannot parse."""
    from rosbags.typesys import get_types_from_idl, get_types_from_msg
    fmt = getattr(msgdef, 'format', None)
    data = getattr(msgdef, 'data', '') or ''
    name = getattr(fmt, 'name', '')
    if name == 'MSG' and data:
        return dict(get_types_from_msg(data, msgtype))
    if name == 'IDL' and data:
        sep = '=' * 80 + '\n'
        types: Dict[str, Any] = {}
        parts = data.split(sep)[1:] if data.startswith(sep + 'IDL: ') else [data]
        for part in parts:
            types.update(get_types_from_idl(part.split('\n', 1)[1] if part.startswith('IDL: ') else part))
        return types
    return {}


class Converter:
    """CDR -> ROS 1 bytes for the connections of one recording, with the ROS 1 connection header
    fields (type, md5sum, message_definition) the checks' decoders use."""

    def __init__(self, connections: Iterable[Any], msg_dir: str) -> None:
        from rosbags.typesys import Stores, get_typestore
        types: Dict[str, Any] = dict(get_typestore(Stores.LATEST).fielddefs)
        types.update(package_msg_types(msg_dir))
        self.problems: Dict[str, str] = {}     # topic -> why its messages cannot be read
        for conn in connections:
            try:
                types.update(recording_types(conn.msgtype, conn.msgdef))
            except Exception as e:  # noqa: BLE001  (a definition rosbags cannot parse)
                self.problems[conn.topic] = ('its type %s has a definition in the recording that '
                                             'cannot be read (%s)' % (conn.msgtype, str(e)[:100]))
        self.store = get_typestore(Stores.EMPTY)
        self.store.register(types)
        self._headers: Dict[str, Dict[str, Any]] = {}
        for conn in connections:
            if conn.topic in self.problems:
                continue
            missing = self.missing(conn.msgtype)
            if missing:
                self.problems[conn.topic] = (
                    'its type %s has no definition in the recording nor in this package (%s '
                    'unknown)' % (conn.msgtype, missing))

    def missing(self, msgtype: str, seen: Optional[set] = None) -> Optional[str]:
        """The first type `msgtype` needs that the typestore lacks, or None."""
        seen = set() if seen is None else seen
        if msgtype in seen:
            return None
        seen.add(msgtype)
        fields = self.store.fielddefs.get(msgtype)
        if fields is None:
            return msgtype
        for sub in _nested(fields):
            gone = self.missing(sub, seen)
            if gone:
                return gone
        return None

    def header(self, msgtype: str) -> Dict[str, Any]:
        """ROS 1 connection header fields of a ROS 2 type (cached)."""
        conn = self._headers.get(msgtype)
        if conn is None:
            name = ros1_name(msgtype)
            text, md5 = self.store.generate_msgdef(msgtype, ros_version=1)
            conn = self._headers[msgtype] = {'type': name, 'md5sum': md5,
                                             'message_definition': ROS1_DEFINITIONS.get(name, text)}
        return conn

    def to_ros1(self, raw: bytes, msgtype: str) -> bytes:
        """One CDR message as ROS 1 wire bytes; b'' when it cannot be converted (truncated or not
        of its type): the window then reports it as a message that could not be decoded."""
        try:
            return bytes(self.store.cdr_to_ros1(raw, msgtype))
        except Exception:  # noqa: BLE001  (corrupt data is a finding of the check, not a crash)
            return b''


def _nested(fields: Tuple[List[Any], List[Any]]) -> List[str]:
    """The message types a rosbags field definition refers to."""
    out: List[str] = []

    def visit(desc: Any) -> None:
        kind, arg = desc
        if getattr(kind, 'name', '') == 'NAME':
            out.append(arg)
        elif getattr(kind, 'name', '') in ('ARRAY', 'SEQUENCE'):
            visit(arg[0])
    for _name, desc in fields[1]:
        visit(desc)
    return out
