"""What the emulator publishes: one SensorSpec per sensor topic, per profile.

The topic names come from the package's topics files (data/pepperTopics.dat for the robot,
data/simulatorTopics.dat for the Gazebo simulator), read once at start; everything else
(type, encoding, size, rate, frame ids, limits) is the behaviour of naoqi_driver, the Gazebo
Pepper simulator and the RealSense driver as listed in docs/emulator.md.
"""
import math
import os
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Tuple

from ..plan import catalog, settings
from ..sensors import families

PROFILES = ('robot', 'robot-stock', 'simulator')
AUDIO_MODES = ('bridge', 'direct', 'off')
RESOLUTIONS = {'QQVGA': (160, 120), 'QVGA': (320, 240), 'VGA': (640, 480)}
# Pepper's head: naoqi_driver asks ALMotion.getSensorNames() for "CameraStereo"
# (ros-naoqi/naoqi_driver src/helpers/driver_helpers.cpp:373-394, isDepthStereo); with it
# (Pepper 1.8 head) depth comes from the stereo pair at stereo_resolution and
# camera/stereo/image_raw exists; without it (Pepper 1.7, ASUS Xtion) depth is the Xtion's at
# xtion_resolution and there is no stereo topic (src/naoqi_driver.cpp:607-616, 712-760).
HEADS = ('stereo', 'xtion')
# healthy but unusual (docs/emulator.md); resting: a robot in Rest mode (its laser frozen)
CONDITIONS = ('normal', 'loaded', 'still', 'dark', 'resting')

AUDIO_RATE = 48000          # Hz, all four channels (src/event/audio.cpp:107-113, 179)
AUDIO_BUFFER = 4096         # samples per channel per AudioCustomMsg: the CSSR fork's bridge
                            # (cssr4africa/naoqi_driver scripts/naoqiAudioPublisher.py:15)
STOCK_AUDIO_BUFFER = 8192   # samples per channel per AudioBuffer: NAOqi's ~170 ms buffers
                            # (issue 8, fact 5; 8192 / 48000 = 170.7 ms) -- to confirm on a robot
MIC_CHANNELS = ('rearLeft', 'rearRight', 'frontLeft', 'frontRight')

# Pepper's joints as naoqi_driver names them in /joint_states: ALMotion.getBodyNames("Body")
# (src/converters/joint_state.cpp:79), 20 on Pepper, wheels included.
JOINT_NAMES = ('HeadYaw', 'HeadPitch', 'HipRoll', 'HipPitch', 'KneePitch',
               'LShoulderPitch', 'LShoulderRoll', 'LElbowYaw', 'LElbowRoll', 'LWristYaw', 'LHand',
               'RShoulderPitch', 'RShoulderRoll', 'RElbowYaw', 'RElbowRoll', 'RWristYaw', 'RHand',
               'WheelFL', 'WheelFR', 'WheelB')
# joints whose velocity and effort naoqi_driver publishes as NaN: it reads
# Motion/Velocity/Sensor/<joint> and Motion/Torque/Sensor/<joint> from ALMemory and writes NaN
# when a key is missing (src/converters/joint_state.cpp:120-133). Which keys a Pepper lacks is
# not in the driver's code; the emulator assumes the wheels (to confirm on a robot).
JOINTS_WITHOUT_VELOCITY = ('WheelFL', 'WheelFR', 'WheelB')

# naoqi_driver's laser layout (src/converters/laser.cpp:165-205, 213-222): right, front and left
# segments of 15 beams each, separated by two blind zones of 8 slots left at -1.0, from
# angle_min (right) to angle_max (left); angle_increment = 2 * 2.0944 / 61 (not / 60).
LASER_SEGMENT = 15
LASER_BLIND = 8
LASER_BEAMS = 3 * LASER_SEGMENT + 2 * LASER_BLIND          # 61
LASER_ANGLE = 2.0944                                       # +-120 degrees
LASER_BLIND_VALUE = -1.0
LASER_INCREMENT = 2 * LASER_ANGLE / LASER_BEAMS
# the simulator's /pepper/laser_2 (awesomebytes/pepper_virtual simulation_that_works,
# pepper_gazebo_plugin/scripts/laser_publisher.py:424-434): 61 x 8 = 488 NaN slots over
# +-half_max_angle (120 deg by default, line 275), increment = span / 488; each of the 45 points
# of the three 15-ray Gazebo lasers is written into the slot of its own angle (lines 460-475).
SIM_LASER_SLOTS = 61 * 8
SIM_LASER_ANGLE = math.radians(120.0)


def laser_blind_mask() -> List[bool]:
    """Boolean list, True for the 16 blind beams of the 61-beam layout."""
    mask = [False] * LASER_BEAMS
    first = LASER_SEGMENT
    second = 2 * LASER_SEGMENT + LASER_BLIND
    for start in (first, second):
        for i in range(start, start + LASER_BLIND):
            mask[i] = True
    return mask


@dataclass(frozen=True)
class SensorSpec:
    """One published sensor stream."""
    name: str                   # canonical sensor name (catalog.SENSORS)
    family: str                 # the check family that judges it (sensors/families.py): range, camera,
                                # depth, laser, imu, joints, odometry, audio
    topic: str
    rate: float                 # nominal Hz
    frame_id: str = ''
    width: int = 0
    height: int = 0
    encoding: str = ''
    view: str = ''              # which camera of the scene: front, bottom, depth, stereo, realsense
    hfov: float = 0.0           # horizontal field of view of a camera, rad
    range_min: float = 0.0
    range_max: float = 0.0
    field_of_view: float = 0.0
    child_frame_id: str = ''
    extra: Tuple[Tuple[str, str], ...] = ()   # companion topics published alike: (topic, frame_id)
    layout: str = ''            # laser: naoqi (61 slots) or gazebo (488 slots); sonar: clip rule;
                                # audio: 'audiobuffer' for stock naoqi_driver's AudioBuffer
    noise: float = 0.0          # standard deviation of the reading noise (m)

    @property
    def msg_type(self) -> str:
        if self.family == 'audio' and self.layout == 'audiobuffer':
            return 'naoqi_bridge_msgs/AudioBuffer'
        return catalog.SENSORS[self.name].msg_type

    @property
    def is_image(self) -> bool:
        return families.family(self.family).traits.images


@dataclass(frozen=True)
class Profile:
    name: str
    sensors: Tuple[SensorSpec, ...]
    speech_topic: Optional[str] = None
    topics_file: str = ''
    notes: Tuple[str, ...] = field(default=())
    sim_time: bool = False      # publishes /clock and sets /use_sim_time (the Gazebo simulator)

    def sensor(self, name: str) -> Optional[SensorSpec]:
        for s in self.sensors:
            if s.name == name:
                return s
        return None


def topics_file(profile: str, path: Optional[str] = None) -> str:
    if path:
        return path
    name = 'simulatorTopics.dat' if profile == 'simulator' else 'pepperTopics.dat'
    return os.path.join(settings.package_dir(), 'data', name)


def _need(topics: Dict[str, str], name: str, path: str) -> str:
    if name not in topics:
        raise settings.ConfigError('no topic for sensor "%s"' % name, path,
                                   fix='add a line "%s /topic/name" to the topics file' % name)
    return topics[name]


def default_resolution(profile: str) -> str:
    """front/bottom camera resolution of each driver's share/boot_config.json: stock
    naoqi_driver asks QVGA ("resolution": 1), the CSSR4Africa fork VGA ("resolution": 2)."""
    return 'VGA' if profile == 'robot' else 'QVGA'


def robot_profile(path: Optional[str] = None, realsense: bool = False, audio: str = 'bridge',
                  resolution: Optional[str] = None, stock: bool = False, head: str = 'stereo',
                  audio_buffer: Optional[int] = None, touch: Optional[bool] = None) -> Profile:
    """naoqi_driver on a physical Pepper (NAOqi 2.5): the CSSR4Africa fork (robot) or stock
    ros-naoqi/naoqi_driver (robot-stock), plus the RealSense D435i when asked.
    Every number is the driver's; file:line references are to ros-naoqi/naoqi_driver master
    unless the CSSR fork (cssr4africa/naoqi_driver master) is named; see docs/drivers.md."""
    name = 'robot-stock' if stock else 'robot'
    path = topics_file(name, path)
    topics = settings.read_topics(path)
    w, h = RESOLUTIONS[resolution or default_resolution(name)]
    if head == 'stereo':
        # depth from the stereo pair: stereo_resolution 9 = kQ720p 640x360, in both
        # boot_config.json files; src/tools/alvisiondefinitions.h:54
        dw, dh = 640, 360
    else:
        # Xtion: xtion_resolution 1 (QVGA) in stock share/boot_config.json, 2 (VGA) in the fork's
        dw, dh = (320, 240) if stock else (640, 480)
    t = lambda n: _need(topics, n, path)                 # noqa: E731
    imu_topic = t('imu')
    torso = imu_topic[:-len('base')] + 'torso' if imu_topic.endswith('/base') else None
    # sonar.cpp:64-72: min 0.25, max 2.55, fov 0.523598776, ULTRASOUND; range = the raw
    # ALMemory value, not clipped (sonar.cpp:111-115); 10 Hz (boot_config.json "sonar")
    sonar: Dict[str, Any] = dict(rate=10.0, range_min=0.25, range_max=2.55, field_of_view=0.523598776,
                 layout='raw', noise=0.01)
    sensors = [
        SensorSpec('backSonar', 'range', t('backSonar'), frame_id='SonarBack_frame', **sonar),
        SensorSpec('frontSonar', 'range', t('frontSonar'), frame_id='SonarFront_frame', **sonar),
        # camera.cpp:193-205, 286-289: rgb8, CameraTop/Bottom_optical_frame; 10 fps (boot_config)
        SensorSpec('frontCamera', 'camera', t('frontCamera'), 10.0, 'CameraTop_optical_frame',
                   w, h, 'rgb8', view='front', hfov=0.9826),
        SensorSpec('bottomCamera', 'camera', t('bottomCamera'), 10.0,
                   'CameraBottom_optical_frame', w, h, 'rgb8', view='bottom', hfov=0.9826),
        # camera.cpp:194, 207-213: 16UC1 (mm), CameraDepth_optical_frame. An Xtion head also
        # has the infrared camera (naoqi_driver.cpp:607-613, 753-762; camera.cpp:215-224:
        # 16UC1, CameraDepth_optical_frame, 10 fps): published here alike, as the depth's
        # companion (same size; stock's ir_camera resolution 1 = QVGA is the Xtion depth's too)
        SensorSpec('depthCamera', 'depth', t('depthCamera'), 10.0, 'CameraDepth_optical_frame',
                   dw, dh, '16UC1', view='depth', hfov=1.0123,
                   extra=() if head == 'stereo' else
                   ((catalog.head_sign_topic('stereoCamera', topics.get('stereoCamera')) or '',
                     'CameraDepth_optical_frame'),)),
    ]
    if head == 'stereo':
        # naoqi_driver.cpp:733-750: only on a stereo head; kQQ720px2 = 640x180 rgb8, two views
        sensors.append(SensorSpec('stereoCamera', 'camera', t('stereoCamera'), 10.0,
                                  'CameraDepth_optical_frame', 640, 180, 'rgb8', view='stereo',
                                  hfov=1.0472))
    sensors += [
        # laser.cpp:213-237 and boot_config.json "laser": 0.1..3.0 m advertised, 10 Hz
        SensorSpec('laser', 'laser', t('laser'), 10.0, 'base_footprint',
                   range_min=0.1, range_max=3.0, layout='naoqi', noise=0.01),
        # joint_state.cpp:99 (no frame id), boot_config.json "joint_states": 50 Hz
        SensorSpec('jointState', 'joints', t('jointState'), 50.0),
        # odom.cpp:78-80: odom -> base_link; boot_config.json "odom": 15 Hz
        SensorSpec('odometry', 'odometry', t('odometry'), 15.0, 'odom', child_frame_id='base_link'),
        # imu.cpp:45-70: base_footprint (imu/base), base_link (imu/torso); 10 Hz (boot_config)
        SensorSpec('imu', 'imu', imu_topic, 10.0, 'base_footprint',
                   extra=((torso, 'base_link'),) if torso else ()),
        # joint_state.cpp:147-201: the URDF's tree with every joint state (tf_publisher.py)
        SensorSpec('tf', 'tf', topics.get('tf', '/tf'), 50.0, layout='realsense' if realsense else ''),
    ]
    if realsense:
        # realsense2_camera (ros1-legacy) base_realsense_node.cpp: colour RGB8 (:116), depth 16UC1 (:95-96),
        # aligned depth on aligned_depth_to_color/image_raw (:989) in the colour optical frame (:1918);
        # 640x480 at 15 fps as the robot launches it (docs/drivers.md)
        sensors += [
            SensorSpec('realsenseRGBCamera', 'camera', t('realsenseRGBCamera'), 15.0,
                       'camera_color_optical_frame', 640, 480, 'rgb8', view='realsense',
                       hfov=1.2043),
            SensorSpec('realsenseDepthCamera', 'depth', t('realsenseDepthCamera'), 15.0,
                       'camera_color_optical_frame', 640, 480, '16UC1', view='realsense',
                       hfov=1.2043),
        ]
    # naoqi_driver.cpp:838-894: the touch events (one message per change: the rate here is how
    # often the emulator looks for one), when boot_config.json enables them: stock
    # share/boot_config.json does (bumper, touch_hand, touch_head "enabled": true), the CSSR fork's
    # does not ("enabled": false), so `touch` defaults to `stock`; :648-660 the diagnostics on
    # /diagnostics at 1 Hz ("diag", enabled in both). A topics file without these keys: not published.
    touch = stock if touch is None else touch
    events = [('robotHealth', 'health', 1.0)]
    if touch:
        events = [('headTouch', 'touch', 20.0), ('handTouch', 'touch', 20.0), ('bumper', 'touch', 20.0)] + events
    for key, family, hz in events:
        if key in topics:
            sensors.append(SensorSpec(key, family, topics[key], hz))
    notes = []
    if stock:
        # src/event/audio.cpp:62-66, 107-113, 177-186: AudioBuffer, 48 kHz, channelMap [3,5,0,2],
        # interleaved int16, one message per NAOqi buffer; published by the driver itself
        n = audio_buffer or STOCK_AUDIO_BUFFER
        if audio != 'off':
            sensors.append(SensorSpec('microphone', 'audio', t('microphone'),
                                      AUDIO_RATE / float(n), width=n, layout='audiobuffer'))
    elif audio == 'direct':
        n = audio_buffer or AUDIO_BUFFER
        sensors.append(SensorSpec('microphone', 'audio', t('microphone'),
                                  AUDIO_RATE / float(n), width=n))
    elif audio == 'bridge':
        notes.append('%s is published by the audio bridge (naoqiAudio + naoqiAudioPublisher)'
                     % t('microphone'))
    return Profile(name, tuple(sensors), speech_topic=t('speech'), topics_file=path,
                   notes=tuple(notes))


def simulator_profile(path: Optional[str] = None) -> Profile:
    """The Gazebo simulator CSSR4Africa installs: awesomebytes/pepper_robot branch
    correct_chain_model_and_gazebo_enabled (pepper_description/urdf/pepper1.0_generated_urdf/
    pepperGazeboCPU.xacro, loaded by pepper_upload_CPU.launch) and awesomebytes/pepper_virtual
    branch simulation_that_works (laser_publisher.py). No microphone, IMU, stereo, speech.
    Runs on sim time (/clock)."""
    path = topics_file('simulator', path)
    topics = settings.read_topics(path)
    t = lambda n: _need(topics, n, path)                 # noqa: E731
    # pepperGazeboCPU.xacro:658-736: ray sensors 5x5 rays over +-0.52 rad, 0..5 m, 20 Hz,
    # gazebo_ros_range with gaussianNoise 0.05, fov 1.05, radiation ultrasound
    sonar: Dict[str, Any] = dict(rate=20.0, range_min=0.0, range_max=5.0, field_of_view=1.05, layout='gazebo',
                 noise=0.05)
    sensors = (
        SensorSpec('backSonar', 'range', t('backSonar'), frame_id='SonarBack_frame', **sonar),
        SensorSpec('frontSonar', 'range', t('frontSonar'), frame_id='SonarFront_frame', **sonar),
        # pepperGazeboCPU.xacro:453-524: 640x480 R8G8B8 (rgb8), update_rate 5, horizontal_fov 1.0
        SensorSpec('frontCamera', 'camera', t('frontCamera'), 5.0, 'CameraTop_optical_frame',
                   640, 480, 'rgb8', view='front', hfov=1.0),
        SensorSpec('bottomCamera', 'camera', t('bottomCamera'), 5.0, 'CameraBottom_optical_frame',
                   640, 480, 'rgb8', view='bottom', hfov=1.0),
        # pepperGazeboCPU.xacro:528-575: gazebo_ros_openni_kinect 320x240, update_rate 30,
        # useDepth16UC1Format true (16UC1 in mm, 0 outside 0.4..8.0 m), hfov 58 deg
        SensorSpec('depthCamera', 'depth', t('depthCamera'), 30.0, 'CameraDepth_optical_frame',
                   320, 240, '16UC1', view='depth', hfov=math.radians(58.0)),
        # laser_publisher.py:386-395: base_footprint, range 0.1..7.0; three 15-ray lasers at
        # update_rate 6.25 (pepperGazeboCPU.xacro:778-871, 0.3..7.0 m, noise mean 0.01 sd 0.01)
        SensorSpec('laser', 'laser', t('laser'), 6.25, 'base_footprint',
                   range_min=0.1, range_max=7.0, layout='gazebo', noise=0.01),
        # joint_state_controller of pepper_control (pepper_virtual pepper_control/config/
        # pepper_trajectory_control.yaml:3-5, publish_rate 50): velocity and effort of every joint
        # with a transmission (pepper_robot pepperTransmission.xacro)
        SensorSpec('jointState', 'joints', t('jointState'), 50.0, layout='gazebo'),
        # pepperGazeboCPU.xacro:741-765: odometryRate 20, odom -> robotBaseFrame base_footprint
        SensorSpec('odometry', 'odometry', t('odometry'), 20.0, 'odom',
                   child_frame_id='base_footprint'),
        # robot_state_publisher and the planar-move plugin (tf_publisher.py, urdf_tree.py)
        SensorSpec('tf', 'tf', topics.get('tf', '/tf'), 50.0, layout='gazebo'),
    )
    return Profile('simulator', sensors, speech_topic=None, topics_file=path, sim_time=True)


def build_profile(name: str, path: Optional[str] = None, realsense: bool = False, audio: str = 'bridge',
                  resolution: Optional[str] = None, head: str = 'stereo',
                  audio_buffer: Optional[int] = None, touch: Optional[bool] = None) -> Profile:
    if name in ('robot', 'robot-stock'):
        return robot_profile(path, realsense, audio, resolution, stock=name == 'robot-stock',
                             head=head, audio_buffer=audio_buffer, touch=touch)
    return simulator_profile(path)
