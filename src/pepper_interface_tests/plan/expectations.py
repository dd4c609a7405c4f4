"""What each sensor should deliver: typed, frozen dataclasses, one per check family.

The expectations file (config/sensorExpectations.yaml) is read once by `load()` into one frozen
object per sensor. The dataclass defaults below are the only defaults: a key left out of the
file takes the value written here. The loader rejects, with file:line and the fix:
  * a file that is not UTF-8 (a UTF-8 BOM at its start is accepted), a YAML syntax error;
  * duplicate keys (PyYAML would silently keep the last one), naming both lines;
  * unknown sections, unknown sensors, unknown keys (a typo `rates:` would disable a check);
  * values of the wrong type (`min_brightness: dark`, `joints: "HeadYaw"`, `ranges: "61"`,
    `quick_messages: .inf`, `rate: [1, .inf]`) and impossible values (`rate: [-16, -4]`,
    `min_messages: -3`, `max_delay: .nan`, `median_range: [8, 0.3]`).

`defaults:` applies to every sensor whose family has the key; a key no family has is unknown.
`drivers:` holds driver profiles ({profile: {sensor: keys}}): a sensor block takes one with
`driver: name`, its own keys overriding the profile's; `load(..., driver=name)` takes one for
every sensor the profile describes (a recording of another driver). Only the chosen platform's
section and the profiles are validated (a file may carry a section for a platform that is not
tested today).

Checks read the fields as attributes (`self.expect.max_delay`): a None field means "not checked".
"""
import dataclasses
import difflib
import math
from dataclasses import dataclass, field, fields
from typing import Any, Callable, Dict, Optional, Tuple, Type

import yaml

from . import catalog
from .textfile import ConfigError, read_text

SECTIONS = ('defaults', 'drivers', 'robot', 'simulator')


# ---------------------------------------------------------------- value kinds
# Each kind checks one value and returns it normalised, or raises Bad(problem, fix example).
# Kept as small functions so that a new key is one line of a dataclass.

class Bad(Exception):
    def __init__(self, problem: str, fix: str) -> None:
        super().__init__(problem)
        self.problem, self.fix = problem, fix


def _is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


# a value kind: (key, value as parsed) -> the value normalised; raises Bad
Kind = Callable[[str, Any], Any]


def number(lo: Optional[float] = None, hi: Optional[float] = None, lo_open: bool = False,
           hi_open: bool = False, example: str = '1.0') -> Kind:
    """A finite number within [lo, hi] (an open end excludes the bound)."""
    def check(key: str, v: Any) -> float:
        if not _is_number(v):
            raise Bad('is %r, not a number' % (v,), '"%s: %s"' % (key, example))
        if math.isnan(v) or math.isinf(v):
            raise Bad('is %r, not a finite number' % (v,), '"%s: %s"' % (key, example))
        if lo is not None and (v < lo or (lo_open and v == lo)):
            raise Bad('is %r, must be %s %g' % (v, 'above' if lo_open else 'at least', lo),
                      '"%s: %s"' % (key, example))
        if hi is not None and (v > hi or (hi_open and v == hi)):
            raise Bad('is %r, must be %s %g' % (v, 'below' if hi_open else 'at most', hi),
                      '"%s: %s"' % (key, example))
        return float(v)
    return check


def whole(lo: int, example: str) -> Kind:
    """A whole number (an integral float such as 10.0 is accepted) of at least `lo`."""
    def check(key: str, v: Any) -> int:
        if not _is_number(v) or math.isnan(v) or math.isinf(v) or v != int(v):
            raise Bad('is %r, not a whole number' % (v,), '"%s: %s"' % (key, example))
        if v < lo:
            raise Bad('is %r, must be at least %d' % (v, lo), '"%s: %s"' % (key, example))
        return int(v)
    return check


def band(lo: float = 0.0, strict: bool = False, example: str = '[4.0, 16.0]') -> Kind:
    """A [min, max] pair of finite numbers, lo <= min <= max (min < max when strict)."""
    def check(key: str, v: Any) -> Tuple[float, float]:
        fix = '"%s: %s"' % (key, example)
        if not (isinstance(v, list) and len(v) == 2 and all(_is_number(b) for b in v)):
            raise Bad('is %r, not a [min, max] pair of numbers' % (v,), fix)
        if any(math.isnan(b) or math.isinf(b) for b in v):
            raise Bad('is %r, both ends must be finite numbers' % (v,), fix)
        if v[0] < lo:
            raise Bad('is %r, values below %g are impossible' % (v, lo), fix)
        if v[0] > v[1] or (strict and v[0] == v[1]):
            raise Bad('is %r, the minimum is not below the maximum' % (v,), fix)
        if v[1] <= 0:
            raise Bad('is %r, nothing can be inside it' % (v,), fix)
        return (float(v[0]), float(v[1]))
    return check


def text(example: str) -> Kind:
    def check(key: str, v: Any) -> str:
        if not isinstance(v, str) or not v.strip():
            raise Bad('is %r, not a text' % (v,), '%s: "%s" (quote it)' % (key, example))
        return v
    return check


def flag(key: str, v: Any) -> bool:
    if not isinstance(v, bool):
        raise Bad('is %r, not true or false' % (v,), '"%s: true"' % key)
    return v


def slot_ranges(example: str) -> Kind:
    """A list of [first, last] index pairs (inclusive), first <= last, none negative."""
    def check(key: str, v: Any) -> Tuple[Tuple[int, int], ...]:
        fix = '"%s: %s"' % (key, example)
        ok = isinstance(v, list) and v and all(
            isinstance(p, list) and len(p) == 2 and all(isinstance(i, int) and not isinstance(i, bool)
                                                        for i in p) for p in v)
        if not ok:
            raise Bad('is %r, not a list of [first, last] slot index pairs' % (v,), fix)
        for first, last in v:
            if first < 0 or last < first:
                raise Bad('has [%d, %d]: indices start at 0 and first <= last' % (first, last), fix)
        return tuple((int(a), int(b)) for a, b in v)
    return check


def named_slot_ranges(example: str) -> Kind:
    """A mapping of names to one [first, last] slot index pair each (inclusive), first <= last,
    none negative, no two overlapping: {right: [0, 14], front: [23, 37]}."""
    pair = slot_ranges(example)

    def check(key: str, v: Any) -> Tuple[Tuple[str, int, int], ...]:
        fix = '"%s: %s"' % (key, example)
        if not isinstance(v, dict) or not v:
            raise Bad('is %r, not a mapping of names to [first, last] slot pairs' % (v,), fix)
        out = []
        for name, slots in v.items():
            if not isinstance(name, str) or not name.strip():
                raise Bad('has the name %r: write a name such as front' % (name,), fix)
            (first, last), = pair(key, [slots])
            out.append((name, first, last))
        spans = sorted(out, key=lambda b: b[1])
        for a, b in zip(spans, spans[1:]):
            if b[1] <= a[2]:
                raise Bad('has %s [%d, %d] and %s [%d, %d] overlapping' % (a + b), fix)
        return tuple(out)
    return check


def names(example: str) -> Kind:
    def check(key: str, v: Any) -> Tuple[str, ...]:
        if not isinstance(v, list) or not all(isinstance(n, str) and n.strip() for n in v):
            raise Bad('is %r, not a list of names' % (v,), '"%s: [%s]"' % (key, example))
        return tuple(v)
    return check


# ---------------------------------------------------------------- the families

def _field(kind, default=None):
    return field(default=default, metadata={'kind': kind})


@dataclass(frozen=True)
class Expect:
    """Keys common to every sensor (reasons in config/sensorExpectations.yaml)."""
    rate: Optional[Tuple[float, float]] = _field(band(example='[4.0, 16.0]'))
    nominal: Optional[float] = _field(number(0, lo_open=True, example='10'))
    frame_id: Optional[str] = _field(text('base_footprint'))
    min_messages: int = _field(whole(0, '3'), 3)
    max_delay: float = _field(number(0, lo_open=True, example='5.0'), 5.0)
    max_future: float = _field(number(0, example='1.0'), 1.0)
    quick_messages: int = _field(whole(1, '10'), 10)
    max_gap_factor: float = _field(number(0, lo_open=True, example='3.0'), 3.0)
    # the driver profile (a name under `drivers:`) whose keys this sensor starts from; the
    # sensor's own keys override the profile's. None: no profile
    driver: Optional[str] = _field(text('naoqi_driver'))
    # why this driver may publish nothing at all while healthy (said with a "no message"
    # reason, e.g. a laser whose driver stops while the robot is at rest). None: nothing said
    silence_note: Optional[str] = _field(text('the driver publishes no scan while the robot is at rest'))

    @classmethod
    def field_names(cls) -> Tuple[str, ...]:
        return tuple(f.name for f in fields(cls))

    def but(self, **changes: Any) -> 'Expect':
        """A copy with some values changed (tests, variants); an unknown name raises TypeError."""
        return dataclasses.replace(self, **changes)


@dataclass(frozen=True)
class RangeExpect(Expect):
    field_of_view: Optional[Tuple[float, float]] = _field(band(example='[0.1, 1.2]'))
    # what the sensor can physically measure; None: the advertised limits of each message
    physical_range: Optional[Tuple[float, float]] = _field(band(example='[0.0, 5.0]'))


@dataclass(frozen=True)
class LaserExpect(Expect):
    ranges: Optional[int] = _field(whole(1, '61'))
    blind_value: Optional[float] = _field(number(example='-1.0'))
    # the driver's blind layout; None: any blind_value counts as blind
    blind_slots: Optional[Tuple[Tuple[int, int], ...]] = _field(slot_ranges('[[15, 22], [38, 45]]'))
    nan_is_no_return: bool = _field(flag, False)
    # +inf means "nothing in range" (REP 117; yohatad/naoqi_driver2's encodeRange); False: a
    # +inf reading is invalid
    inf_is_no_return: bool = _field(flag, True)
    # the boards (sensors) whose readings the scan is made of: name -> its slots [first, last];
    # a board with no valid reading in the window, or stuck, fails by name. None: not judged
    boards: Optional[Tuple[Tuple[str, int, int], ...]] = _field(
        named_slot_ranges('{right: [0, 14], front: [23, 37], left: [46, 60]}'))
    # a short human name of the expected layout and its source, said when a scan differs
    layout: Optional[str] = _field(text("naoqi_driver's 61 slots (laser.cpp:165-221)"))
    max_invalid_share: Optional[float] = _field(number(0, 1, example='0.5'))
    # N scans identical slot for slot in a row fail as stuck; None: not checked (a noise-free
    # simulated laser in a still world repeats itself legitimately)
    stuck_scans: Optional[int] = _field(whole(2, '20'))


@dataclass(frozen=True)
class ImageExpect(Expect):
    encoding: Optional[str] = _field(text('rgb8'))
    width: Optional[int] = _field(whole(1, '640'))
    height: Optional[int] = _field(whole(1, '480'))


@dataclass(frozen=True)
class CameraExpect(ImageExpect):
    min_brightness: float = _field(number(0, 255, example='5.0'), 5.0)
    min_spread: float = _field(number(0, example='2.0'), 2.0)
    # Pepper may send a frame twice at low rates: fewer than 3 identical frames is not "frozen"
    frozen_frames: int = _field(whole(3, '5'), 5)
    bad_frame_share: float = _field(number(0, 1, example='0.5'), 0.5)
    stereo: bool = _field(flag, False)     # the loader sets True for stereoCamera unless given


@dataclass(frozen=True)
class DepthExpect(ImageExpect):
    min_valid_share: Optional[float] = _field(number(0, 1, example='0.2'))
    median_range: Optional[Tuple[float, float]] = _field(band(example='[0.3, 8.0]'))
    video_range: Tuple[float, float] = _field(band(strict=True, example='[0.0, 5.0]'), (0.0, 5.0))
    # N identical consecutive depth images fail as frozen; None: not checked (see the yaml)
    frozen_frames: Optional[int] = _field(whole(3, '10'))
    # [min, max] m the camera can measure: a frame with most valid pixels outside it is
    # impossible data; None: not checked
    physical_range: Optional[Tuple[float, float]] = _field(band(example='[0.0, 10.0]'))
    # the sensor whose image an aligned depth topic (realsense-ros's aligned_depth_to_<stream>)
    # is aligned to: its size and frame_id must be that image's (sensors/depth.py); None: not checked
    aligned_to: Optional[str] = _field(text('realsenseRGBCamera'))


@dataclass(frozen=True)
class AudioExpect(Expect):
    sample_rate: int = _field(whole(1, '48000'), 48000)
    sample_rate_tolerance: float = _field(number(0, 1, hi_open=True, example='0.05'), 0.05)
    silence_dbfs: float = _field(number(hi=0, example='-70.0'), -70.0)
    max_clipping_share: float = _field(number(0, 1, example='0.01'), 0.01)
    # without `rate`: the message rate band is sample_rate / buffer size +- this share
    buffer_rate_tolerance: Optional[float] = _field(number(0, 1, hi_open=True, example='0.5'))
    # N identical consecutive buffers fail as stuck; None: not checked
    stuck_buffers: Optional[int] = _field(whole(2, '3'))
    # a channel silent (below silence_dbfs) from some time to the end for at least this many
    # seconds fails as "went silent at t = ..."; None: not checked
    channel_death_s: Optional[float] = _field(number(0, lo_open=True, example='1.0'))
    # every pair of the four channels differing by less than this share of a channel's own
    # one-sample step is a warning (one microphone dealt out over four channels,
    # sensors/channels.py); None: not checked
    similar_channels_ratio: Optional[float] = _field(number(0, lo_open=True, example='0.8'))


@dataclass(frozen=True)
class JointsExpect(Expect):
    joints: Tuple[str, ...] = _field(names('HeadYaw, HeadPitch'), ())
    # positions beyond Pepper's joint limits (joint_limits.py, from pepper_description's URDF)
    # by more than this many rad fail; None: limits not checked
    position_margin: Optional[float] = _field(number(0, example='0.05'), 0.05)
    # a position changing faster than limit x this factor (over max(dt, 0.1 s), every position
    # against the last 0.1 s) fails as a jump; the reported velocity above it is a warning;
    # None: not checked
    velocity_factor: Optional[float] = _field(number(1, example='1.5'), 1.5)


@dataclass(frozen=True)
class OdometryExpect(Expect):
    child_frame_id: Optional[str] = _field(text('base_link'))
    # poses under 0.5 s apart differing by more than this x 0.5 s, or further apart implying
    # more than this (m/s), are a jump and fail (sensors/jumps.py); None: off
    max_speed: Optional[float] = _field(number(0, lo_open=True, example='0.8'), 0.8)
    # |twist| differing from the pose-implied speed by more than this (m/s) in most of the
    # window fails as "twist contradicts the pose"; None: not checked
    twist_tolerance: Optional[float] = _field(number(0, lo_open=True, example='0.25'), 0.25)


@dataclass(frozen=True)
class ImuExpect(Expect):
    # N identical consecutive readings (rates and accelerations) fail as stuck; None: off
    stuck_messages: Optional[int] = _field(whole(2, '10'))
    # [min, max] m/s^2 the median |linear acceleration| must lie in (gravity included, the
    # robot upright); messages outside it are a warning; None: not checked
    acceleration_norm: Optional[Tuple[float, float]] = _field(band(example='[6.8, 12.8]'),
                                                              (6.8, 12.8))
    # rad/s beyond the gyrometer's range (~500 deg/s): impossible; None: not checked
    max_angular_velocity: Optional[float] = _field(number(0, lo_open=True, example='8.73'), 8.73)


@dataclass(frozen=True)
class SpeechExpect(Expect):
    text: str = _field(text('This is the CSSR4Africa speaker test.'),
                       'This is the CSSR4Africa speaker test.')
    subscriber_wait: float = _field(number(0, lo_open=True, example='3.0'), 3.0)
    listen_after: float = _field(number(0, example='4.0'), 4.0)


@dataclass(frozen=True)
class TouchExpect(Expect):
    # a zone pressed for longer than this (s) without a release fails as stuck: a touch or a
    # deliberate press lasts a second or two, a slow operator's press a few seconds
    max_press: float = _field(number(0, lo_open=True, example='8.0'), 8.0)


@dataclass(frozen=True)
class HealthExpect(Expect):
    # the verdict is given once this many arrays of the driver's statuses have arrived
    # (naoqi_driver publishes them at 1 Hz: share/boot_config.json "diag")
    arrays: int = _field(whole(1, '2'), 2)


@dataclass(frozen=True)
class MotionExpect(Expect):
    """The motion check's plan (--move; sensors/motion.py, motion/): small, slow, bounded
    moves, each waited for (reasons in config/sensorExpectations.yaml)."""
    # the head yaws to +head_yaw, -head_yaw and back to its start (rad); 0: no head part
    head_yaw: float = _field(number(0, 1.0, example='0.5'), 0.5)
    # /joint_angles speed, a fraction of the joint's maximum speed (teleop.cpp: setAngles)
    head_speed: float = _field(number(0, 0.5, lo_open=True, example='0.1'), 0.1)
    # the base turns in place by +base_turn and back (rad, /move_base_simple/goal); 0: no base part
    base_turn: float = _field(number(0, 1.0, example='0.5'), 0.5)
    # seconds one step may take to settle before it is judged as not reaching its target
    step_timeout: float = _field(number(1, 60, example='15.0'), 15.0)
    # a step has settled once the witnesses changed less than this (rad) for settle_time s
    settle_time: float = _field(number(0.1, 5, example='1.0'), 1.0)
    # a commanded joint within this of its target (rad) reached it
    joint_tolerance: float = _field(number(0, 0.5, lo_open=True, example='0.08'), 0.08)
    # a witness's turn within this share of the commanded turn (and the right sign) agrees
    turn_tolerance: float = _field(number(0, 1, lo_open=True, example='0.35'), 0.35)
    # below this share of the command, a witness saw no motion at all
    still_share: float = _field(number(0, 1, lo_open=True, example='0.2'), 0.2)
    # nothing may be closer than this (m) to the laser or sonars before the base turns
    clearance: float = _field(number(0, 5, lo_open=True, example='0.5'), 0.5)
    # during a turn, anything closer than this (m) stops the base at once
    stop_distance: float = _field(number(0, 5, lo_open=True, example='0.3'), 0.3)
    # a joint whose /diagnostics Stiffness is below this is not stiff (the robot is resting)
    min_stiffness: float = _field(number(0, 1, example='0.5'), 0.5)
    # seconds the witnesses are listened to before the first move (their first messages)
    witness_wait: float = _field(number(0.5, 30, example='3.0'), 3.0)


@dataclass(frozen=True)
class TfExpect(Expect):
    """The robot's transform tree (sensors/tf.py; reasons in config/sensorExpectations.yaml)."""
    # the frame at the tree's root (naoqi_driver: odom, joint_state.cpp:176)
    root: Optional[str] = _field(text('odom'))
    # frames the tree must hold (sensors' frames are looked up on their own rows)
    frames: Tuple[str, ...] = _field(names('base_link, base_footprint'), ())
    # a stamp this far ahead of its arrival is in the future (s)
    future: float = _field(number(0, example='0.1'), 0.1)
    # a stamp this far behind its arrival is stale (s)
    stale: float = _field(number(0, lo_open=True, example='0.5'), 0.5)
    # /naoqi_driver/odom's pose against odom -> base_link at its stamp (m, with 0.3 m per rad)
    odom_tolerance: float = _field(number(0, lo_open=True, example='0.05'), 0.05)
    # /joint_states' HeadYaw against torso -> Neck's turn at its stamp (rad)
    head_tolerance: float = _field(number(0, lo_open=True, example='0.02'), 0.02)


FAMILIES: Dict[str, Type[Expect]] = {'range': RangeExpect, 'laser': LaserExpect, 'camera': CameraExpect,
            'depth': DepthExpect, 'audio': AudioExpect, 'joints': JointsExpect,
            'odometry': OdometryExpect, 'imu': ImuExpect, 'speech': SpeechExpect,
            'touch': TouchExpect, 'health': HealthExpect, 'motion': MotionExpect,
            'tf': TfExpect}


def family_of(name: str) -> Type[Expect]:
    return FAMILIES[catalog.SENSORS[name].family]


def default_for(name: str) -> Expect:
    """The expectations of sensor `name` when the file says nothing about it."""
    return build(name, {})


def build(name: str, values: Dict[str, Any]) -> Expect:
    """A frozen expectations object from already validated values (see `load`)."""
    cls = family_of(name)
    values = dict(values)
    if cls is CameraExpect and 'stereo' not in values:
        values['stereo'] = name == 'stereoCamera'
    return cls(**{k: v for k, v in values.items() if k in cls.field_names()})


# ---------------------------------------------------------------- YAML with lines and duplicates

class Mapping(dict):
    """A YAML mapping that remembers the line of each key (1-based) and its own line."""
    line: Optional[int] = None

    def __init__(self) -> None:
        super().__init__()
        self.lines: Dict[Any, int] = {}


# libyaml's loader when PyYAML has it (Debian's and Ubuntu's do): about ten times faster than the
# pure-Python one, with the same marks (line numbers) for the error messages.
_SafeLoader = getattr(yaml, 'CSafeLoader', yaml.SafeLoader)


class _Loader(_SafeLoader):  # type: ignore[misc,valid-type]
    path: Optional[str] = None


def _construct_mapping(loader, node):
    originals = {id(k) for k, _ in node.value}
    loader.flatten_mapping(node)            # merge keys (<<: *anchor) may be overridden
    out = Mapping()
    out.line = node.start_mark.line + 1
    own_lines = set()                       # lines of keys written in this block (not merged)
    for key_node, value_node in node.value:
        key = loader.construct_object(key_node, deep=True)
        line = key_node.start_mark.line + 1
        try:
            hash(key)
        except TypeError:
            raise ConfigError('a key that is a list or mapping (%r)' % (key,), loader.path, line,
                              fix='keys are plain names, e.g. "rate:"') from None
        if key in out and id(key_node) in originals and out.lines[key] in own_lines:
            raise ConfigError('duplicate key "%s" (first on line %d); YAML would silently keep '
                              'only the last one' % (key, out.lines[key]), loader.path, line,
                              fix='keep one "%s:" line in this block' % key)
        out[key] = loader.construct_object(value_node, deep=True)
        out.lines[key] = line
        if id(key_node) in originals:
            own_lines.add(line)
    return out


_Loader.add_constructor('tag:yaml.org,2002:map', _construct_mapping)


def parse_yaml(path: str) -> Any:
    """The file's YAML as Mapping/list/scalars; ConfigError with the line on any problem."""
    content = read_text(path, 'expectations file',
                        fix_missing='give --expectations an existing file '
                                    '(default config/sensorExpectations.yaml)')
    loader = _Loader(content)
    loader.path = path
    try:
        return loader.get_single_data()
    except yaml.YAMLError as e:
        mark = getattr(e, 'problem_mark', None)
        raise ConfigError('cannot read expectations: %s' % str(e).splitlines()[0], path,
                          mark.line + 1 if mark is not None else None, fix='fix the YAML syntax') from None
    finally:
        loader.dispose()


# ---------------------------------------------------------------- validation

def _need_mapping(where, value, path, line):
    if value is None:
        return Mapping()
    if not isinstance(value, dict):
        raise ConfigError('%s is %r, not a mapping of "key: value" lines' % (where, value), path, line,
                          fix='indent "key: value" lines under it (see the comments at the top of '
                              'config/sensorExpectations.yaml)')
    return value


def _unknown_key(where, key, valid, path, line):
    close = difflib.get_close_matches(str(key), valid, n=1)
    hint = 'did you mean "%s"? ' % close[0] if close else ''
    return ConfigError('%s: unknown key "%s"' % (where, key), path, line,
                       fix='%svalid keys here: %s' % (hint, ', '.join(valid)))


def _kinds(cls):
    return {f.name: f.metadata['kind'] for f in fields(cls)}


def _validate(where, key, value, kind, path, line):
    try:
        return kind(key, value)
    except Bad as e:
        raise ConfigError('%s: %s %s' % (where, key, e.problem), path, line,
                          fix='write e.g. ' + e.fix) from None


def _lines(mapping) -> dict:
    """Key -> line of a parsed YAML mapping (empty for one built here)."""
    return getattr(mapping, 'lines', {})


def _read_sensors(where: str, section: Any, path: str) -> Dict[str, dict]:
    """A mapping of sensor blocks (a platform's section, or one driver profile) -> {canonical
    sensor name: validated values}; unknown sensors and keys, a sensor given twice stop it."""
    given: Dict[str, dict] = {}
    seen: Dict[str, tuple] = {}
    for spelling, block in section.items():
        line = _lines(section).get(spelling)
        name = catalog.canonical(str(spelling))
        if name is None:
            raise ConfigError('unknown sensor "%s" in section %s' % (spelling, where), path, line,
                              fix='valid sensors: ' + ', '.join(catalog.SENSORS))
        if name in seen:
            raise ConfigError('sensor "%s" appears twice in section %s (first on line %d, as "%s")'
                              % (spelling, where, seen[name][0], seen[name][1]), path, line,
                              fix='keep one block per sensor')
        seen[name] = (line, spelling)
        here = '%s.%s' % (where, spelling)
        block = _need_mapping(here, block, path, line)
        kinds = _kinds(family_of(name))
        values = {}
        for key, value in block.items():
            if key not in kinds:
                raise _unknown_key(here, key, sorted(kinds), path, _lines(block).get(key))
            values[key] = _validate(here, key, value, kinds[key], path, _lines(block).get(key))
        given[name] = values
    return given


def _read_drivers(data: Any, path: str) -> Dict[str, Dict[str, dict]]:
    """The `drivers:` section -> {profile name: {sensor name: validated values}}."""
    section = _need_mapping('drivers', data.get('drivers'), path, _lines(data).get('drivers'))
    out = {}
    for profile, sensors in section.items():
        line = _lines(section).get(profile)
        where = 'drivers.%s' % profile
        sensors = _need_mapping(where, sensors, path, line)
        out[str(profile)] = _read_sensors(where, sensors, path)
        for spelling, block in sensors.items():
            if isinstance(block, dict) and 'driver' in block:
                raise ConfigError('%s.%s: a driver profile cannot name another (driver: %s)'
                                  % (where, spelling, block['driver']), path,
                                  _lines(block).get('driver'), fix='remove the "driver:" line here')
    return out


def load(path: str, platform: str, driver: Optional[str] = None) -> Dict[str, Expect]:
    """Expectations file -> {canonical sensor name: frozen expectations} for `platform`.

    A sensor's values: `defaults`, then the keys of its driver profile (`driver: name` in its
    block, a name under `drivers:`), then its own keys. `driver` (when given) names the profile
    for every sensor that profile describes, whatever the blocks say (a recording of another
    driver); an unknown name stops it with the profiles known."""
    data = parse_yaml(path)
    if data is None:
        data = Mapping()
    if not isinstance(data, dict):
        raise ConfigError('expected a mapping with "defaults", "robot" and "simulator"', path, 1,
                          fix='see the comments at the top of config/sensorExpectations.yaml')
    for key in data:
        if key not in SECTIONS:
            raise _unknown_key('top level', key, list(SECTIONS), path, _lines(data).get(key))
    every = {}
    for cls in FAMILIES.values():
        every.update(_kinds(cls))
    defaults = _need_mapping('defaults', data.get('defaults'), path, _lines(data).get('defaults'))
    checked_defaults = {}
    for key, value in defaults.items():
        if key not in every:
            raise _unknown_key('defaults', key, sorted(every), path, _lines(defaults).get(key))
        checked_defaults[key] = _validate('defaults', key, value, every[key], path, _lines(defaults).get(key))
    profiles = _read_drivers(data, path)
    if driver is not None and driver not in profiles:
        raise ConfigError('unknown driver profile "%s"' % driver, path, _lines(data).get('drivers'),
                          fix='known profiles under "drivers:": %s' % (', '.join(profiles) or 'none'))
    section = _need_mapping(platform, data.get(platform), path, _lines(data).get(platform))
    given = _read_sensors(platform, section, path)
    out = {}
    for name in catalog.SENSORS:
        values = {k: v for k, v in checked_defaults.items() if k in family_of(name).field_names()}
        own = given.get(name, {})
        profile = driver if driver is not None and name in profiles[driver] else own.get('driver')
        if profile is not None:
            if profile not in profiles:
                block = section.get(next((s for s in section if catalog.canonical(str(s)) == name), name), {})
                raise ConfigError('%s.%s: unknown driver profile "%s"' % (platform, name, profile), path,
                                  _lines(block).get('driver'),
                                  fix='known profiles under "drivers:": %s' % (', '.join(profiles) or 'none'))
            values.update(profiles[profile].get(name, {}))
        values.update(own)
        if profile is not None:
            values['driver'] = profile
        out[name] = build(name, values)
    return out
