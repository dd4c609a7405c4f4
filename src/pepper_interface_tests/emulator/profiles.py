"""What the emulator publishes: one SensorSpec per sensor topic, per profile.

The topic names come from the package's topics files (data/pepperTopics.dat for the robot,
data/simulatorTopics.dat for the Gazebo simulator), read once at start; everything else
(type, encoding, size, rate, frame ids, limits) is the behaviour of naoqi_driver, the Gazebo
Pepper simulator and the RealSense driver as listed in docs/emulator.md.
"""
import os
from dataclasses import dataclass, field
from typing import Optional, Tuple

from .. import settings

PROFILES = ('robot', 'simulator')
AUDIO_MODES = ('bridge', 'direct', 'off')
RESOLUTIONS = {'QQVGA': (160, 120), 'QVGA': (320, 240), 'VGA': (640, 480)}

AUDIO_RATE = 48000          # Hz, all four channels
AUDIO_BUFFER = 4096         # samples per channel per message
MIC_CHANNELS = ('rearLeft', 'rearRight', 'frontLeft', 'frontRight')

# Pepper's joints as naoqi_driver names them in /joint_states.
JOINT_NAMES = ('HeadYaw', 'HeadPitch', 'HipRoll', 'HipPitch', 'KneePitch',
               'LShoulderPitch', 'LShoulderRoll', 'LElbowYaw', 'LElbowRoll', 'LWristYaw', 'LHand',
               'RShoulderPitch', 'RShoulderRoll', 'RElbowYaw', 'RElbowRoll', 'RWristYaw', 'RHand',
               'WheelFL', 'WheelFR', 'WheelB')

# naoqi_driver's laser layout: right, front and left segments of 15 beams each, separated by
# two blind zones of 8 beams reported as -1.0, from angle_min (right) to angle_max (left).
LASER_SEGMENT = 15
LASER_BLIND = 8
LASER_BEAMS = 3 * LASER_SEGMENT + 2 * LASER_BLIND          # 61
LASER_ANGLE = 2.0944                                       # +-120 degrees
LASER_BLIND_VALUE = -1.0


def laser_blind_mask():
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
    kind: str                   # camera, depth, stereo, laser, sonar, imu, joints, odometry, audio
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

    @property
    def msg_type(self):
        return {'camera': 'sensor_msgs/Image', 'depth': 'sensor_msgs/Image',
                'stereo': 'sensor_msgs/Image', 'laser': 'sensor_msgs/LaserScan',
                'sonar': 'sensor_msgs/Range', 'imu': 'sensor_msgs/Imu',
                'joints': 'sensor_msgs/JointState', 'odometry': 'nav_msgs/Odometry',
                'audio': 'pepper_interface_tests/AudioCustomMsg'}[self.kind]

    @property
    def is_image(self):
        return self.kind in ('camera', 'depth', 'stereo')


@dataclass(frozen=True)
class Profile:
    name: str
    sensors: Tuple[SensorSpec, ...]
    speech_topic: Optional[str] = None
    topics_file: str = ''
    notes: Tuple[str, ...] = field(default=())

    def sensor(self, name):
        for s in self.sensors:
            if s.name == name:
                return s
        return None


def topics_file(profile, path=None):
    if path:
        return path
    name = 'pepperTopics.dat' if profile == 'robot' else 'simulatorTopics.dat'
    return os.path.join(settings.package_dir(), 'data', name)


def _need(topics, name, path):
    if name not in topics:
        raise settings.ConfigError('no topic for sensor "%s"' % name, path,
                                   fix='add a line "%s /topic/name" to the topics file' % name)
    return topics[name]


def robot_profile(path=None, realsense=False, audio='bridge', resolution='QVGA'):
    """naoqi_driver on a physical Pepper (NAOqi 2.5), plus the RealSense D435i when asked."""
    path = topics_file('robot', path)
    topics = settings.read_topics(path)
    w, h = RESOLUTIONS[resolution]
    dw, dh = (w, h) if w <= 320 else (320, 240)          # QVGA is the depth camera's maximum
    t = lambda n: _need(topics, n, path)                 # noqa: E731
    imu_topic = t('imu')
    torso = imu_topic[:-len('base')] + 'torso' if imu_topic.endswith('/base') else None
    sonar = dict(rate=10.0, range_min=0.25, range_max=2.55, field_of_view=0.5236)
    sensors = [
        SensorSpec('backSonar', 'sonar', t('backSonar'), frame_id='SonarBack_frame', **sonar),
        SensorSpec('frontSonar', 'sonar', t('frontSonar'), frame_id='SonarFront_frame', **sonar),
        SensorSpec('frontCamera', 'camera', t('frontCamera'), 10.0, 'CameraTop_optical_frame',
                   w, h, 'rgb8', view='front', hfov=0.9826),
        SensorSpec('bottomCamera', 'camera', t('bottomCamera'), 10.0,
                   'CameraBottom_optical_frame', w, h, 'rgb8', view='bottom', hfov=0.9826),
        SensorSpec('depthCamera', 'depth', t('depthCamera'), 10.0, 'CameraDepth_optical_frame',
                   dw, dh, '16UC1', view='depth', hfov=1.0123),
        SensorSpec('stereoCamera', 'stereo', t('stereoCamera'), 10.0, 'CameraDepth_optical_frame',
                   640, 180, 'rgb8', view='stereo', hfov=1.0472),
        SensorSpec('laser', 'laser', t('laser'), 10.0, 'base_footprint',
                   range_min=0.1, range_max=3.0),
        SensorSpec('jointState', 'joints', t('jointState'), 50.0),
        SensorSpec('odometry', 'odometry', t('odometry'), 15.0, 'odom', child_frame_id='base_link'),
        SensorSpec('imu', 'imu', imu_topic, 10.0, 'base_footprint',
                   extra=((torso, 'base_link'),) if torso else ()),
    ]
    if realsense:
        sensors += [
            SensorSpec('realsenseRGBCamera', 'camera', t('realsenseRGBCamera'), 15.0,
                       'camera_color_optical_frame', 640, 480, 'rgb8', view='realsense',
                       hfov=1.2043),
            SensorSpec('realsenseDepthCamera', 'depth', t('realsenseDepthCamera'), 15.0,
                       'camera_color_optical_frame', 640, 480, '16UC1', view='realsense',
                       hfov=1.2043),
        ]
    notes = []
    if audio == 'direct':
        sensors.append(SensorSpec('microphone', 'audio', t('microphone'),
                                  AUDIO_RATE / float(AUDIO_BUFFER)))
    elif audio == 'bridge':
        notes.append('%s is published by the audio bridge (naoqiAudio + naoqiAudioPublisher)'
                     % t('microphone'))
    return Profile('robot', tuple(sensors), speech_topic=t('speech'), topics_file=path,
                   notes=tuple(notes))


def simulator_profile(path=None):
    """The Gazebo Pepper simulator (pepper_gazebo_plugin): no microphone, IMU, stereo, speech."""
    path = topics_file('simulator', path)
    topics = settings.read_topics(path)
    t = lambda n: _need(topics, n, path)                 # noqa: E731
    sonar = dict(rate=20.0, range_min=0.0, range_max=5.0, field_of_view=0.5236)
    sensors = (
        SensorSpec('backSonar', 'sonar', t('backSonar'), frame_id='SonarBack_frame', **sonar),
        SensorSpec('frontSonar', 'sonar', t('frontSonar'), frame_id='SonarFront_frame', **sonar),
        SensorSpec('frontCamera', 'camera', t('frontCamera'), 5.0, 'CameraTop_optical_frame',
                   640, 480, 'rgb8', view='front', hfov=0.9826),
        SensorSpec('bottomCamera', 'camera', t('bottomCamera'), 5.0, 'CameraBottom_optical_frame',
                   640, 480, 'rgb8', view='bottom', hfov=0.9826),
        SensorSpec('depthCamera', 'depth', t('depthCamera'), 20.0, 'CameraDepth_optical_frame',
                   320, 240, '16UC1', view='depth', hfov=1.0123),
        SensorSpec('laser', 'laser', t('laser'), 6.25, 'base_footprint',
                   range_min=0.1, range_max=7.0),
        SensorSpec('jointState', 'joints', t('jointState'), 50.0),
        SensorSpec('odometry', 'odometry', t('odometry'), 20.0, 'odom',
                   child_frame_id='base_footprint'),
    )
    return Profile('simulator', sensors, speech_topic=None, topics_file=path)


def build_profile(name, path=None, realsense=False, audio='bridge', resolution='QVGA'):
    if name == 'robot':
        return robot_profile(path, realsense, audio, resolution)
    return simulator_profile(path)
