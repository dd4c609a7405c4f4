"""Message types of the NAOqi ROS stack that this package must read or publish without having
their packages installed.

Stock naoqi_driver publishes the microphones as `naoqi_bridge_msgs/AudioBuffer`
(ros-naoqi/naoqi_driver src/event/audio.cpp:179-180 fills `frequency` and `channelMap`;
the definition is ros-naoqi/naoqi_bridge_msgs msg/AudioBuffer.msg). naoqi_bridge_msgs is rarely
installed next to this package, and ROS 1 does not need it to be: every connection header
carries the full message definition, and a recorded bag keeps it too. So the class is generated
here from the definition text (genpy.dynamic), with the same md5sum as the real package's,
and a publisher or subscriber made with it interoperates with naoqi_driver's.
"""
from typing import Dict, Tuple, Type

import genpy
import genpy.dynamic

AUDIO_BUFFER_TYPE = 'naoqi_bridge_msgs/AudioBuffer'

# msg/AudioBuffer.msg of ros-naoqi/naoqi_bridge_msgs (master), comments dropped: the md5sum
# depends only on the constants, field types and names.
AUDIO_BUFFER_DEFINITION = """Header header
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
uint8[] channelMap
int16[] data
================================================================================
MSG: std_msgs/Header
uint32 seq
time stamp
string frame_id
"""

# Channel codes of AudioBuffer.channelMap -> this package's microphone names. Pepper's four
# microphones are at the top of the head, two at the rear and two at the front; naoqi_driver
# maps them as [3, 5, 0, 2] = rear left, rear right, front left, front right
# (src/event/audio.cpp:63-66, the Pepper branch of its channel map).
CHANNEL_NAMES = {0: 'frontLeft', 1: 'frontCenter', 2: 'frontRight', 3: 'rearLeft',
                 4: 'rearCenter', 5: 'rearRight', 6: 'surroundLeft', 7: 'surroundRight',
                 8: 'subwoofer', 9: 'lfe'}
PEPPER_CHANNEL_MAP = (3, 5, 0, 2)

_CLASSES: Dict[Tuple[str, str], Type[genpy.Message]] = {}


# The touch events of naoqi_driver (src/event/touch.cpp:246-248): msg/Bumper.msg, HandTouch.msg and
# HeadTouch.msg of ros-naoqi/naoqi_bridge_msgs (master), comments dropped. This package's own
# msg/Bumper.msg, HandTouch.msg and HeadTouch.msg have the same definitions (same md5sums).
TOUCH_DEFINITIONS = {
    'naoqi_bridge_msgs/Bumper': """uint8 bumper
uint8 state
uint8 right=0
uint8 left=1
uint8 back=2
uint8 stateReleased=0
uint8 statePressed=1
""",
    'naoqi_bridge_msgs/HandTouch': """uint8 hand
uint8 state
uint8 RIGHT_BACK=0
uint8 RIGHT_LEFT=1
uint8 RIGHT_RIGHT=2
uint8 LEFT_BACK=3
uint8 LEFT_LEFT=4
uint8 LEFT_RIGHT=5
uint8 stateReleased=0
uint8 statePressed=1
""",
    'naoqi_bridge_msgs/HeadTouch': """uint8 button
uint8 state
uint8 buttonFront=1
uint8 buttonMiddle=2
uint8 buttonRear=3
uint8 stateReleased=0
uint8 statePressed=1
""",
}

# What naoqi_driver's /joint_angles subscriber takes (ros-naoqi/naoqi_driver
# src/subscribers/teleop.cpp: setAngles, or changeAngles when relative is 1): msg/JointAnglesWithSpeed.msg
# of ros-naoqi/naoqi_bridge_msgs (master), comments dropped. This package's own
# msg/JointAnglesWithSpeed.msg has the same definition (same md5sum). A publisher made with this
# class has naoqi_driver's type name, so it connects to the real driver and to the emulator alike.
JOINT_ANGLES_TYPE = 'naoqi_bridge_msgs/JointAnglesWithSpeed'
JOINT_ANGLES_DEFINITION = """Header header
string[] joint_names
float32[] joint_angles
float32 speed
uint8 relative
================================================================================
MSG: std_msgs/Header
uint32 seq
time stamp
string frame_id
"""

# naoqi_driver's latched robot identity, /naoqi_driver/info (src/publishers/info.cpp:38
# advertises it latched; src/converters/info.cpp:83-88 fills `data`): msg/StringStamped.msg of
# ros-naoqi/naoqi_bridge_msgs (master). Read by sources/identity.py, published by the emulator.
STRING_STAMPED_TYPE = 'naoqi_bridge_msgs/StringStamped'
STRING_STAMPED_DEFINITION = """Header header
string data
================================================================================
MSG: std_msgs/Header
uint32 seq
time stamp
string frame_id
"""

# every naoqi_bridge_msgs type this package knows without the package installed
DEFINITIONS = dict(TOUCH_DEFINITIONS, **{AUDIO_BUFFER_TYPE: AUDIO_BUFFER_DEFINITION,
                                         JOINT_ANGLES_TYPE: JOINT_ANGLES_DEFINITION,
                                         STRING_STAMPED_TYPE: STRING_STAMPED_DEFINITION})


def message_class_from_definition(type_name: str, definition: str) -> Type[genpy.Message]:
    """A genpy message class for `type_name` built from its full definition text (as found in
    a connection header or a bag); cached per (type, definition)."""
    key = (type_name, definition)
    cls = _CLASSES.get(key)
    if cls is None:
        cls = _CLASSES[key] = genpy.dynamic.generate_dynamic(type_name, definition)[type_name]
    return cls


def known_class(type_name: str) -> Type[genpy.Message]:
    """The class of a naoqi_bridge_msgs type of DEFINITIONS; KeyError for any other type."""
    return message_class_from_definition(type_name, DEFINITIONS[type_name])


def audio_buffer_class() -> Type[genpy.Message]:
    """The naoqi_bridge_msgs/AudioBuffer class (same md5sum as the real package's)."""
    return message_class_from_definition(AUDIO_BUFFER_TYPE, AUDIO_BUFFER_DEFINITION)


def joint_angles_class() -> Type[genpy.Message]:
    """The naoqi_bridge_msgs/JointAnglesWithSpeed class (same md5sum as the real package's)."""
    return message_class_from_definition(JOINT_ANGLES_TYPE, JOINT_ANGLES_DEFINITION)
