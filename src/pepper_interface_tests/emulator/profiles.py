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

from ..plan import catalog, declaration, settings
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


# What the emulator adds to a declared stream (plan/declaration.py) to model it, per family and
# platform: the parts of a message the declaration does not hold (a sonar's geometry, a laser's
# layout, the noise), each with its driver's source.
# sonar.cpp:64-72: min 0.25, max 2.55, fov 0.523598776, ULTRASOUND; range = the raw ALMemory
# value, not clipped (sonar.cpp:111-115). pepperGazeboCPU.xacro:658-736: ray sensors 5x5 rays
# over +-0.52 rad, 0..5 m, gazebo_ros_range with gaussianNoise 0.05, fov 1.05, radiation ultrasound.
# laser.cpp:213-237 and boot_config.json "laser": 0.1..3.0 m advertised; laser_publisher.py:386-395:
# range 0.1..7.0, three 15-ray lasers (pepperGazeboCPU.xacro:778-871, noise mean 0.01 sd 0.01).
# pepper_control (pepper_virtual pepper_control/config/pepper_trajectory_control.yaml:3-5):
# velocity and effort of every joint with a transmission (pepper_robot pepperTransmission.xacro).
# odom.cpp:78-80: odom -> base_link; pepperGazeboCPU.xacro:741-765: odom -> base_footprint.
MODEL: Dict[Tuple[str, str], Dict[str, Any]] = {
    ('range', 'robot'): dict(range_min=0.25, range_max=2.55, field_of_view=0.523598776, layout='raw', noise=0.01),
    ('range', 'simulator'): dict(range_min=0.0, range_max=5.0, field_of_view=1.05, layout='gazebo', noise=0.05),
    ('laser', 'robot'): dict(range_min=0.1, range_max=3.0, layout='naoqi', noise=0.01),
    ('laser', 'simulator'): dict(range_min=0.1, range_max=7.0, layout='gazebo', noise=0.01),
    ('joints', 'simulator'): dict(layout='gazebo'),
    ('odometry', 'robot'): dict(child_frame_id='base_link'),
    ('odometry', 'simulator'): dict(child_frame_id='base_footprint'),
}
# the order in which a profile's streams start (each stream's noise seed is its place in it):
# the driver's periodic streams, the RealSense's, the events, the microphone
PERIODIC = (('range',), ('camera', 'depth'), ('laser',), ('joints',), ('odometry',), ('imu',), ('tf',))
EVENT_POLL_HZ = {'touch': 20.0}    # how often the emulator looks for a touch event to publish


def camera_view(sensor: catalog.Sensor) -> str:
    """Which camera of the scene (emulator/scene.py) a declared camera shows."""
    return 'realsense' if sensor.camera == 'realsense' else sensor.name[:-len('Camera')]


def declared_spec(name: str, driver: str, head: Optional[str], topic: str, platform: str,
                  **changes: Any) -> Optional[SensorSpec]:
    """The SensorSpec of sensor `name` as `driver` publishes it on `head` (the declaration's
    rate, frame, encoding, size and field of view, the emulator's MODEL of its family), on
    `topic` (the topics file's); None when that driver does not publish it there."""
    sensor = catalog.SENSORS[name]
    stream = sensor.stream(driver, head)
    if stream is None:
        return None
    w, h = stream.size
    values: Dict[str, Any] = dict(rate=stream.rate, frame_id=stream.frame, width=w, height=h,
                                  encoding=stream.encoding, hfov=stream.hfov)
    if stream.encoding:
        values['view'] = camera_view(sensor)
    values.update(MODEL.get((sensor.family, platform), {}))
    values.update(changes)
    return SensorSpec(name, sensor.family, topic, **values)


def _periodic(driver: str, head: Optional[str], topics: Dict[str, str], path: str, platform: str,
              changes: Dict[str, Dict[str, Any]]) -> List[SensorSpec]:
    out = []
    for group in PERIODIC:
        for name in [n for n, s in catalog.SENSORS.items() if s.family in group]:
            stream = catalog.SENSORS[name].stream(driver, head)
            if stream is None:
                continue
            topic = topics.get(name, stream.topic) if group == ('tf',) else _need(topics, name, path)
            spec = declared_spec(name, driver, head, topic, platform, **changes.get(name, {}))
            if spec is not None:
                out.append(spec)
    return out


def robot_profile(path: Optional[str] = None, realsense: bool = False, audio: str = 'bridge',
                  resolution: Optional[str] = None, stock: bool = False, head: str = 'stereo',
                  audio_buffer: Optional[int] = None, touch: Optional[bool] = None) -> Profile:
    """naoqi_driver on a physical Pepper (NAOqi 2.5): the CSSR4Africa fork (robot) or stock
    ros-naoqi/naoqi_driver (robot-stock), plus the RealSense D435i when asked.
    Every stream is the declaration's (plan/declaration.py, with the driver's file:line); the
    emulator's own parts are MODEL's; see docs/drivers.md."""
    name = 'robot-stock' if stock else 'robot'
    driver = declaration.STOCK if stock else declaration.FORK
    path = topics_file(name, path)
    topics = settings.read_topics(path)
    t = lambda n: _need(topics, n, path)                 # noqa: E731
    changes: Dict[str, Dict[str, Any]] = {}
    if resolution:       # the front and bottom cameras' resolution, asked of the emulator
        for cam in ('frontCamera', 'bottomCamera'):
            changes[cam] = dict(zip(('width', 'height'), RESOLUTIONS[resolution]))
    imu_topic = t('imu')
    torso = imu_topic[:-len('base')] + 'torso' if imu_topic.endswith('/base') else None
    # imu.cpp:45-70: base_footprint (imu/base), base_link (imu/torso)
    changes['imu'] = dict(extra=((torso, 'base_link'),) if torso else ())
    changes['tf'] = dict(layout='realsense' if realsense else '')
    # the driver's sign of this head (declaration.HEADS) when no declared sensor publishes it:
    # carried by the depth camera alike (same frame and size), as the driver's companion stream
    sign = declaration.HEADS[head]
    if not any(sign.sign_part in s.topic for n in catalog.SENSORS
               for s in [catalog.SENSORS[n].stream(driver, head)] if s and n != 'depthCamera'):
        other = next(n for n in catalog.SENSORS if head not in catalog.SENSORS[n].heads)
        changes['depthCamera'] = dict(extra=((catalog.head_sign_topic(other, topics.get(other)) or '',
                                              'CameraDepth_optical_frame'),))
    sensors = _periodic(driver, head, topics, path, 'robot', changes)
    if realsense:
        sensors += _periodic(declaration.REALSENSE, head, topics, path, 'robot', changes)
    # the touch events (one message per change: the rate here is how often the emulator looks for
    # one), when boot_config.json enables them (declaration: stock's does, the CSSR fork's does
    # not), so `touch` defaults to the driver's; /diagnostics ("diag", enabled in both). A topics
    # file without these keys: not published.
    for family in ('touch', 'health'):
        for key in declaration.sensors_of(family):
            stream = catalog.SENSORS[key].stream(driver, head)
            on = stream is not None and (stream.enabled if touch is None or family != 'touch' else touch)
            if on and stream is not None and key in topics:
                sensors.append(SensorSpec(key, family, topics[key], EVENT_POLL_HZ.get(family, stream.rate)))
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
    branch simulation_that_works (laser_publisher.py): the declaration's pepper_virtual streams.
    No microphone, IMU, stereo, speech. Runs on sim time (/clock)."""
    path = topics_file('simulator', path)
    topics = settings.read_topics(path)
    sensors = _periodic(declaration.SIMULATOR, None, topics, path, 'simulator',
                        {'tf': dict(layout='gazebo')})
    return Profile('simulator', tuple(sensors), speech_topic=None, topics_file=path, sim_time=True)


def build_profile(name: str, path: Optional[str] = None, realsense: bool = False, audio: str = 'bridge',
                  resolution: Optional[str] = None, head: str = 'stereo',
                  audio_buffer: Optional[int] = None, touch: Optional[bool] = None) -> Profile:
    if name in ('robot', 'robot-stock'):
        return robot_profile(path, realsense, audio, resolution, stock=name == 'robot-stock',
                             head=head, audio_buffer=audio_buffer, touch=touch)
    return simulator_profile(path)
