"""The declaration: one row per sensor sensorTest knows, with what each driver publishes.

A row holds the sensor's own facts (canonical name, every old spelling, message type, check
family, camera group, video file, whether the input file turns it on) and one `Stream` per
driver that publishes it: topic, nominal rate, frame id, image encoding and size, field of
view, which robot heads have it, and the driver's source (file:line). Everything else that
needs those facts derives them from here (plan/catalog.py is the lookups over these rows):
the topics files' and the input file's sensor lines (tools/gen_sensors.py, `make docs`), the
emulator's streams for each profile (emulator/profiles.py), the head and simulator skip
rules (catalog.py), the motion check's head cameras (motion/witnesses.py), the tests' lists
and the tables in docs/ (generated, test/docs/test_generated.py keeps them current).

Adding a sensor to an existing family is one row here (docs/architecture.md, "Adding a
sensor to a family"); file:line references are to ros-naoqi/naoqi_driver (aed1b87) unless
another source is named.
"""
import math
from collections import OrderedDict
from typing import Dict, NamedTuple, Optional, Tuple

# The drivers whose publications are declared; the names of config/sensorExpectations.yaml's
# `drivers:` profiles. naoqi_driver: stock ros-naoqi/naoqi_driver (the emulator's robot-stock);
# cssr4africa_naoqi_driver: the CSSR4Africa fork (the emulator's robot); pepper_virtual: the
# Gazebo simulator CSSR4Africa installs (the emulator's simulator); realsense2_camera: the
# RealSense D435i on the robot (ros1-legacy).
# naoqi_driver2: ros-naoqi/naoqi_driver2 (ROS 2; its streams: DRIVER2_TOPICS below).
STOCK, FORK, SIMULATOR, REALSENSE = ('naoqi_driver', 'cssr4africa_naoqi_driver', 'pepper_virtual',
                                     'realsense2_camera')
DRIVER2 = 'naoqi_driver2'
NAOQI = (STOCK, FORK)
DRIVERS = (STOCK, FORK, SIMULATOR, REALSENSE, DRIVER2)
# the drivers of each platform (plan/settings.py PLATFORMS)
PLATFORM_DRIVERS = {'robot': (STOCK, FORK, REALSENSE), 'simulator': (SIMULATOR,)}
# the drivers of data/naoqi_driver2Topics.dat (sensorTest's and the emulator's default on ROS 2):
# naoqi_driver2, and the RealSense lines as the ROS 1 wrapper names them
ROS2_DRIVERS = (DRIVER2, REALSENSE)


class Head(NamedTuple):
    """A variant of Pepper's head. naoqi_driver asks ALMotion.getSensorNames() for
    "CameraStereo" (src/helpers/driver_helpers.cpp:373-394, isDepthStereo, read at
    src/naoqi_driver.cpp:128): with it (Pepper 1.8) the stereo head, without it (Pepper 1.7)
    the ASUS Xtion head."""
    title: str          # "an Xtion head (Pepper 1.7)"
    sign_part: str      # the part of a topic that only this head has (its sign)
    sign_topic: str     # the driver's default topic that shows this head
    shows: str          # what the driver publishes on this head, said in a skip reason (%s: the sign)


HEADS: Dict[str, Head] = OrderedDict([
    # naoqi_driver.cpp:733-750: the stereo camera only `has_stereo && camera_stereo_enabled`;
    # :610-611: on a stereo head ir_camera is disabled
    ('stereo', Head('a stereo head (Pepper 1.8)', '/camera/stereo/', '/naoqi_driver/camera/stereo/image_raw',
                    'naoqi_driver publishes its stereo camera on %s and, with "CameraStereo" in '
                    'ALMotion\'s sensor names, no infrared camera (naoqi_driver.cpp:610-611)')),
    # naoqi_driver.cpp:753-762: the infrared camera, "ir_camera" enabled in share/boot_config.json
    ('xtion', Head('an Xtion head (Pepper 1.7)', '/camera/ir/', '/naoqi_driver/camera/ir/image_raw',
                   'naoqi_driver publishes its infrared camera on %s and, without "CameraStereo" in '
                   'ALMotion\'s sensor names, no stereo camera; the IR camera is the one to look at '
                   'on this head')),
])


class Stream(NamedTuple):
    """What one or more drivers publish for a sensor (the same facts for each driver named)."""
    drivers: Tuple[str, ...]
    topic: str
    rate: float = 0.0               # nominal Hz as the driver is configured; 0: events
    frame: str = ''                 # header.frame_id ('' none)
    encoding: str = ''              # image encoding
    size: Tuple[int, int] = (0, 0)  # image width, height
    heads: Tuple[str, ...] = ()     # the heads that have it (HEADS); () every head
    hfov: float = 0.0               # a camera's horizontal field of view, rad
    msg_type: str = ''              # when not the sensor's own
    enabled: bool = True            # False: the driver's default configuration turns it off
    source: str = ''                # where the driver says so


class Sensor(NamedTuple):
    name: str                  # canonical name, as in sensorTestInput.ini
    title: str                 # heading in sensorTestOutput.dat ("BACK SONAR")
    aliases: Tuple[str, ...]   # other spellings found in the original files (matched case-insensitively)
    msg_type: str              # ROS message type, "pkg/Type"
    family: str                # check family (sensors/families.py): range, laser, camera, ... touch, health
    camera: Optional[str] = None    # camera group for --cameras: 'pepper', 'realsense' or None
    video: Optional[str] = None     # file name of the recording, or None
    also: Tuple[str, ...] = ()      # other message types accepted on the topic, besides msg_type
    # the robot's topic when the topics file has no key for it (a file older than the sensor)
    driver_topic: Optional[str] = None
    # the option that adds this row to a run (never the input file): `--move` adds `motion`
    opt_in: Optional[str] = None
    streams: Tuple[Stream, ...] = ()
    on: bool = True            # its line in the package's sensorTestInput.ini: true or false

    @property
    def simulator(self) -> bool:
        """True when the Gazebo simulator provides this sensor."""
        return any(SIMULATOR in s.drivers for s in self.streams)

    def stream(self, driver: str, head: Optional[str] = None) -> Optional[Stream]:
        """What `driver` publishes for this sensor on `head` (None: any head), or None."""
        for s in self.streams:
            if driver in s.drivers and (head is None or not s.heads or head in s.heads):
                return s
        return None

    @property
    def heads(self) -> Tuple[str, ...]:
        """The heads on which naoqi_driver publishes it (every head when not head-bound)."""
        found = [h for s in self.streams if STOCK in s.drivers for h in (s.heads or tuple(HEADS))]
        return tuple(h for h in HEADS if h in found) or tuple(HEADS)


def _sonar(side: str, sim_topic: str) -> Tuple[Stream, ...]:
    return (Stream(NAOQI, '/naoqi_driver/sonar/%s' % side.lower(), 10.0, 'Sonar%s_frame' % side,
                   source='src/converters/sonar.cpp:64-72; share/boot_config.json "sonar" 10 Hz'),
            Stream((SIMULATOR,), sim_topic, 20.0, 'Sonar%s_frame' % side,
                   source='awesomebytes/pepper_robot pepperGazeboCPU.xacro:658-736 (20 Hz)'))


def _head_camera(part: str, frame: str, sim: bool) -> Tuple[Stream, ...]:
    cite = 'src/converters/camera.cpp:193-205, 286-289 (rgb8); boot_config.json 10 fps, resolution '
    topic = '/naoqi_driver/camera/%s/image_raw' % part
    out: Tuple[Stream, ...] = (
        Stream((STOCK,), topic, 10.0, frame, 'rgb8', (320, 240), hfov=0.9826, source=cite + '1 (QVGA)'),
        Stream((FORK,), topic, 10.0, frame, 'rgb8', (640, 480), hfov=0.9826,
               source='cssr4africa/naoqi_driver ' + cite + '2 (VGA)'))
    if sim:
        out += (Stream((SIMULATOR,), '/pepper/camera/%s/image_raw' % part, 5.0, frame, 'rgb8', (640, 480),
                       hfov=1.0, source='pepperGazeboCPU.xacro:453-524 (R8G8B8 640x480, update_rate 5)'),)
    return out


_DEPTH = 'src/converters/camera.cpp:194, 207-213 (16UC1 mm); '
_RS = 'realsense2_camera (ros1-legacy) base_realsense_node.cpp'

SENSORS: Dict[str, Sensor] = OrderedDict((s.name, s) for s in [
    Sensor('backSonar', 'BACK SONAR', ('BackSonar', 'sonarBack'), 'sensor_msgs/Range', 'range',
           streams=_sonar('Back', '/pepper/sonar_back')),
    Sensor('frontSonar', 'FRONT SONAR', ('FrontSonar', 'sonarFront'), 'sensor_msgs/Range', 'range',
           streams=_sonar('Front', '/pepper/sonar_front')),
    Sensor('bottomCamera', 'BOTTOM CAMERA', ('BottomCamera',), 'sensor_msgs/Image', 'camera', 'pepper',
           'bottomCameraOutput.mp4', streams=_head_camera('bottom', 'CameraBottom_optical_frame', True)),
    Sensor('frontCamera', 'FRONT CAMERA', ('FrontCamera',), 'sensor_msgs/Image', 'camera', 'pepper',
           'frontCameraOutput.mp4', streams=_head_camera('front', 'CameraTop_optical_frame', True)),
    Sensor('realsenseRGBCamera', 'REALSENSE RGB CAMERA',
           ('RealSenseCameraRGB', 'realsenseCameraRGB', 'realsenseRGB'), 'sensor_msgs/Image', 'camera',
           'realsense', 'realsenseRGBOutput.mp4', on=False, streams=(
               Stream((REALSENSE,), '/camera/color/image_raw', 15.0, 'camera_color_optical_frame', 'rgb8',
                      (640, 480), hfov=1.2043, source=_RS + ':116 (RGB8); 640x480 at 15 fps as the robot '
                                                        'launches it (docs/drivers.md)'),)),
    Sensor('realsenseDepthCamera', 'REALSENSE DEPTH CAMERA',
           ('RealSenseCameraDepth', 'realsenseCameraDepth', 'realsenseDepth'), 'sensor_msgs/Image', 'depth',
           'realsense', 'realsenseDepthOutput.mp4', on=False, streams=(
               Stream((REALSENSE,), '/camera/aligned_depth_to_color/image_raw', 15.0,
                      'camera_color_optical_frame', '16UC1', (640, 480), hfov=1.2043,
                      source=_RS + ':95-96 (16UC1), :989 (aligned_depth_to_color), :1918 (the colour '
                                   'optical frame)'),)),
    Sensor('depthCamera', 'DEPTH CAMERA', ('DepthCamera',), 'sensor_msgs/Image', 'depth', 'pepper',
           'depthCameraOutput.mp4', streams=(
               # depth from the stereo pair: stereo_resolution 9 = kQ720p 640x360 in both
               # boot_config.json files (src/tools/alvisiondefinitions.h:54)
               Stream(NAOQI, '/naoqi_driver/camera/depth/image_raw', 10.0, 'CameraDepth_optical_frame',
                      '16UC1', (640, 360), ('stereo',), 1.0123,
                      source=_DEPTH + 'stereo_resolution 9 (640x360)'),
               # the Xtion: xtion_resolution 1 (QVGA) in stock share/boot_config.json, 2 (VGA) in the fork's
               Stream((STOCK,), '/naoqi_driver/camera/depth/image_raw', 10.0, 'CameraDepth_optical_frame',
                      '16UC1', (320, 240), ('xtion',), 1.0123, source=_DEPTH + 'xtion_resolution 1 (QVGA)'),
               Stream((FORK,), '/naoqi_driver/camera/depth/image_raw', 10.0, 'CameraDepth_optical_frame',
                      '16UC1', (640, 480), ('xtion',), 1.0123, source=_DEPTH + 'xtion_resolution 2 (VGA)'),
               Stream((SIMULATOR,), '/pepper/camera/depth/image_raw', 30.0, 'CameraDepth_optical_frame',
                      '16UC1', (320, 240), hfov=math.radians(58.0),
                      source='pepperGazeboCPU.xacro:528-575 (openni_kinect 320x240, update_rate 30, '
                             'useDepth16UC1Format)'))),
    Sensor('stereoCamera', 'STEREO CAMERA', ('StereoCamera',), 'sensor_msgs/Image', 'camera', 'pepper',
           'stereoCameraOutput.mp4', streams=(
               Stream(NAOQI, '/naoqi_driver/camera/stereo/image_raw', 10.0, 'CameraDepth_optical_frame',
                      'rgb8', (640, 180), ('stereo',), 1.0472,
                      source='src/naoqi_driver.cpp:733-750 (a stereo head only); kQQ720px2 640x180'),)),
    # the Xtion head's infrared camera: ir_camera resolution 1 (QVGA), 10 fps in both drivers'
    # share/boot_config.json; off on a stereo head. naoqi_driver2 publishes it alike
    # (ros-naoqi/naoqi_driver2 10c4ca9 src/naoqi_driver.cpp:640-643, 667, 810-820)
    Sensor('irCamera', 'IR CAMERA', ('IRCamera', 'infraredCamera', 'InfraredCamera', 'ir'), 'sensor_msgs/Image',
           'camera', 'pepper', 'irCameraOutput.mp4', streams=(
               Stream(NAOQI, '/naoqi_driver/camera/ir/image_raw', 10.0, 'CameraDepth_optical_frame', '16UC1',
                      (320, 240), ('xtion',), 1.0123,
                      source='src/naoqi_driver.cpp:584-587 (ir_camera QVGA, 10 fps), :610-611 (off on a stereo '
                             'head), :753-762 (camera/ir/image_raw); src/converters/camera.cpp:215-224 (16UC1, '
                             'CameraDepth_optical_frame)'),)),
    Sensor('laser', 'LASER', ('Laser', 'laserSensor'), 'sensor_msgs/LaserScan', 'laser', streams=(
        Stream(NAOQI, '/naoqi_driver/laser', 10.0, 'base_footprint',
               source='src/converters/laser.cpp:213-237; boot_config.json "laser" 10 Hz'),
        Stream((SIMULATOR,), '/pepper/laser_2', 6.25, 'base_footprint',
               source='pepper_virtual laser_publisher.py:386-395; pepperGazeboCPU.xacro:778-871'))),
    Sensor('microphone', 'MICROPHONE', ('Microphone', 'mic', 'audio'),
           'pepper_interface_tests/AudioCustomMsg', 'audio',
           also=('naoqi_driver/AudioCustomMsg', 'naoqi_bridge_msgs/AudioBuffer'), streams=(
               # one message per NAOqi buffer: the rate is 48000 / samples per buffer
               Stream((STOCK,), '/naoqi_driver/audio', msg_type='naoqi_bridge_msgs/AudioBuffer',
                      source='src/event/audio.cpp:62-66, 107-113, 177-186'),
               Stream((FORK,), '/naoqi_driver/audio',
                      source='the audio bridge (naoqiAudio + naoqiAudioPublisher; '
                             'cssr4africa/naoqi_driver scripts/naoqiAudioPublisher.py:15)'))),
    Sensor('jointState', 'JOINT STATE', ('JointState', 'jointStates', 'joint_states'),
           'sensor_msgs/JointState', 'joints', streams=(
               Stream(NAOQI, '/joint_states', 50.0,
                      source='src/converters/joint_state.cpp:99; boot_config.json "joint_states" 50 Hz'),
               Stream((SIMULATOR,), '/joint_states', 50.0,
                      source='pepper_virtual pepper_control/config/pepper_trajectory_control.yaml:3-5'))),
    Sensor('odometry', 'ODOMETRY', ('Odometry', 'odom'), 'nav_msgs/Odometry', 'odometry', streams=(
        Stream(NAOQI, '/naoqi_driver/odom', 15.0, 'odom', source='src/converters/odom.cpp:78-80; '
                                                                 'boot_config.json "odom" 15 Hz'),
        Stream((SIMULATOR,), '/pepper/odom', 20.0, 'odom', source='pepperGazeboCPU.xacro:741-765'))),
    Sensor('imu', 'IMU', ('IMU', 'imuBase'), 'sensor_msgs/Imu', 'imu', streams=(
        Stream(NAOQI, '/naoqi_driver/imu/base', 10.0, 'base_footprint',
               source='src/converters/imu.cpp:45-70; boot_config.json 10 Hz'),)),
    # not published: the driver's subscriber (naoqi_driver.cpp, the speech subscriber)
    Sensor('speech', 'SPEECH', ('Speech', 'speaker', 'loudspeaker'), 'std_msgs/String', 'speech', streams=(
        Stream(NAOQI, '/speech', source='src/subscribers/speech.cpp'),)),
    # naoqi_driver's touch events (src/naoqi_driver.cpp:838-894): naoqi_bridge_msgs types, read
    # from the definition their connection carries (sources/naoqi_msgs.py); this package's own
    # copies (msg/, same md5sums) are accepted too
    # (topics in the driver's private namespace, NodeHandle("~"): naoqi_driver.cpp:991);
    # naoqi_driver.cpp:603-605: stock share/boot_config.json enables them, the fork's does not
    Sensor('headTouch', 'HEAD TOUCH', ('HeadTouch', 'head_touch', 'tactile'), 'naoqi_bridge_msgs/HeadTouch',
           'touch', also=('pepper_interface_tests/HeadTouch',), driver_topic='/naoqi_driver/head_touch',
           streams=(Stream((STOCK,), '/naoqi_driver/head_touch', source='src/naoqi_driver.cpp:838-894'),
                    Stream((FORK,), '/naoqi_driver/head_touch', enabled=False,
                           source='cssr4africa/naoqi_driver share/boot_config.json touch_head disabled'))),
    Sensor('handTouch', 'HAND TOUCH', ('HandTouch', 'hand_touch'), 'naoqi_bridge_msgs/HandTouch',
           'touch', also=('pepper_interface_tests/HandTouch',), driver_topic='/naoqi_driver/hand_touch',
           streams=(Stream((STOCK,), '/naoqi_driver/hand_touch', source='src/naoqi_driver.cpp:838-894'),
                    Stream((FORK,), '/naoqi_driver/hand_touch', enabled=False,
                           source='cssr4africa/naoqi_driver share/boot_config.json touch_hand disabled'))),
    Sensor('bumper', 'BUMPER', ('Bumper', 'bumpers'), 'naoqi_bridge_msgs/Bumper',
           'touch', also=('pepper_interface_tests/Bumper',), driver_topic='/naoqi_driver/bumper',
           streams=(Stream((STOCK,), '/naoqi_driver/bumper', source='src/naoqi_driver.cpp:838-894'),
                    Stream((FORK,), '/naoqi_driver/bumper', enabled=False,
                           source='cssr4africa/naoqi_driver share/boot_config.json bumper disabled'))),
    # naoqi_driver's own health on /diagnostics (src/converters/diagnostics.cpp; naoqi_driver.cpp:652)
    Sensor('robotHealth', 'ROBOT HEALTH', ('RobotHealth', 'health', 'diagnostics'),
           'diagnostic_msgs/DiagnosticArray', 'health', driver_topic='/diagnostics', streams=(
               Stream(NAOQI, '/diagnostics', 1.0, source='src/naoqi_driver.cpp:648-660 ("diag", 1 Hz)'),)),
    # the robot's transform tree on /tf (sensors/tf.py, sensors/tree.py): naoqi_driver publishes
    # it with every joint state (src/converters/joint_state.cpp:147-201)
    Sensor('tf', 'TRANSFORMS', ('TF', 'transforms', 'tfTree'), 'tf2_msgs/TFMessage', 'tf',
           driver_topic='/tf', streams=(
               Stream(NAOQI, '/tf', 50.0, source='src/converters/joint_state.cpp:147-201'),
               Stream((SIMULATOR,), '/tf', 50.0, source='robot_state_publisher and the planar-move plugin'))),
    # the motion check (--move, sensors/motion.py, motion/): its topic is the command it sends,
    # naoqi_driver's bounded moveTo (src/subscribers/moveto.cpp; naoqi_driver.cpp:938)
    Sensor('motion', 'MOTION', ('Motion', 'move'), 'geometry_msgs/PoseStamped', 'motion',
           driver_topic='/move_base_simple/goal', opt_in='--move', streams=(
               Stream(NAOQI, '/move_base_simple/goal', source='src/subscribers/moveto.cpp'),)),
])

# naoqi_driver2 (ros-naoqi/naoqi_driver2 2.1.2, 10c4ca9) is naoqi_driver ported to ROS 2: the
# same converters (frames, encodings: src/converters/*.cpp) and the same share/boot_config.json
# (:5-103: resolutions, fps, frequencies, enabled as stock naoqi_driver's), so each of its
# streams is stock naoqi_driver's, on its own topic: the node (named naoqi_driver, :124)
# publishes relative names and its launch file gives it no namespace
# (launch/naoqi_driver.launch.py:33-47), so every topic is at the root (docs/drivers.md,
# "naoqi_driver2"). {sensor: (topic, where naoqi_driver2 says so)}; a sensor not named here
# naoqi_driver2 does not publish.
_DRV2 = 'ros-naoqi/naoqi_driver2 10c4ca9 src/naoqi_driver.cpp:'
DRIVER2_TOPICS: Dict[str, Tuple[str, str]] = OrderedDict([
    ('backSonar', ('/sonar/back', _DRV2 + '860; src/converters/sonar.cpp:45-46, 63-66; boot_config.json:78-82')),
    ('frontSonar', ('/sonar/front', _DRV2 + '859; src/converters/sonar.cpp:45-46, 63-66; boot_config.json:78-82')),
    ('bottomCamera', ('/camera/bottom/image_raw', _DRV2 + '759-761; src/converters/camera.cpp:194, 200-216; '
                                                  'boot_config.json:12-18')),
    ('frontCamera', ('/camera/front/image_raw', _DRV2 + '747-749; src/converters/camera.cpp:194, 200-216; '
                                                'boot_config.json:5-11')),
    ('depthCamera', ('/camera/depth/image_raw', _DRV2 + '774; src/converters/camera.cpp:194, 207-213; '
                                                'boot_config.json:19-26')),
    ('stereoCamera', ('/camera/stereo/image_raw', _DRV2 + '793; boot_config.json:27-33')),
    ('irCamera', ('/camera/ir/image_raw', _DRV2 + '640, 667 (off on a stereo head), 810-820; '
                                          'boot_config.json:34-40')),
    ('laser', ('/laser', _DRV2 + '841; src/converters/laser.cpp:159-198, 230; boot_config.json:71-77')),
    ('microphone', ('/audio', _DRV2 + '878; src/event/audio.cpp:61-64, 173-182')),
    ('jointState', ('/joint_states', _DRV2 + '826; boot_config.json:66-70')),
    ('odometry', ('/odom', _DRV2 + '958; src/converters/odom.cpp:50-73; boot_config.json:99-103')),
    ('imu', ('/imu/base', _DRV2 + '734; src/converters/imu.cpp:41, 54; boot_config.json:61-65')),
    ('speech', ('/speech', _DRV2 + '998 (its subscriber)')),
    ('headTouch', ('/head_touch', _DRV2 + '940-951; boot_config.json:95-97')),
    ('handTouch', ('/hand_touch', _DRV2 + '920-934; boot_config.json:91-94')),
    ('bumper', ('/bumper', _DRV2 + '908-914; boot_config.json:87-90')),
    ('robotHealth', ('/diagnostics', _DRV2 + '708-709 ("diag", 1 Hz: boot_config.json:51-55)')),
    ('tf', ('/tf', 'ros-naoqi/naoqi_driver2 10c4ca9 src/publishers/joint_state.cpp:41, 48')),
    ('motion', ('/move_base_simple/goal', _DRV2 + '997 (its subscriber)')),
])
for _name, (_topic, _source) in DRIVER2_TOPICS.items():
    _row = SENSORS[_name]
    SENSORS[_name] = _row._replace(streams=_row.streams + tuple(
        s._replace(drivers=(DRIVER2,), topic=_topic, source=_source) for s in _row.streams if STOCK in s.drivers))


def sensors_of(family: Optional[str] = None, head: Optional[str] = None,
               camera: Optional[str] = None) -> Tuple[str, ...]:
    """The declared sensors (in declaration order) of a family, a head, a camera group."""
    return tuple(n for n, s in SENSORS.items()
                 if (family is None or s.family == family) and (head is None or head in s.heads)
                 and (camera is None or s.camera == camera))


def on_head(head: Optional[str] = None) -> Tuple[str, ...]:
    """Every sensor the input file can turn on that a robot with `head` has (None: any head)."""
    return tuple(n for n, s in SENSORS.items() if not s.opt_in and (head is None or head in s.heads))


if __name__ == '__main__':     # the demo's --sensors: `python -m ...declaration [HEAD]`
    import sys
    print(','.join(on_head(sys.argv[1] if len(sys.argv) > 1 else None)))
