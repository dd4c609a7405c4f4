"""ROS message classes by type name, for decoding what a source delivers as raw bytes."""
from typing import TYPE_CHECKING, Optional, Type

if TYPE_CHECKING:
    import genpy


def message_class(type_name: str, definition: Optional[str] = None) -> Type['genpy.Message']:
    """The Python class of a ROS message type, e.g. 'sensor_msgs/Range'.

    A type whose package is not installed (naoqi_bridge_msgs/AudioBuffer from stock
    naoqi_driver, its touch events) is built from `definition`, the full text every ROS 1 connection header and
    every bag connection carries (naoqi_msgs.message_class_from_definition)."""
    if type_name.startswith('naoqi_driver/AudioCustomMsg'):
        type_name = 'pepper_interface_tests/AudioCustomMsg'
    pkg, name = type_name.split('/')
    try:
        module = __import__(pkg + '.msg', fromlist=[name])
        return getattr(module, name)
    except (ImportError, AttributeError):
        from . import naoqi_msgs
        if definition:
            return naoqi_msgs.message_class_from_definition(type_name, definition)
        if type_name in naoqi_msgs.DEFINITIONS:
            return naoqi_msgs.known_class(type_name)
        raise
