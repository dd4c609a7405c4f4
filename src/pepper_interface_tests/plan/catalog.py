"""The sensor table: one row per sensor sensorTest knows.

Every part of the package looks sensors up here: their canonical name (the input-file name),
every spelling the original configuration files use, the ROS message type, the check family
that validates them, and where they exist. Behaviour is driven by this table, not by one copy
of the code per sensor.
"""
from collections import OrderedDict
from typing import Dict, NamedTuple, Optional, Tuple


class Sensor(NamedTuple):
    name: str                  # canonical name, as in sensorTestInput.ini
    title: str                 # heading in sensorTestOutput.dat ("BACK SONAR")
    aliases: Tuple[str, ...]   # other spellings found in the original files (matched case-insensitively)
    msg_type: str              # ROS message type, "pkg/Type"
    family: str                # check family (sensors/families.py): range, laser, camera, ... touch, health
    camera: Optional[str]      # camera group for --cameras: 'pepper', 'realsense' or None
    simulator: bool            # True when the Gazebo simulator provides this sensor
    video: Optional[str]       # file name of the recording, or None
    also: Tuple[str, ...] = ()   # other message types accepted on the topic, besides msg_type
    # the robot's topic when the topics file has no key for it (a file older than the sensor)
    driver_topic: Optional[str] = None
    # the option that adds this row to a run (never the input file): `--move` adds `motion`
    opt_in: Optional[str] = None


SENSORS: Dict[str, Sensor] = OrderedDict((s.name, s) for s in [
    Sensor('backSonar', 'BACK SONAR', ('BackSonar', 'sonarBack'), 'sensor_msgs/Range',
           'range', None, True, None),
    Sensor('frontSonar', 'FRONT SONAR', ('FrontSonar', 'sonarFront'), 'sensor_msgs/Range',
           'range', None, True, None),
    Sensor('bottomCamera', 'BOTTOM CAMERA', ('BottomCamera',), 'sensor_msgs/Image',
           'camera', 'pepper', True, 'bottomCameraOutput.mp4'),
    Sensor('frontCamera', 'FRONT CAMERA', ('FrontCamera',), 'sensor_msgs/Image',
           'camera', 'pepper', True, 'frontCameraOutput.mp4'),
    Sensor('realsenseRGBCamera', 'REALSENSE RGB CAMERA',
           ('RealSenseCameraRGB', 'realsenseCameraRGB', 'realsenseRGB'), 'sensor_msgs/Image',
           'camera', 'realsense', False, 'realsenseRGBOutput.mp4'),
    Sensor('realsenseDepthCamera', 'REALSENSE DEPTH CAMERA',
           ('RealSenseCameraDepth', 'realsenseCameraDepth', 'realsenseDepth'), 'sensor_msgs/Image',
           'depth', 'realsense', False, 'realsenseDepthOutput.mp4'),
    Sensor('depthCamera', 'DEPTH CAMERA', ('DepthCamera',), 'sensor_msgs/Image',
           'depth', 'pepper', True, 'depthCameraOutput.mp4'),
    Sensor('stereoCamera', 'STEREO CAMERA', ('StereoCamera',), 'sensor_msgs/Image',
           'camera', 'pepper', False, 'stereoCameraOutput.mp4'),
    Sensor('laser', 'LASER', ('Laser', 'laserSensor'), 'sensor_msgs/LaserScan',
           'laser', None, True, None),
    Sensor('microphone', 'MICROPHONE', ('Microphone', 'mic', 'audio'),
           'pepper_interface_tests/AudioCustomMsg', 'audio', None, False, None,
           ('naoqi_driver/AudioCustomMsg', 'naoqi_bridge_msgs/AudioBuffer')),
    Sensor('jointState', 'JOINT STATE', ('JointState', 'jointStates', 'joint_states'),
           'sensor_msgs/JointState', 'joints', None, True, None),
    Sensor('odometry', 'ODOMETRY', ('Odometry', 'odom'), 'nav_msgs/Odometry',
           'odometry', None, True, None),
    Sensor('imu', 'IMU', ('IMU', 'imuBase'), 'sensor_msgs/Imu', 'imu', None, False, None),
    Sensor('speech', 'SPEECH', ('Speech', 'speaker', 'loudspeaker'), 'std_msgs/String',
           'speech', None, False, None),
    # naoqi_driver's touch events (src/naoqi_driver.cpp:838-894): naoqi_bridge_msgs types, read
    # from the definition their connection carries (sources/naoqi_msgs.py); this package's own
    # copies (msg/, same md5sums) are accepted too
    # (topics in the driver's private namespace, NodeHandle("~"): naoqi_driver.cpp:991)
    Sensor('headTouch', 'HEAD TOUCH', ('HeadTouch', 'head_touch', 'tactile'), 'naoqi_bridge_msgs/HeadTouch',
           'touch', None, False, None, ('pepper_interface_tests/HeadTouch',), '/naoqi_driver/head_touch'),
    Sensor('handTouch', 'HAND TOUCH', ('HandTouch', 'hand_touch'), 'naoqi_bridge_msgs/HandTouch',
           'touch', None, False, None, ('pepper_interface_tests/HandTouch',), '/naoqi_driver/hand_touch'),
    Sensor('bumper', 'BUMPER', ('Bumper', 'bumpers'), 'naoqi_bridge_msgs/Bumper',
           'touch', None, False, None, ('pepper_interface_tests/Bumper',), '/naoqi_driver/bumper'),
    # naoqi_driver's own health on /diagnostics (src/converters/diagnostics.cpp; naoqi_driver.cpp:652)
    Sensor('robotHealth', 'ROBOT HEALTH', ('RobotHealth', 'health', 'diagnostics'),
           'diagnostic_msgs/DiagnosticArray', 'health', None, False, None, (), '/diagnostics'),
    # the robot's transform tree on /tf (sensors/tf.py, sensors/tree.py): naoqi_driver publishes
    # it with every joint state (src/converters/joint_state.cpp:147-201)
    Sensor('tf', 'TRANSFORMS', ('TF', 'transforms', 'tfTree'), 'tf2_msgs/TFMessage', 'tf', None,
           True, None, (), '/tf'),
    # the motion check (--move, sensors/motion.py, motion/): its topic is the command it sends,
    # naoqi_driver's bounded moveTo (src/subscribers/moveto.cpp; naoqi_driver.cpp:938)
    Sensor('motion', 'MOTION', ('Motion', 'move'), 'geometry_msgs/PoseStamped', 'motion', None,
           False, None, (), '/move_base_simple/goal', opt_in='--move'),
])

# Keys of the topics files that belong to the actuator test; sensorTest ignores them.
ACTUATOR_KEYS = ('head', 'rarm', 'larm', 'rhand', 'lhand', 'leg', 'wheels')

# Message types accepted on the microphone topic (`also` of its row): AudioCustomMsg (the same
# definition, same md5sum, generated by the CSSR4Africa naoqi_driver fork and by this package)
# and stock naoqi_driver's naoqi_bridge_msgs/AudioBuffer (ros-naoqi/naoqi_driver
# src/event/audio.cpp:74), decoded from the definition its connection carries (naoqi_msgs.py),
# the package not needed.

# Why a healthy robot may have no publisher for a sensor, added to the "no publisher" reason.
# naoqi_driver registers the stereo camera only on a stereo head (Pepper 1.8: ALMotion reports
# "CameraStereo"); a Pepper 1.7 head has an Xtion depth camera and no stereo pair
# (ros-naoqi/naoqi_driver src/naoqi_driver.cpp:733-750, src/helpers/driver_helpers.cpp:373-394).
NO_PUBLISHER_HINTS = {
    'stereoCamera': 'a Pepper head with an Xtion depth camera (Pepper 1.7) has no stereo camera: '
                    'naoqi_driver publishes it on a stereo head only; on such a robot set '
                    'stereoCamera false in the input file',
    # naoqi_driver.cpp:603-605 (converters.bumper / touch_hand / touch_head); the CSSR4Africa
    # fork's share/boot_config.json sets all three "enabled": false, stock's true
    'headTouch': 'naoqi_driver publishes the head\'s touch events only with converters touch_head '
                 'enabled in its share/boot_config.json (the CSSR4Africa fork disables it): enable it '
                 'and restart the driver, or set headTouch false in the input file',
    'handTouch': 'naoqi_driver publishes the hands\' touch events only with converters touch_hand '
                 'enabled in its share/boot_config.json (the CSSR4Africa fork disables it): enable it '
                 'and restart the driver, or set handTouch false in the input file',
    'bumper': 'naoqi_driver publishes the bumpers\' events only with converters bumper enabled in '
              'its share/boot_config.json (the CSSR4Africa fork disables it): enable it and restart '
              'the driver, or set bumper false in the input file',
}

# A sensor the robot's head variant does not have: SKIPPED (not FAILED) when its topic is
# absent and the robot shows the other head. naoqi_driver asks ALMotion.getSensorNames() for
# "CameraStereo" (ros-naoqi/naoqi_driver src/helpers/driver_helpers.cpp:373-394, isDepthStereo,
# read at src/naoqi_driver.cpp:128); without it (Pepper 1.7, ASUS Xtion head) it registers
# no stereo camera (naoqi_driver.cpp:733-747: `has_stereo && camera_stereo_enabled`) and
# publishes the Xtion's infrared image on camera/ir/image_raw instead (naoqi_driver.cpp:
# 607-613 and 753-762; "ir_camera" enabled in share/boot_config.json). A topic on camera/ir
# is the driver's own sign of an Xtion head.
# sensor -> (its topic's part, the sign topic's part replacing it, the driver's default sign
# topic, the reason)
HEAD_VARIANT_SKIPS = {
    'stereoCamera': ('/camera/stereo/', '/camera/ir/', '/naoqi_driver/camera/ir/image_raw',
                     'this robot has an Xtion head (Pepper 1.7): naoqi_driver publishes its '
                     'infrared camera on %s and, without "CameraStereo" in ALMotion\'s sensor '
                     'names, no stereo camera; the IR camera is the one to look at on this head'),
}


def head_sign_topic(name: str, topic: Optional[str]) -> Optional[str]:
    """The topic whose presence shows that the robot's head has no `name` sensor (the IR
    camera of an Xtion head for stereoCamera), next to `topic` when it follows the driver's
    layout; None for a sensor every head has."""
    rule = HEAD_VARIANT_SKIPS.get(name)
    if rule is None:
        return None
    part, sign, default, _ = rule
    if topic and part in topic:
        return topic.replace(part, sign, 1)
    return default


def head_skip_reason(name: str, sign_topic: str) -> str:
    return HEAD_VARIANT_SKIPS[name][3] % sign_topic


# Why a sensor is SKIPPED in the simulator, where it has a known reason (default: "not
# available in the simulator"). awesomebytes/pepper_virtual (simulation_that_works) has no
# touch, bumper or diagnostics publisher (the words appear only as frame names in
# pepper_gazebo_plugin/config/pepper_sensors.rviz), and the model's Gazebo bumper sensors are
# commented out (awesomebytes/pepper_robot pepperGazeboCPU.xacro:578-652; docs/drivers.md).
_NOT_SIMULATED = 'the Gazebo simulator (pepper_virtual) publishes no %s: its source has no such publisher'
SIMULATOR_SKIP = {
    'headTouch': _NOT_SIMULATED % 'head touch events',
    'handTouch': _NOT_SIMULATED % 'hand touch events',
    'bumper': _NOT_SIMULATED % 'bumper events' + ' (the model\'s Gazebo bumper sensors are commented out)',
    'robotHealth': _NOT_SIMULATED % 'naoqi_driver diagnostics (joint temperatures, battery) on /diagnostics',
    # awesomebytes/pepper_virtual simulation_that_works README.md:52 (/pepper/cmd_vel); the goal
    # topic appears only as an rviz tool (pepper_gazebo_plugin/config/pepper_sensors.rviz:713)
    'motion': 'the Gazebo simulator (pepper_virtual) takes only /pepper/cmd_vel: no '
              '/move_base_simple/goal (bounded moveTo) and no /joint_angles subscriber, so --move has '
              'nothing bounded to command',
}


def simulator_skip_reason(name: str) -> str:
    """Why sensor `name`, absent from the simulator, is SKIPPED there."""
    return SIMULATOR_SKIP.get(name, 'not available in the simulator')


_LOOKUP: Dict[str, str] = {}
for _s in SENSORS.values():
    for _spelling in (_s.name,) + _s.aliases:
        _LOOKUP[_spelling.lower()] = _s.name


def canonical(spelling: str) -> Optional[str]:
    """Canonical sensor name for any known spelling (case-insensitive), or None."""
    return _LOOKUP.get(spelling.strip().lower())


def is_actuator_key(key: str) -> bool:
    return key.strip().lower() in ACTUATOR_KEYS


def accepted_types(sensor: Sensor) -> Tuple[str, ...]:
    """Every message type accepted on the sensor's topic, its own first."""
    return (sensor.msg_type,) + sensor.also


def expected_types(sensor: Sensor) -> str:
    """The accepted type names of a sensor, as text for reasons ("a or b")."""
    return ' or '.join(accepted_types(sensor))


def accepts_type(sensor: Sensor, type_name: str) -> bool:
    """True when a topic of ROS type `type_name` is what `sensor` expects."""
    return type_name in accepted_types(sensor)
