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
import functools
import os
import struct
from types import MappingProxyType
from typing import Any, Dict, Iterable, List, Mapping, Optional, Set, Tuple, Union

from . import naoqi_msgs
from .ros2defs import DEFAULT_DISTRO, DISTROS, ROS1_DEFINITIONS, ros1_definition, ros1_text, ros2_text  # noqa: F401  (home: ros2defs.py)

# naoqi_bridge_msgs/msg/AudioBuffer.msg of ros-naoqi/naoqi_bridge_msgs2 (ROS 2: the field is
# `channel_map`; naoqi_driver2 src/event/audio.cpp:173-176 fills it). Same layout as the ROS 1
# message: converted, it decodes with naoqi_msgs.AUDIO_BUFFER_DEFINITION's class (channelMap).
AUDIO_BUFFER_DEFINITION_ROS2 = (naoqi_msgs.AUDIO_BUFFER_DEFINITION.split('=' * 80)[0]
                                .replace('Header header', 'std_msgs/Header header')
                                .replace('channelMap', 'channel_map'))

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
                try:
                    types.update(get_types_from_msg(text, '%s/msg/%s' % (pkg, name[:-4])))
                except Exception:  # noqa: BLE001  (ROS 1 spelling rosbags refuses: its ROS 2 form)
                    types.update(get_types_from_msg(ros2_text(text), '%s/msg/%s' % (pkg, name[:-4])))
            except Exception:  # noqa: BLE001  (a malformed .msg: that type stays unknown)
                break
    # the naoqi_bridge_msgs types this package knows without a file (StringStamped, ...)
    for type_name, text in naoqi_msgs.DEFINITIONS.items():
        pkg, name = type_name.split('/')
        key = '%s/msg/%s' % (pkg, name)
        if key not in types:
            try:
                types.update(get_types_from_msg(ros2_text(text), key))
            except Exception:  # noqa: BLE001  (cannot happen for the shipped texts: tested)
                pass
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



def standard_types(distro: Optional[str]) -> Dict[str, Any]:
    """The standard ROS 2 field definitions of `distro` (Humble's when unknown)."""
    name = DISTROS.get((distro or '').strip().lower(), DISTROS[DEFAULT_DISTRO])
    return dict(_store_fields(name))


@functools.lru_cache(maxsize=None)
def _store_fields(name: str) -> Mapping[str, Any]:
    from rosbags.typesys import Stores, get_typestore
    return MappingProxyType(dict(get_typestore(getattr(Stores, name, Stores.ROS2_HUMBLE)).fielddefs))


class Converter:
    """CDR -> ROS 1 bytes for the connections of one recording, with the ROS 1 connection header
    fields (type, md5sum, message_definition) the checks' decoders use."""

    def __init__(self, connections: Iterable[Any], msg_dir: str, distro: Optional[str] = None) -> None:
        from rosbags.typesys import Stores, get_typestore
        connections = list(connections)
        types: Dict[str, Any] = standard_types(distro)
        types.update(package_msg_types(msg_dir))
        self.problems: Dict[str, str] = {}     # topic -> why its messages cannot be read
        for conn in connections:
            try:
                types.update(recording_types(conn.msgtype, conn.msgdef))
            except Exception as e:  # noqa: BLE001  (a definition rosbags cannot parse)
                self.problems[conn.topic] = ('its type %s has a definition in the recording that '
                                             'cannot be read (%s)' % (conn.msgtype, str(e)[:100]))
        # only the types the recording's topics need are registered (a few, not the ~150
        # standard ones: registering builds a class for each)
        needed: Set[str] = set()
        for conn in connections:
            if conn.topic in self.problems:
                continue
            missing = _closure(conn.msgtype, types, needed)
            if missing:
                self.problems[conn.topic] = (
                    'its type %s has no definition in the recording nor in this package (%s '
                    'unknown)' % (conn.msgtype, missing))
        self.store = get_typestore(Stores.EMPTY)
        self.store.register({name: types[name] for name in needed})
        self._headers: Dict[str, Dict[str, Any]] = {}
        # the heavy types converted in one copy (cdr_fast.py), when the recording's definition
        # of them is the one that module reads
        from . import cdr_fast
        self.fast = {name: convert for name, convert in cdr_fast.CONVERTERS.items()
                     if name in needed and _same_layout(types, name)}

    def header(self, msgtype: str) -> Dict[str, Any]:
        """ROS 1 connection header fields of a ROS 2 type (cached)."""
        conn = self._headers.get(msgtype)
        if conn is None:
            from . import messages
            name = ros1_name(msgtype)
            text = ROS1_DEFINITIONS.get(name) or ros1_text(self.store.generate_msgdef(msgtype, ros_version=1)[0])
            try:
                md5 = messages.message_class(name, text)._md5sum
            except Exception:  # noqa: BLE001  (a definition genpy cannot build: decoding will say so)
                md5 = '*'
            conn = self._headers[msgtype] = {'type': name, 'md5sum': md5, 'message_definition': text}
        return conn

    def for_checks(self, raw: Union[bytes, memoryview], msgtype: str) -> Any:
        """What a recording hands the listeners: a camera frame read in place (cdr_fast.Ros2Image:
        its pixels a view, no copy; bytes() of it are the ROS 1 bytes), anything else as ROS 1
        wire bytes (to_ros1)."""
        if msgtype == 'sensor_msgs/msg/Image' and msgtype in self.fast:
            from .cdr_fast import Ros2Image
            try:
                return Ros2Image(raw)
            except (ValueError, struct.error):   # unusual: converted as before
                pass
        return self.to_ros1(raw, msgtype)

    def to_ros1(self, raw: Union[bytes, memoryview], msgtype: str) -> bytes:
        """One CDR message (bytes, or a view into an MCAP chunk) as ROS 1 wire bytes; b'' when it
        cannot be converted (truncated or not of its type): the window then reports it as a
        message that could not be decoded."""
        fast = self.fast.get(msgtype)
        if fast is not None:
            try:
                return fast(raw)
            except (ValueError, struct.error):   # anything unusual: rosbags decides, as before
                pass
        try:
            return bytes(self.store.cdr_to_ros1(bytes(raw), msgtype))
        except Exception:  # noqa: BLE001  (corrupt data is a finding of the check, not a crash)
            return b''


@functools.lru_cache(maxsize=None)
def fast_layouts() -> Mapping[str, Any]:
    """The field definitions cdr_fast.py reads: Image, TFMessage and the types in them of the
    standard types (the same in every ROS 2 release), naoqi_driver2's AudioBuffer
    (AUDIO_BUFFER_DEFINITION_ROS2)."""
    from rosbags.typesys import get_types_from_msg
    std = _store_fields(DISTROS[DEFAULT_DISTRO])
    layouts: Dict[str, Any] = {name: std[name] for name in
                               ('sensor_msgs/msg/Image', 'std_msgs/msg/Header', 'builtin_interfaces/msg/Time',
                                'tf2_msgs/msg/TFMessage', 'geometry_msgs/msg/TransformStamped',
                                'geometry_msgs/msg/Transform', 'geometry_msgs/msg/Vector3',
                                'geometry_msgs/msg/Quaternion')}
    layouts.update(get_types_from_msg(AUDIO_BUFFER_DEFINITION_ROS2, 'naoqi_bridge_msgs/msg/AudioBuffer'))
    return MappingProxyType(layouts)


def _same_layout(types: Mapping[str, Any], name: str) -> bool:
    """True when `types` defines `name`, its std_msgs/Header and builtin_interfaces/Time with the
    wire layout cdr_fast.py reads: the same kinds of fields in the same order (the names and the
    constants do not change the bytes: rosbags-convert stores the ROS 1 AudioBuffer's
    `channelMap` where naoqi_driver2's says `channel_map`)."""
    ref = fast_layouts()

    def kinds(fields: Any) -> str:
        return repr([desc for _name, desc in fields[1]]) if fields else ''
    from .cdr_fast import NESTED
    return name in ref and all(kinds(types.get(t)) == kinds(ref[t])
                               for t in (name, 'std_msgs/msg/Header', 'builtin_interfaces/msg/Time')
                               + NESTED.get(name, ()))


def _closure(msgtype: str, types: Mapping[str, Any], into: Set[str]) -> Optional[str]:
    """Adds `msgtype` and every type it refers to (that `types` defines) to `into`; returns the
    first one `types` lacks, or None. `into` is only extended when nothing is missing."""
    found: Set[str] = set()
    todo = [msgtype]
    while todo:
        name = todo.pop()
        if name in found or name in into:
            continue
        fields = types.get(name)
        if fields is None:
            return name
        found.add(name)
        todo.extend(_nested(fields))
    into.update(found)
    return None


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
