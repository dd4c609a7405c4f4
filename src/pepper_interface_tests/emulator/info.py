"""The robot's identity as naoqi_driver publishes it: the latched `/naoqi_driver/info`.

naoqi_driver reads these ALMemory keys once (ros-naoqi/naoqi_driver src/converters/info.cpp:40-56,
in this order, the last five on Pepper only), joins them as "key: value ; key: value"
(info.cpp:83-88) and publishes that once on a latched naoqi_bridge_msgs/StringStamped
(src/publishers/info.cpp:38; src/naoqi_driver.cpp:617-633). The robot profiles publish the same
message; the fake NAOqi (fake_memory.py) answers the same keys with the same values, so the
real driver run against it says the same. The chest board's BodyId is the robot's serial
number: `~robot_id` sets it, so a test can emulate two different robots.
"""
import re
from typing import Dict, List

from ..plan.settings import ConfigError
from .qos2 import INFO_DEPTH

INFO_TOPIC = '/naoqi_driver/info'
DEFAULT_BODY_ID = 'AP990370B0000000'     # the shape of a Pepper serial: AP9903 + 70B + 7 digits

INFO_KEYS: List[str] = [
    'RobotConfig/Head/FullHeadId', 'Device/DeviceList/ChestBoard/BodyId', 'RobotConfig/Body/Type',
    'RobotConfig/Body/BaseVersion', 'RobotConfig/Body/Device/LeftArm/Version',
    'RobotConfig/Body/Device/RightArm/Version', 'RobotConfig/Body/Device/Hand/Left/Version',
    'RobotConfig/Body/Version', 'RobotConfig/Body/SoftwareRequirement', 'RobotConfig/Body/Device/Legs/Version',
    'Device/DeviceList/BatteryFuelGauge/SerialNumber', 'Device/DeviceList/BatteryFuelGauge/FirmwareVersion',
    'RobotConfig/Body/Device/Platform/Version', 'RobotConfig/Body/Device/Brakes/Version',
    'RobotConfig/Body/Device/Wheel/Version']


def check_body_id(value: object) -> str:
    """A usable serial number: letters, digits, '-' or '_' (the message separates with ' ; ');
    'none' ('' returned): no info topic, as a driver whose boot_config.json disables
    converters.info (ros-naoqi/naoqi_driver share/boot_config.json:41-44, src/naoqi_driver.cpp:544)."""
    text = str(value if value is not None else '').strip()
    if text.lower() in ('none', 'off', 'false'):
        return ''
    if not re.fullmatch(r'[A-Za-z0-9_-]{1,64}', text):
        raise ConfigError('~robot_id "%s" is not a robot serial number' % value,
                          fix='give letters and digits, e.g. %s, or none (no info topic)' % DEFAULT_BODY_ID)
    return text


def identity_values(head: str, body_id: str = DEFAULT_BODY_ID) -> Dict[str, str]:
    """ALMemory's identity keys of an emulated Pepper (`head`: stereo = 1.8a, xtion = 1.7)."""
    return {
        'RobotConfig/Body/Type': 'juliette',         # Pepper's body type (driver_helpers.cpp:61)
        'RobotConfig/Body/BaseVersion': '1.8a' if head == 'stereo' else '1.7',
        'RobotConfig/Head/FullHeadId': 'AP990495A0000000',
        'Device/DeviceList/ChestBoard/BodyId': body_id,
        'RobotConfig/Body/Version': '1.8a', 'RobotConfig/Body/SoftwareRequirement': '2.5',
        'RobotConfig/Body/Device/LeftArm/Version': '1.8a',
        'RobotConfig/Body/Device/RightArm/Version': '1.8a',
        'RobotConfig/Body/Device/Hand/Left/Version': '1.8a',
        'RobotConfig/Body/Device/Legs/Version': '1.8a',
        'Device/DeviceList/BatteryFuelGauge/SerialNumber': 'FAKE0001',
        'Device/DeviceList/BatteryFuelGauge/FirmwareVersion': '1.0',
        'RobotConfig/Body/Device/Platform/Version': '1.8a',
        'RobotConfig/Body/Device/Brakes/Version': '1.8a',
        'RobotConfig/Body/Device/Wheel/Version': '1.8a',
    }


def info_text(values: Dict[str, str]) -> str:
    """The message's data, as info.cpp:83-88 joins it."""
    return ' ; '.join('%s: %s' % (k, values.get(k, '')) for k in INFO_KEYS)


INFO_TOPIC_ROS2 = '/info'


class InfoPublisher:
    """The info message, published once (as the driver does): latched on ROS 1; on ROS 2 on
    naoqi_driver2's `/info`, volatile and keep-last 10 as its publisher is (src/publishers/basic.hpp:72,
    whatever its comment at src/naoqi_driver.cpp:675-681 says), so a node started later never gets it."""

    def __init__(self, head: str, body_id: str) -> None:
        from .. import rosapi
        from ..sources.naoqi_msgs import STRING_STAMPED_TYPE, known_class
        cls = known_class(STRING_STAMPED_TYPE)
        if rosapi.version() == 2:
            self.pub = rosapi.publisher(INFO_TOPIC_ROS2, STRING_STAMPED_TYPE, queue_size=INFO_DEPTH, cls=cls)
        else:
            self.pub = rosapi.publisher(INFO_TOPIC, STRING_STAMPED_TYPE, queue_size=1, latch=True, cls=cls)
        msg = cls()
        msg.header.stamp = rosapi.now()
        msg.data = info_text(identity_values(head, body_id))
        self.pub.publish(msg)

    def close(self) -> None:
        self.pub.unregister()
