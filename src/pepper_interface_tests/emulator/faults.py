"""Fault injection: the `~faults` string -> {sensor name: Faults}.

Format (documented in docs/emulator.md)::

    sensor:fault[=value][,fault[=value]...][;sensor:...]

e.g. ``frontCamera:frozen;laser:nan;imu:broken_quaternion;jointState:die_after=3``.
``after=T`` makes a sensor's stuck, frozen, black and silent_channel faults begin T s after its
first subscriber (a partial failure inside the window): ``laser:stuck,after=1.5``.
Sensor names are the canonical names (any spelling the catalog knows, case-insensitive);
fault names are case-insensitive. Every mistake raises FaultError naming the valid choices.
"""
from dataclasses import dataclass
from typing import Any, Dict, Optional, Tuple

from ..plan import catalog
from ..sensors import families, touch
from .profiles import JOINT_NAMES, MIC_CHANNELS

# fault name -> (takes a value?, check families it applies to (sensors/families.py); None = every one)
IMAGE = ('camera', 'depth')
FAULTS: Dict[str, Tuple[bool, Optional[Tuple[str, ...]]]] = {
    'silent': (False, None),
    'rate': (True, None),
    'die_after': (True, None),
    'wrong_type': (False, None),
    'frozen': (False, IMAGE),
    'black': (False, IMAGE),
    'wrong_encoding': (False, IMAGE),
    'wrong_step': (False, IMAGE),
    'nan': (False, ('laser', 'range', 'joints', 'odometry', 'imu')),
    'out_of_range': (False, ('laser', 'range', 'joints')),
    'broken_quaternion': (False, ('imu', 'odometry')),
    'nan_attitude': (False, ('imu',)),
    'all_blind': (False, ('laser',)),
    'no_returns': (False, ('laser',)),
    'silent_channel': (True, ('audio',)),
    # a broken bridge's channels (issue 24): one microphone in every channel, or dealt out
    'copied_channels': (False, ('audio',)),
    'planar_as_interleaved': (False, ('audio',)),
    # data that looks healthy but cannot be real (issue 10)
    'stuck': (False, ('laser', 'imu', 'depth', 'camera', 'audio')),
    'after': (True, None),
    'dead_accelerometer': (False, ('imu',)),
    'gyro_overrange': (False, ('imu',)),
    'joint_jump': (False, ('joints',)),
    'pose_jump': (False, ('odometry',)),
    'twist_mismatch': (False, ('odometry',)),
    'far_depth': (False, ('depth',)),
    'flat_depth': (False, ('depth',)),
    'dead_board': (True, ('laser',)),
    'nan_board': (True, ('laser',)),
    'spike': (False, ('odometry',)),
    # touch sensors, bumpers and the robot's health (emulator/events.py)
    'dead_zone': (True, ('touch',)),
    'jammed': (True, ('touch',)),
    'hot_joint': (True, ('health',)),
    'empty_battery': (False, ('health',)),
    # wear: still within the absolute rules, a drift from a baseline (outputs/drift.py)
    'blur': (False, ('camera',)),
    'dim': (True, ('camera',)),
    'gyro_bias': (True, ('imu',)),
    'noisy': (False, ('range', 'joints')),
    'quiet_channel': (True, ('audio',)),
    'scratched': (True, ('laser',)),
    # a robot that is commanded (issue 25: the three command topics, emulator/body.py)
    'gyro_inverted': (False, ('imu',)),
    'dead_gyro': (False, ('imu',)),
    'swapped_axes': (False, ('imu',)),
    'frozen_pose': (False, ('odometry',)),
    'stuck_joint': (True, ('joints',)),
    'reversed': (False, ('laser',)),
    'not_following': (False, IMAGE),
    'glass': (False, ('range',)),
    'clock_offset': (True, None),
    # conditions of the robot and its world, not of one sensor: the pseudo-sensor `robot`
    'resting': (False, ('robot',)),
    'base_blocked': (False, ('robot',)),
    'obstacle': (False, ('robot',)),
    # the robot's transform tree on /tf (emulator/urdf_tree.py, sensors/tf.py)
    'no_description': (False, ('tf',)),
    'second_publisher': (False, ('tf',)),
    'stale': (False, ('tf',)),
    'future_stamps': (False, ('tf',)),
}
# the pseudo-sensor of the robot's own conditions (`robot:resting`): no topic of its own
ROBOT = 'robot'
# the laser's boards, in slot order (naoqi_driver laser.cpp:166-205: right, front, left)
LASER_BOARDS = ('right', 'front', 'left')

# canonical sensor name -> its family, for validation before a profile is built: every sensor
# the emulator publishes (a check that drives itself, speech, is what the emulator listens to)
SENSOR_KINDS = {s.name: s.family for s in catalog.SENSORS.values()
                if not families.family(s.family).traits.drives_itself}


class FaultError(ValueError):
    """A malformed or unknown fault specification."""


@dataclass(frozen=True)
class Faults:
    """The faults of one sensor. Defaults = healthy."""
    silent: bool = False
    rate: float = 1.0
    die_after: Optional[float] = None
    wrong_type: bool = False
    frozen: bool = False
    black: bool = False
    wrong_encoding: bool = False
    wrong_step: bool = False
    nan: bool = False
    out_of_range: bool = False
    broken_quaternion: bool = False
    nan_attitude: bool = False      # imu: NaN orientation, covariance still -1 (a broken IMU)
    all_blind: bool = False         # laser: every slot blind (-1.0 robot, NaN simulator)
    no_returns: bool = False        # laser, simulator: no point reaches laser_2 (all NaN)
    silent_channel: Tuple[str, ...] = ()
    copied_channels: bool = False   # microphone: rearLeft's samples in all four channels
    planar_as_interleaved: bool = False     # microphone: planar buffers read as interleaved
    stuck: bool = False             # the data of one message republished with new stamps
    after: Optional[float] = None   # stuck/frozen/black/silent_channel from T s after the first subscriber
    dead_accelerometer: bool = False    # imu: linear acceleration 0, 0, 0
    gyro_overrange: bool = False    # imu: 12 rad/s about z, beyond the gyrometer's ~500 deg/s
    joint_jump: bool = False        # joints: HeadYaw jumps between -2 and +2 rad every 0.25 s
    pose_jump: bool = False         # odometry: x jumps by 1 m every 2 s
    twist_mismatch: bool = False    # odometry: twist says 0.4 m/s whatever the pose does
    far_depth: bool = False         # depth: every pixel about 20 m
    flat_depth: bool = False        # depth: every pixel 1.5 m
    dead_board: Optional[str] = None    # laser: this board stopped (ALMemory x = y = 0)
    nan_board: Optional[str] = None     # laser: this board NaN throughout (yohatad's fork)
    spike: bool = False             # odometry: the pose leaps 25 m for one message in eight
    dead_zone: Tuple[str, ...] = ()     # touch: these zones send nothing
    jammed: Tuple[str, ...] = ()        # touch: pressed 1 s after the first subscriber, never released
    hot_joint: Optional[float] = None   # health: HipPitch at this temperature (°C)
    empty_battery: bool = False         # health: 12 %, not charging
    blur: bool = False                  # camera: out of focus (a 5 x 5 box blur)
    dim: Optional[float] = None         # camera: brightness times VALUE (a dusty lens)
    gyro_bias: Optional[float] = None   # imu: VALUE rad/s added about x (a drifting gyrometer)
    noisy: bool = False                 # sonar, joints: four times the noise (a worn sensor)
    quiet_channel: Tuple[str, ...] = () # audio: these channels 12 dB quieter (a clogged grille)
    scratched: Optional[str] = None     # laser: this board's window scratched (a third of its points lost)
    gyro_inverted: bool = False     # imu: angular velocity of the opposite sign (all three axes)
    dead_gyro: bool = False         # imu: angular velocity 0, 0, 0 whatever the base does
    swapped_axes: bool = False      # imu: x and z exchanged (gyro and accelerometer)
    frozen_pose: bool = False       # odometry: pose and twist of the start while the wheels turn
    stuck_joint: Optional[str] = None   # joints: this joint's encoder reads its start angle
    reversed: bool = False          # laser: the beams in the opposite order
    not_following: bool = False     # camera, depth: live picture that does not pan with the head
    glass: bool = False             # sonar: a glass pane 0.8 m ahead the laser sees through
    clock_offset: Optional[float] = None    # any sensor: header stamps VALUE s off the others
    resting: bool = False           # robot: stiffness 0, every command ignored (ALMotion rest)
    base_blocked: bool = False      # robot: awake, the head moves, the base refuses to
    obstacle: bool = False          # robot: a box 0.35 m in front of the base
    no_description: bool = False    # tf: naoqi_driver without share/urdf: odom -> base_link alone
    second_publisher: bool = False  # tf: a second node publishes Head -> CameraTop_frame, 1 cm off
    stale: bool = False             # tf: stamps 0.8 s behind their publication
    future_stamps: bool = False     # tf: stamps 1.0 s ahead of their publication

    def describe(self) -> str:
        out = []
        for name in FAULTS:
            value = getattr(self, name)
            default = getattr(HEALTHY, name)
            if value != default:
                out.append(name if value is True else '%s=%s' % (
                    name, '|'.join(value) if isinstance(value, tuple) else value))
        return ','.join(out)


HEALTHY = Faults()


def valid_sensors() -> str:
    return ', '.join(list(SENSOR_KINDS) + [ROBOT])


def valid_faults(kind: Optional[str] = None) -> str:
    return ', '.join(n + ('=VALUE' if takes else '') for n, (takes, kinds) in FAULTS.items()
                     if kind is None or kinds is None or kind in kinds)


def _number(sensor: str, fault: str, value: str, positive_only: bool = True) -> float:
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = float('nan')
    if not number == number or number in (float('inf'), float('-inf')) or \
            (positive_only and number <= 0) or (not positive_only and number < 0):
        raise FaultError('%s:%s=%s: the value must be a %s number' % (
            sensor, fault, value, 'positive' if positive_only else 'non-negative'))
    return number


def parse_faults(text: Optional[str]) -> Dict[str, Faults]:
    """Parse a fault string into {canonical sensor name: Faults}. Empty/None -> {}."""
    if text is None:
        return {}
    text = str(text).strip()
    found: Dict[str, Dict[str, Any]] = {}
    for entry in (e.strip() for e in text.replace('\n', ';').split(';')):
        if not entry:
            continue
        if ':' not in entry:
            raise FaultError('"%s" is not "sensor:fault"; example: frontCamera:frozen;laser:nan'
                             % entry)
        sensor_text, fault_text = (p.strip() for p in entry.split(':', 1))
        name = ROBOT if sensor_text.lower() == ROBOT else catalog.canonical(sensor_text)
        if name != ROBOT and name not in SENSOR_KINDS:
            raise FaultError('unknown sensor "%s" in faults; valid sensors: %s'
                             % (sensor_text, valid_sensors()))
        kind = ROBOT if name == ROBOT else SENSOR_KINDS[name]
        values = dict(found.get(name, {}))
        for item in (i.strip() for i in fault_text.split(',')):
            if not item:
                continue
            fault, _, value = item.partition('=')
            fault = fault.strip().lower()
            value = value.strip()
            if fault not in FAULTS:
                raise FaultError('unknown fault "%s" for %s; valid faults: %s'
                                 % (fault, name, valid_faults(kind)))
            takes_value, kinds = FAULTS[fault]
            if kinds is not None and kind not in kinds:
                raise FaultError('fault "%s" does not apply to %s; valid faults for it: %s'
                                 % (fault, name, valid_faults(kind)))
            if takes_value and not value:
                raise FaultError('fault "%s" of %s needs a value, e.g. %s'
                                 % (fault, name, {'rate': 'rate=0.3', 'die_after': 'die_after=3', 'after': 'after=1.5',
                                                  'silent_channel': 'silent_channel=rearRight',
                                                  'dead_board': 'dead_board=front', 'nan_board': 'nan_board=left',
                                                  'dead_zone': 'dead_zone=front', 'jammed': 'jammed=back',
                                                  'hot_joint': 'hot_joint=76', 'dim': 'dim=0.6',
                                                  'gyro_bias': 'gyro_bias=0.02',
                                                  'quiet_channel': 'quiet_channel=rearLeft',
                                                  'scratched': 'scratched=front',
                                                  'stuck_joint': 'stuck_joint=HeadYaw',
                                                  'clock_offset': 'clock_offset=0.5'}[fault]))
            if not takes_value and value:
                raise FaultError('fault "%s" of %s takes no value (got "%s")' % (fault, name, value))
            if fault == 'rate':
                values['rate'] = _number(name, fault, value)
            elif fault in ('hot_joint', 'dim', 'gyro_bias'):
                values[fault] = _number(name, fault, value)
            elif fault in ('dead_zone', 'jammed'):
                zones = [z.id for z in touch.zones_of(catalog.SENSORS[name].msg_type)[1]]
                chosen = list(values.get(fault, ()))
                for z in (c.strip() for c in value.replace('+', '|').split('|')):
                    match = [c for c in zones if c.lower() == z.lower()]
                    if not match:
                        raise FaultError('unknown zone "%s" of %s; valid zones: %s'
                                         % (z, name, ', '.join(zones)))
                    if match[0] not in chosen:
                        chosen.append(match[0])
                values[fault] = tuple(chosen)
            elif fault == 'clock_offset':
                offset = _number(name, fault, value.lstrip('+-'))
                values[fault] = -offset if value.startswith('-') else offset
            elif fault == 'stuck_joint':
                match = [j for j in JOINT_NAMES if j.lower() == value.lower()]
                if not match:
                    raise FaultError('unknown joint "%s" in %s:stuck_joint; valid joints: %s'
                                     % (value, name, ', '.join(JOINT_NAMES)))
                values[fault] = match[0]
            elif fault in ('die_after', 'after'):
                values[fault] = _number(name, fault, value, positive_only=False)
            elif fault in ('silent_channel', 'quiet_channel'):
                channels = list(values.get(fault, ()))
                for ch in (c.strip() for c in value.replace('+', '|').split('|')):
                    match = [c for c in MIC_CHANNELS if c.lower() == ch.lower()]
                    if not match:
                        raise FaultError('unknown microphone channel "%s"; valid channels: %s'
                                         % (ch, ', '.join(MIC_CHANNELS)))
                    if match[0] not in channels:
                        channels.append(match[0])
                values[fault] = tuple(channels)
            elif fault in ('dead_board', 'nan_board', 'scratched'):
                if value.lower() not in LASER_BOARDS:
                    raise FaultError('unknown laser board "%s" in %s:%s; valid boards: %s'
                                     % (value, name, fault, ', '.join(LASER_BOARDS)))
                values[fault] = value.lower()
            else:
                values[fault] = True
        found[name] = values
    return {name: Faults(**values) for name, values in found.items()}


def format_faults(faults: Dict[str, Faults]) -> str:
    """Inverse of parse_faults (canonical spelling)."""
    return ';'.join('%s:%s' % (name, f.describe()) for name, f in faults.items() if f.describe())
