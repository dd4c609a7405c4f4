"""ROS message classes by type name, for decoding what a source delivers as raw bytes."""
import os
from typing import TYPE_CHECKING, Dict, Optional, Tuple, Type

if TYPE_CHECKING:
    import genpy


# (type name, definition) -> class: the witnesses ask once per message (a module import with a
# from-list each time cost 20 us, 3 % of reading a recording); a process's classes never change
_CLASSES: Dict[Tuple[str, Optional[str]], Type['genpy.Message']] = {}


def message_class(type_name: str, definition: Optional[str] = None) -> Type['genpy.Message']:
    """The Python class of a ROS message type, e.g. 'sensor_msgs/Range'.

    A type whose package is not installed (naoqi_bridge_msgs/AudioBuffer from stock
    naoqi_driver, its touch events) is built from `definition`, the full text every ROS 1 connection header and
    every bag connection carries (naoqi_msgs.message_class_from_definition)."""
    key = (type_name, definition)
    cls = _CLASSES.get(key)
    if cls is None:
        cls = _CLASSES[key] = _message_class(type_name, definition)
    return cls


def _message_class(type_name: str, definition: Optional[str]) -> Type['genpy.Message']:
    if type_name.startswith('naoqi_driver/AudioCustomMsg'):
        type_name = 'pepper_interface_tests/AudioCustomMsg'
    pkg, name = type_name.split('/')
    try:
        if os.environ.get('ROS_VERSION', '').strip() == '2':
            # ROS 2: a ROS 1 (genpy) package on the path (Debian's python3-tf2-msgs) imports
            # its nested types by name, and finds ROS 2's: built from the definition instead
            raise ImportError(type_name)
        module = __import__(pkg + '.msg', fromlist=[name])
        cls = getattr(module, name)
        if hasattr(cls, '_md5sum'):
            return cls
        # a ROS 2 (rosidl) class of the same name, first on the path in a ROS 2 environment:
        # the checks read ROS 1 wire bytes, so a genpy class is built from the definition
        raise ImportError(type_name)
    except (ImportError, AttributeError):
        from . import naoqi_msgs
        if definition:
            return naoqi_msgs.message_class_from_definition(type_name, definition)
        if type_name in naoqi_msgs.DEFINITIONS:
            return naoqi_msgs.known_class(type_name)
        from .ros2defs import ros1_definition
        text = ros1_definition(type_name) or _own_definition(type_name)
        if text:
            return naoqi_msgs.message_class_from_definition(type_name, text)
        raise


def _own_definition(type_name: str) -> Optional[str]:
    """The text of this package's own msg/<Name>.msg (AudioCustomMsg: plain arrays, no nested
    type), for a ROS 2 environment where pepper_interface_tests.msg is rosidl's."""
    from ..plan.settings import package_dir
    pkg, name = type_name.split('/')
    if pkg != 'pepper_interface_tests':
        return None
    try:
        with open(os.path.join(package_dir(), 'msg', name + '.msg'), encoding='utf-8') as f:
            return f.read()
    except OSError:
        return None
