"""The ROS 1 definition text of a ROS 2 message, as the CDR -> ROS 1 conversion writes it
(ros2types.py), and the ROS 2 releases whose standard types rosbags ships. A leaf: messages.py
builds a genpy class from it where no ROS 1 package is importable (a ROS 2 environment)."""
import functools
import re
from typing import Optional

from . import naoqi_msgs

# ROS 1 definitions this package already knows, used for the converted message instead of one
# generated from the ROS 2 definition (same wire layout, the field names the checks read)
ROS1_DEFINITIONS = {naoqi_msgs.AUDIO_BUFFER_TYPE: naoqi_msgs.AUDIO_BUFFER_DEFINITION}

# the standard types of the ROS 2 release a recording names (rosbag2 stores `ros_distro` from
# Humble's sqlite3 schema 3 and in metadata.yaml from version 8); naoqi_driver2 is released for
# Humble and later, so a recording that does not say is read with Humble's types. They differ:
# sensor_msgs/Range has a `variance` field only after Jazzy (rosbags' LATEST).
DISTROS = {'foxy': 'ROS2_FOXY', 'galactic': 'ROS2_GALACTIC', 'humble': 'ROS2_HUMBLE',
           'iron': 'ROS2_IRON', 'jazzy': 'ROS2_JAZZY', 'kilted': 'ROS2_KILTED',
           'lyrical': 'ROS2_LYRICAL', 'rolling': 'LATEST'}
DEFAULT_DISTRO = 'humble'


def ros1_text(ros2_generated: str) -> str:
    """rosbags writes the ROS 1 definition of a ROS 2 type with the ROS 2 Header (no seq); the
    bytes cdr_to_ros1 writes do carry seq, and so must the definition a class is built from."""
    return ros2_generated.replace('MSG: std_msgs/Header\ntime stamp\n',
                                  'MSG: std_msgs/Header\nuint32 seq\ntime stamp\n')


@functools.lru_cache(maxsize=None)
def ros1_definition(type_name: str, distro: Optional[str] = None) -> Optional[str]:
    """The ROS 1 definition text of a standard type ('sensor_msgs/Range') as the converted CDR
    bytes carry it (Header with seq), from rosbags' ROS 2 types of `distro`; None when unknown.
    Used where no ROS 1 message package is importable (a ROS 2 environment)."""
    from rosbags.typesys import Stores, get_typestore
    parts = type_name.split('/')
    if len(parts) != 2:
        return None
    ros2 = '%s/msg/%s' % tuple(parts)
    name = DISTROS.get((distro or '').strip().lower(), DISTROS[DEFAULT_DISTRO])
    store = get_typestore(getattr(Stores, name, Stores.ROS2_HUMBLE))
    if ros2 not in store.fielddefs:
        return None
    return ROS1_DEFINITIONS.get(type_name) or ros1_text(store.generate_msgdef(ros2, ros_version=1)[0])


def _snake(name: str) -> str:
    return re.sub(r'(?<=[a-z0-9])([A-Z])', r'_\1', name).lower()


def ros2_text(ros1: str) -> str:
    """The ROS 2 form of the top-level part of a ROS 1 definition, as naoqi_bridge_msgs2 writes
    its messages: `std_msgs/Header`, snake_case fields (channelMap -> channel_map), UPPER_CASE
    constants (buttonFront -> BUTTON_FRONT; its msg/HeadTouch.msg). Field order and types are
    unchanged, so the wire layout is the same."""
    out = []
    for line in ros1.split('=' * 80)[0].splitlines():
        text = line.split('#', 1)[0].strip()
        if not text:
            continue
        kind, rest = text.split(None, 1)
        if kind == 'Header':
            kind = 'std_msgs/Header'
        if '=' in rest:
            name, value = (part.strip() for part in rest.split('=', 1))
            out.append('%s %s=%s' % (kind, _snake(name).upper(), value))
        else:
            out.append('%s %s' % (kind, _snake(rest)))
    return '\n'.join(out) + '\n'
