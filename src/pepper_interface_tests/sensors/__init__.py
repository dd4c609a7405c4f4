"""One module per sensor family; `check_class(family)` picks the Check for a sensor."""
import importlib
from typing import TYPE_CHECKING, Type

if TYPE_CHECKING:
    from .base import Check

_FAMILIES = {
    'range': ('range', 'RangeCheck'),
    'laser': ('laser', 'LaserCheck'),
    'joints': ('joints', 'JointsCheck'),
    'odometry': ('odometry', 'OdometryCheck'),
    'imu': ('imu', 'ImuCheck'),
    'speech': ('speech', 'SpeechCheck'),
    'camera': ('camera', 'CameraCheck'),
    'depth': ('depth', 'DepthCheck'),
    'audio': ('audio', 'AudioCheck'),
}


def check_class(family: str) -> Type['Check']:
    module, name = _FAMILIES[family]
    return getattr(importlib.import_module('.' + module, __name__), name)
