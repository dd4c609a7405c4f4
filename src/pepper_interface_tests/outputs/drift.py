"""Drift: what moved since this robot's baseline run, value by value (pure; no files, no ROS).

A baseline is a run of the same robot on a good day (outputs/baseline.py pins one). For every
sensor both runs measured, `measures(result)` takes the values that wear shows in (a cheap
number per value, from the sensor's rate and its family's values dataclass) and `drift(then,
now, ref)` compares them, each with the margin of its row in RULES. A value beyond its margin is
a Drift (results.py) and a warning on the sensor naming the value then and now: a WARN, never a
FAIL (the absolute rules decide failures). docs/drift.md lists every margin with its reason.

Margins are about the sensor, not the room: a value the surroundings change (brightness in
another room, a sonar's distance) has a wide margin and its warning says the room may differ;
the microphones are compared with each other (one channel against the change of the other
three), so a louder room moves all four and warns about none.
"""
import math
import statistics
from dataclasses import dataclass
from typing import Dict, List, Optional, Tuple

from ..results import FAIL, PASS, Drift, SensorResult
from ..sensors import families
from ..sensors.values.audio import AudioValues
from ..sensors.values.camera import CameraValues
from ..sensors.values.depth import DepthValues
from ..sensors.values.health import HealthValues
from ..sensors.values.imu import ImuValues
from ..sensors.values.joints import JointsValues
from ..sensors.values.laser import LaserValues
from ..sensors.values.motion import MotionValues
from ..sensors.values.range import RangeValues

MIN_RATE_MESSAGES = 10        # a rate from fewer messages (robotHealth's 1 Hz arrays) is too coarse
WHOLE = ('dBFS', 'degC')      # units shown in whole numbers
ROOM = 'or the room differs from the baseline\'s'


@dataclass(frozen=True)
class Rule:
    """How one kind of measured value is compared with the baseline's."""
    label: str              # what it is, '%s' the subject (a channel, a board, a joint) if any
    unit: str
    margin: float           # beyond this it drifted: a share of the baseline's value when relative
    relative: bool
    up: str                 # the change in words, when the value rose ...
    down: str               # ... and when it fell
    advice: str             # what to look at
    reason: str             # why this margin (docs/drift.md repeats it)
    floor: float = 0.0      # a relative margin: no change smaller than this is a drift (in unit)
    way: int = 0            # +1: only a rise is wear, -1: only a fall, 0: either
    many: str = ''          # the advice when GROUP or more subjects drift together
    against: str = ''       # the margin is against these, not against the value then

    def beyond(self, then: float, now: float) -> bool:
        if self.way and (now - then) * self.way <= 0:
            return False
        if self.relative:
            return then > 0 and abs(now - then) > max(self.margin * then, self.floor)
        return abs(now - then) > self.margin

    def margin_text(self) -> str:
        if self.against:
            return '%g %s against %s' % (self.margin, {'dBFS': 'dB'}.get(self.unit, self.unit), self.against)
        if self.relative:
            return '%g %% of the baseline\'s' % (100 * self.margin) + \
                (', at least %g%s' % (self.floor, _unit_of(self.unit)) if self.floor else '')
        return '%g%s' % (self.margin, ' points' if self.unit == '%' else _unit_of(self.unit))


RULES: Dict[str, Rule] = {
    'rate': Rule(
        'message rate', 'Hz', 0.30, True, 'faster', 'slower',
        'check the driver\'s settings and the robot\'s load',
        'a healthy stream keeps its rate within a few per cent from run to run (the emulator\'s '
        'streams: within 1 %, its loaded cameras at 1.3 fps within 3 %); a busy machine adds a '
        'few per cent more; a driver update or a failing board halves it'),
    'brightness': Rule(
        'brightness', '/255', 0.35, True, 'brighter', 'darker',
        'check the lens and the exposure, %s (its light)' % ROOM,
        'the same room under the same light gives the same mean within about 10 %; a dusty or '
        'covered lens or a failing exposure takes a third off; another room changes it too'),
    'contrast': Rule(
        'contrast (pixel spread)', '/255', 0.35, True, 'more contrast', 'less contrast',
        'check the lens (dust, a smear), %s' % ROOM,
        'the spread of a still scene varies by about 10 % between runs; haze on the lens flattens it'),
    'sharpness': Rule(
        'sharpness (Laplacian / grey variance)', '', 0.50, True, 'sharper', 'blurred',
        'check the focus and the lens, %s (its detail)' % ROOM,
        'the focus measure of one scene varies by about 20 % between runs; a knocked lens or a '
        'smear halves it or worse', way=-1),
    'noise': Rule(
        'image noise', '/255', 0.50, True, 'noisier', 'less noisy',
        'check the sensor\'s gain and temperature, %s (darker rooms are noisier)' % ROOM,
        'the noise of one sensor at one light level varies by about 20 %; an ageing or hot '
        'sensor adds half again; under 0.5 grey levels of change is not worth a word', floor=0.5, way=1),
    'valid_share': Rule(
        'valid share', '%', 10.0, False, 'more valid readings', 'fewer valid readings',
        'check the window in front of it for dirt or scratches',
        'the share of valid readings of a healthy sensor in one place moves by a few hundredths; '
        'a scratched or dirty window loses a tenth or more', way=-1),
    'distance': Rule(
        'distance (the middle third of the frame)', 'm', 0.75, True, 'farther', 'nearer',
        'check that nothing covers it, %s' % ROOM,
        'the distance follows the room and where the robot looks (a robot turning in a room '
        'halves it from run to run): only a collapse to a quarter (a hand, a cover, dirt in '
        'front of the lens) is worth a word', way=-1),
    'range_noise': Rule(
        'range noise (sd)', 'm', 1.0, True, 'noisier', 'less noisy',
        'check the sensor\'s window and mounting',
        'a still sensor\'s scatter is its own; a doubling is wear or a loose mounting, not the '
        'room; under 5 mm of change is below what a sonar or the laser resolves', floor=0.005, way=1),
    'level': Rule(
        'level', 'dBFS', 6.0, False, 'louder', 'quieter',
        'check that microphone\'s grille',
        'the four microphones hear one room within a few dB of each other; a channel that moves '
        '6 dB against the other three (a clogged grille, a failing capsule) is the microphone',
        against='the change of the other channels'),
    'gyro_bias': Rule(
        'gyro bias (mean angular speed at rest)', 'rad/s', 0.01, False, 'larger', 'smaller',
        'recalibrate the IMU (keep the robot still during the run)',
        'a still gyrometer reads within about 0.003 rad/s of zero; a bias growing by 0.01 rad/s '
        '(0.6 deg/s) is drift of the sensor', way=1),
    'gyro_noise': Rule(
        'gyro noise (sd of the angular speed)', 'rad/s', 1.0, True, 'noisier', 'quieter',
        'check the IMU board',
        'the noise of a still gyrometer is its own; a doubling is the sensor; under 0.002 rad/s '
        'of change is within a healthy gyrometer\'s own noise', floor=0.002, way=1),
    'gravity': Rule(
        'gravity magnitude', 'm/s^2', 0.3, False, 'larger', 'smaller',
        'recalibrate the accelerometer',
        'gravity is 9.81 m/s^2 everywhere a robot goes; a still accelerometer reads it within '
        '0.1 m/s^2 from run to run'),
    'joint_noise': Rule(
        '%s position noise', 'rad', 1.0, True, 'noisier', 'quieter',
        'check that joint\'s encoder (keep the robot still during the run)',
        'a still joint\'s encoder noise is its own; a doubling is a worn encoder or a loose '
        'magnet; a change under 0.001 rad (0.06 deg) is not worth a word (a real Pepper\'s '
        'still joints were not measured here: the floor is a judgement, not a datasheet '
        'figure)', floor=0.001, way=1,
        many='many joints at once: check that the robot stood still, then the supply of the '
             'encoders and the boards that read them'),
    'follow_error': Rule(
        '%s follow error (mean |measured - commanded| per step)', 'rad', 0.05, False, 'larger',
        'smaller',
        'check that part (friction in the head, a wheel slipping or worn) or that witness',
        'a --move run commands the same small, slow steps each time (0.5 rad); a healthy head, '
        'base and witness follow them within a few hundredths of a radian, with a spread from '
        'run to run of about 0.01 rad (the laser\'s scan matching the widest: 0.474 and 0.467 for '
        '0.5 rad through the real naoqi_driver); 0.05 rad (3 deg) more is a part that follows '
        'worse or a witness that measures worse', way=1),
    'temperature': Rule(
        '%s temperature', 'degC', 8.0, False, 'hotter', 'cooler',
        'check that joint (friction, a stalled motor) %s (its temperature, the robot\'s work '
        'before the run)' % ROOM,
        'a joint at rest settles within a few degrees of where it did; 8 degC hotter in the same '
        'conditions is friction or a motor working against something', way=1,
        many='many joints at once: the room is warmer or the robot worked before the run'),
}

# the witnesses whose follow error drifts, per motion part (motion/rules.py names them)
FOLLOWED: Dict[str, Tuple[str, ...]] = {'head': ('HeadYaw',), 'base': ('odometry', 'gyro_z', 'laser')}


def _unit_of(unit: str) -> str:
    """A unit as it follows a number: ' m', '/255', '%'."""
    return (' ' + unit) if unit and unit[0] not in '/%' else unit


def _rule(key: str) -> Tuple[Rule, str]:
    kind, _, subject = key.partition(':')
    return RULES[kind], subject


def _label(rule: Rule, subject: str) -> str:
    """'rearLeft level', 'HipPitch position noise', 'brightness'."""
    if '%s' in rule.label:
        return rule.label % subject
    return '%s %s' % (subject, rule.label) if subject else rule.label


def _finite(v: Optional[float]) -> bool:
    return v is not None and isinstance(v, (int, float)) and math.isfinite(v)


def measures(r: SensorResult) -> Dict[str, float]:
    """The values of one sensor's result that drift is judged on: key -> number, the key
    'kind' or 'kind:subject' (a channel, board or joint), the kind a row of RULES."""
    out: Dict[str, Optional[float]] = {}
    fam = families.FAMILIES.get(r.family)
    if r.rate_hz and fam is not None and fam.traits.periodic and not fam.traits.drives_itself \
            and r.messages >= MIN_RATE_MESSAGES:
        out['rate'] = r.rate_hz        # event streams (touch) have no rate of their own
    v = r.values
    if isinstance(v, CameraValues):
        out['brightness'] = v.brightness_mean.mean if v.brightness_mean else None
        out['contrast'] = v.brightness_spread.mean if v.brightness_spread else None
        out['sharpness'] = v.sharpness
        out['noise'] = v.noise
    elif isinstance(v, DepthValues):
        out['valid_share'] = 100 * v.valid_share.mean if v.valid_share and v.valid_share.mean is not None \
            else None
        out['distance'] = v.centre_depth_m if v.centre_depth_m is not None else \
            v.depth_m.median if v.depth_m else None
    elif isinstance(v, LaserValues):
        for board, share in (v.board_valid_share or {}).items():
            out['valid_share:' + board] = 100 * share
        if v.invalid_share is not None and not v.board_valid_share:
            out['valid_share'] = 100 * (1.0 - v.invalid_share)
        out['range_noise'] = v.range_noise_m
    elif isinstance(v, RangeValues):
        if r.messages:
            out['valid_share'] = 100 * (1.0 - (v.infinite_ranges or 0) / r.messages)
        out['range_noise'] = v.range_noise_m
    elif isinstance(v, AudioValues):
        for ch, level in (v.channels or {}).items():
            out['level:' + ch] = level.rms_dbfs
    elif isinstance(v, ImuValues):
        out['gyro_bias'] = v.angular_velocity_norm_rad_s.mean if v.angular_velocity_norm_rad_s else None
        out['gyro_noise'] = v.angular_velocity_noise_rad_s
        out['gravity'] = v.acceleration_norm_median_m_s2
    elif isinstance(v, JointsValues):
        for joint, noise in (v.position_noise_rad or {}).items():
            out['joint_noise:' + joint] = noise
    elif isinstance(v, MotionValues):
        # --move runs: how closely the head and the base followed each command, per witness
        # (the mean over the settled steps of |measured change - commanded change|)
        errors: Dict[str, List[float]] = {}
        for step in v.steps:
            if not step.settled:
                continue
            for witness in FOLLOWED.get(step.part, ()):
                got = step.measured.get(witness)
                if _finite(got):
                    errors.setdefault(witness, []).append(abs(float(got) - step.commanded))  # type: ignore[arg-type]
        for witness, errs in errors.items():
            out['follow_error:' + witness] = statistics.mean(errs)
    elif isinstance(v, HealthValues):
        for joint, temp in (v.temperatures or {row.joint: row.temperature_c for row in v.hottest
                                                 if row.temperature_c is not None}).items():
            out['temperature:' + joint] = temp
    return {k: float(x) for k, x in out.items() if _finite(x)}   # type: ignore[arg-type]


@dataclass(frozen=True)
class Ref:
    """The baseline run as a warning names it."""
    run_id: str
    day: str                # YYYY-MM-DD


def _num(v: float, rule: Rule) -> str:
    """Three significant digits, none after the point from 100 on (nor for dB and degrees):
    0.00213, 9.81, 1530, -41 dBFS."""
    if v == 0 or abs(v) >= 100 or rule.unit in WHOLE:
        return '%.0f' % v
    return '%.*f' % (max(0, 2 - int(math.floor(math.log10(abs(v))))), v)


def _unit(rule: Rule) -> str:
    return _unit_of(rule.unit)


def _sentence(label: str, rule: Rule, then: float, now: float, change: str, extra: str, ref: Ref) -> str:
    unit = _unit(rule)
    return '%s %s%s, was %s%s on %s (run %s): %s%s: %s' % (
        label, _num(now, rule), unit, _num(then, rule), unit, ref.day, ref.run_id, change, extra, rule.advice)


def _change(rule: Rule, then: float, now: float) -> str:
    word = rule.up if now > then else rule.down
    if rule.relative and now >= 2 * then:
        ratio = now / then
        return '%s: %s times the baseline\'s' % (word, '%.1f' % ratio if ratio < 10 else '%.0f' % ratio)
    if rule.relative:
        return '%.0f %% %s' % (100 * abs(now - then) / then, word)
    unit = {'dBFS': 'dB', '%': ' points'}.get(rule.unit, ' ' + rule.unit if rule.unit else '')
    return '%s%s %s' % (_num(abs(now - then), rule), unit, word)


def drift(then: SensorResult, now: SensorResult, ref: Ref) -> List[Drift]:
    """Each value of `now` beyond its margin from the baseline's `then` (both the same sensor).
    Nothing when the baseline's sensor did not pass or this one was not judged."""
    if then.verdict != PASS or now.verdict not in (PASS, FAIL):
        return []
    a, b = measures(then), measures(now)
    out: List[Drift] = []
    levels = {k: b[k] - a[k] for k in b if k.startswith('level:') and k in a}
    for key in (k for k in b if k in a):
        rule, subject = _rule(key)
        x, y = a[key], b[key]
        label = _label(rule, subject)
        extra = ''
        if rule is RULES['level']:
            # one channel against the others: a louder or quieter room moves all four
            others = [d for k, d in levels.items() if k != key]
            if not others:
                continue
            common = statistics.median(others)
            moved = (y - x) - common
            if abs(moved) <= rule.margin:
                continue
            change = '%.0f dB %s' % (abs(moved), rule.up if moved > 0 else rule.down)
            spread = max(abs(d - common) for d in others)
            extra = ', the others within %.0f dB' % max(1.0, math.ceil(spread)) if abs(common) < 1.5 else \
                ', the others %.0f dB %s (the room)' % (abs(common), 'louder' if common > 0 else 'quieter')
            if abs(common) >= 1.5:
                change = '%.0f dB %s than the others' % (abs(moved), rule.up if moved > 0 else rule.down)
        else:
            if not rule.beyond(x, y):
                continue
            change = _change(rule, x, y)
        text = _sentence(label, rule, x, y, change, extra, ref)
        out.append(Drift(measure=key, label=label, unit=rule.unit, then=x, now=y, change=change,
                         margin=rule.margin_text(), text=text))
    return _grouped(out, a, ref)


GROUP = 4       # this many subjects (joints, boards) of one kind drifting: one warning for them all


def _grouped(found: List[Drift], a: Dict[str, float], ref: Ref) -> List[Drift]:
    """Drifts of GROUP or more subjects of one kind (every joint noisier) as one: something
    they share (a supply, the board reading them) rather than each one, and one line to read."""
    by_kind: Dict[str, List[Drift]] = {}
    for d in found:
        kind, _, subject = d.measure.partition(':')
        if subject:
            by_kind.setdefault(kind, []).append(d)
    out = []
    for d in found:
        kind, _, subject = d.measure.partition(':')
        group = by_kind.get(kind, [])
        if len(group) < GROUP or not subject:
            out.append(d)
            continue
        if d is not group[0]:
            continue
        rule = RULES[kind]
        of = sum(1 for k in a if k.startswith(kind + ':'))
        names = [g.measure.partition(':')[2] for g in group]
        then = statistics.median(g.then for g in group if g.then is not None)
        now = statistics.median(g.now for g in group if g.now is not None)
        label = '%s of %s' % ((rule.label % '').strip(), 'all %d' % of if len(group) == of else
                              '%d of %d (%s)' % (len(group), of, ', '.join(names)))
        change = 'median ' + _change(rule, then, now)
        unit = _unit(rule)
        text = '%s: median %s%s, was %s%s on %s (run %s): %s: %s' % (
            label, _num(now, rule), unit, _num(then, rule), unit, ref.day, ref.run_id, change,
            rule.many or rule.advice)
        out.append(Drift(measure=kind + ':*', label=label, unit=rule.unit, then=then, now=now, change=change,
                         margin=rule.margin_text(), text=text))
    return out


def table(then: SensorResult, now: SensorResult) -> List[Tuple[str, float, float, str, bool]]:
    """Every value both runs measured, drifted or not: (label, then, now, margin, beyond) for
    `sensorTestHistory compare` and the report."""
    a, b = measures(then), measures(now)
    found = drift(then, now, Ref('', ''))
    drifted = {d.measure for d in found}
    grouped = {d.measure.partition(':')[0] for d in found if d.measure.endswith(':*')}
    rows = []
    for key in (k for k in b if k in a):
        rule, subject = _rule(key)
        label = _label(rule, subject)
        rows.append((label + (' (%s)' % rule.unit if rule.unit and rule.unit[0] not in '/%' else ''),
                     a[key], b[key], rule.margin_text(),
                     key in drifted or (key.partition(':')[0] in grouped and rule.beyond(a[key], b[key]))))
    return rows


def apply(result: SensorResult, then: SensorResult, ref: Ref) -> List[Drift]:
    """Record the drift of `result` from `then` on it: result.drift and one warning each."""
    found = drift(then, result, ref)
    result.drift = list(found)
    result.warnings.extend(d.text for d in found)
    return found
