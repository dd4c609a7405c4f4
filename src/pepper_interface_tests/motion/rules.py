"""The motion check's rules: what each witness measured in each step, judged on the row of the
sensor it concerns (RunContext.findings), and the motion row's own verdict.

Head steps (HeadYaw commanded to start + a, start - a, start):
- jointState: HeadYaw moves the commanded way and ends within `joint_tolerance` of its target;
  one that does not move while a head camera saw the head turn fails by name (a stuck encoder);
- head cameras (front, bottom, stereo, depth): the picture moves sideways the right way (a head
  yawing left moves the scene right: estimate.picture_shift), at least MIN_SHIFT pixels of the
  ~80-pixel-wide copy; a live picture that does not follow fails, unless the room has too
  little texture to follow (MIN_TEXTURE, a plain floor: then a warning says so); a picture
  that did not change at all while the head turned fails whatever its texture.
Base steps (a turn in place by +t, then -t):
- the witnesses vote: wheel encoders (jointState), the gyro (imu, integrated z), odometry (its
  yaw) and the laser (the scan's turn). A witness "saw a turn" when it changed by at least
  `still_share` of the command. When most of those present saw it, the base turned and each
  one that did not, or saw it the wrong way, on the wrong axis, or by more than
  `turn_tolerance` of the command away, fails on its row with what it saw. When most did not,
  the base did not move: the motion row fails (the actuator, not a sensor) and no sensor is
  failed (a lone witness that saw a turn gets a warning).
- motion row: PASS when the head and the base moved as commanded; FAIL when a part was
  commanded but did not move while its witnesses agree it did not (with the usual causes);
  SKIPPED with the reason when a part did not run (the checks before moving, the operator, a
  safety stop).
"""
import math
from typing import Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np

from ..plan.expectations import MotionExpect
from . import estimate
from .record import WHEELS, Recording
from .sequence import HEAD_YAW_SPEED, Step
from .sequence import Sequence as Run
from .witnesses import HEAD_CAMERAS

MIN_SHIFT = 2.0       # pixels of the ~80-pixel-wide copy: a 0.5 rad yaw moves it ~30-40
# rad the head may turn between two frames for their shift to be measured: picture_shift looks
# a third of the width either way, and Pepper's head cameras see about 1 rad across (front and
# bottom 56 deg, depth 58 deg: doc.aldebaran.com/2-5/family/pepper_technical/video_pep.html), so
# 0.3 rad (24 of 80 pixels) is the most; a loaded robot's 1.3 fps at head_speed 0.1 (0.73 rad/s)
# turns 0.56 rad between frames: its cameras are then not judged (a warning says why)
MAX_TURN_PER_FRAME = 0.3
# grey levels (mm for a depth camera) the still picture must differ from itself moved
# TEXTURE_LAG pixels sideways (estimate.still_texture) for a picture that did not follow the
# head to fail: with less, the room has nothing to follow (a plain floor or wall) and what
# moves on its own (a person, a ball) decides the shift. In the emulator's room, measured at
# 21 headings of each view, every 0.1 rad turn measured wrong had a still texture under 0.6
# and every heading at 0.75 or more was measured right; a real camera's noise adds about 0.05
# (8x8 blocks averaged, a median of frames, the blur). Below it the camera gets a warning.
MIN_TEXTURE = 0.75
WHEEL_STILL = 0.3     # rad of wheel rotation (summed over the three): a 0.5 rad turn is ~3 rad

HEAD_CAUSES = ('the robot is resting (stiffness off), Autonomous Life holds the head, a joint '
               'too hot, or naoqi_driver has no /joint_angles subscriber')
BASE_CAUSES = ('the robot is resting (stiffness off), the charging flap is open (ALMotion does '
               'not move the base then), collision protection saw an obstacle, the robot is '
               'on its charging station, or naoqi_driver has no /move_base_simple/goal subscriber')

Add = Callable[[str, List[str], List[str]], None]   # (sensor, fail reasons, warnings)


def _r(x: Optional[float]) -> str:
    return 'nothing' if x is None else '%+.2f' % x


def _sign(x: float) -> int:
    return 1 if x > 0 else -1 if x < 0 else 0


class Judge:
    def __init__(self, run: Run, rec: Recording, expect: MotionExpect, add: Add) -> None:
        self.run, self.rec, self.e, self.add = run, rec, expect, add
        self.motion_fail: List[str] = []
        self.motion_warn: List[str] = []
        self.measured: Dict[int, Dict[str, Optional[float]]] = {}
        self.head_state: Optional[str] = None
        self.base_state: Optional[str] = None
        self.found: Dict[str, List[str]] = {}      # sensor -> reasons (first per sensor kept)
        self.warned: Dict[str, List[str]] = {}
        self.slow: Dict[str, float] = {}           # camera -> the longest gap between frames (s)
        # camera -> its picture did not change at all over the last step: no camera's noise
        # and nothing moving on its own, a feed not following whatever its texture
        self.unchanged: Dict[str, bool] = {}
        self.told: Dict[str, set] = {'head': set(), 'base': set()}   # part -> witnesses that could tell

    def _fail(self, sensor: str, text: str) -> None:
        self.found.setdefault(sensor, [])
        if not self.found[sensor]:
            self.found[sensor].append(text)

    def _warn(self, sensor: str, text: str) -> None:
        self.warned.setdefault(sensor, []).append(text)

    def completed(self) -> List[Step]:
        return [s for s in self.run.steps[:self.run.index] if s.sent is not None and s.ended is not None]

    # ---------------------------------------------------------------- head
    def _camera_shift(self, cam: str, t0: float, t1: float) -> Optional[float]:
        """The picture's shift over a head step, summed frame to frame; None when it cannot be
        told: fewer than two frames, flat frames, or frames too far apart for the head's speed
        (see MAX_TURN_PER_FRAME)."""
        with self.rec.lock:
            frames = list(self.rec.frames.get(cam, []))
        before = [(t, f) for t, f in frames if t <= t0]
        inside = [(t, f) for t, f in frames if t0 < t <= t1]
        seq = before[-1:] + inside
        if len(seq) < 2:
            return None
        rate = self.e.head_speed * HEAD_YAW_SPEED
        if any((b[0] - a[0]) * rate > MAX_TURN_PER_FRAME for a, b in zip(seq, seq[1:])):
            self.slow[cam] = max(b[0] - a[0] for a, b in zip(seq, seq[1:]))
            return None
        total, seen = 0.0, False
        self.unchanged[cam] = all(np.array_equal(a[1], b[1]) for a, b in zip(seq, seq[1:]))
        for a, b in zip(seq, seq[1:]):
            s = estimate.picture_shift(a[1], b[1])
            if s is not None:
                total += s
                seen = True
        return total if seen else None

    def _texture(self, cam: str, t0: float, t1: float) -> Optional[float]:
        """The least still texture of the head's view before the step (the frames of the
        settle_time before t0) and after it (those of the settle_time up to t1, when the step
        had settled); None when neither has a frame."""
        span = self.e.settle_time
        with self.rec.lock:
            frames = list(self.rec.frames.get(cam, []))
        found = [estimate.still_texture([f for t, f in frames if a - span <= t <= a])
                 for a in (t0, t1)]
        values = [v for v in found if v is not None]
        return min(values) if values else None

    def head_step(self, i: int, step: Step) -> Optional[bool]:
        e = self.e
        assert step.sent is not None and step.ended is not None
        t0, t1 = step.sent, step.ended
        enc = estimate.change(self.rec.joint_series('HeadYaw'), t0, t1, angle=False)
        m: Dict[str, Optional[float]] = {'HeadYaw': enc}
        for cam in HEAD_CAMERAS:
            if cam in self.rec.frames:
                m[cam] = self._camera_shift(cam, t0, t1)
        self.measured[i] = m
        still = e.still_share * abs(step.commanded)
        enc_moved = enc is not None and abs(enc) >= still
        cams = {c: v for c, v in m.items() if c != 'HeadYaw' and v is not None}
        self.told['head'] |= ({'HeadYaw encoder'} if enc is not None else set()) | set(cams)
        cam_moved = [c for c, v in cams.items() if abs(v) >= MIN_SHIFT]
        moved = enc_moved or len(cam_moved) > len(cams) / 2 if cams else enc_moved
        if not moved:
            return False
        end = estimate.value_at(self.rec.joint_series('HeadYaw'), t1)
        if not enc_moved:
            self._fail('jointState', 'HeadYaw did not move (changed %s rad) when commanded %+.2f rad, '
                       'while %s saw the head turn: its encoder is stuck'
                       % (_r(enc), step.commanded, ', '.join(cam_moved) or 'the cameras'))
        elif _sign(enc or 0) != _sign(step.commanded):
            self._fail('jointState', 'HeadYaw moved the wrong way: %s rad when commanded %+.2f rad'
                       % (_r(enc), step.commanded))
        elif end is not None and abs(end - step.target) > e.joint_tolerance:
            self._fail('jointState', 'HeadYaw ended at %+.2f rad, not within %.2f rad of its target '
                       '%+.2f rad' % (end, e.joint_tolerance, step.target))
        for cam in HEAD_CAMERAS:
            if cam not in m:
                continue
            v = m[cam]
            if v is None and cam in self.slow:
                self._warn(cam, 'not judged on the head\'s motion: %.1f s between two frames while '
                           'the head turned up to %.2f rad/s (more than %.1f rad between frames)'
                           % (self.slow[cam], self.e.head_speed * HEAD_YAW_SPEED, MAX_TURN_PER_FRAME))
            elif v is None:
                self._warn(cam, 'could not tell whether the picture follows the head (a flat '
                           'picture or too few frames while it yawed)')
            elif abs(v) >= MIN_SHIFT and _sign(v) == _sign(step.commanded):
                continue
            elif not self.unchanged.get(cam) and (self._texture(cam, t0, t1) or 0.0) < MIN_TEXTURE:
                self._warn(cam, 'not judged on the head\'s motion: the still picture has too '
                           'little texture to follow (a plain floor or wall; less than %.2f '
                           'grey levels between it and itself moved %d pixels sideways): the '
                           'picture moved %+.1f px while the head yawed %+.2f rad'
                           % (MIN_TEXTURE, estimate.TEXTURE_LAG, v, step.commanded))
            elif abs(v) < MIN_SHIFT:
                self._fail(cam, 'live but not following the head: the picture moved %.1f px while '
                           'the head yawed %+.2f rad' % (v, step.commanded))
            elif _sign(v) != _sign(step.commanded):
                self._fail(cam, 'the picture moved the wrong way: %+.1f px (%s) while the head '
                           'yawed %+.2f rad (%s: the scene should move right)'
                           % (v, 'left' if v < 0 else 'right', step.commanded,
                              'left' if step.commanded > 0 else 'right'))
        return True

    # ---------------------------------------------------------------- base
    def base_step(self, i: int, step: Step) -> Optional[bool]:
        e = self.e
        assert step.sent is not None and step.ended is not None
        t0, t1, c = step.sent, step.ended, step.commanded
        with self.rec.lock:
            odom_s = list(self.rec.odom_yaw)
            gyro = list(self.rec.gyro)
            scans = list(self.rec.scans)
        odom = estimate.change(odom_s, t0, t1) if odom_s else None
        g = estimate.integrated_gyro(gyro, t0, t1) if gyro else None
        laser = None
        before = [s for s in scans if s.t <= t0]
        after = [s for s in scans if t0 < s.t <= t1]
        if before and after:
            laser = estimate.scan_turn(before[-1].ranges, after[-1].ranges, before[-1].increment)
        wheels = None
        series = [self.rec.joint_series(w) for w in WHEELS]
        if any(series):
            # wheel angles may wrap at +-pi (a continuous joint): changes are summed unwrapped
            wheels = sum(abs(estimate.change(s, t0, t1) or 0.0) for s in series if s) + 0.0
        m = {'odometry': odom, 'gyro_z': g[2] if g else None, 'gyro_x': g[0] if g else None,
             'gyro_y': g[1] if g else None, 'laser': laser, 'wheels': wheels}
        self.measured[i] = m
        still = e.still_share * abs(c)
        saw: Dict[str, bool] = {}
        if odom is not None:
            saw['odometry'] = abs(odom) >= still
        if g is not None:
            saw['gyro'] = max(abs(g[0]), abs(g[1]), abs(g[2])) >= still
        if laser is not None:
            saw['laser'] = abs(laser) >= still
        if wheels is not None:
            saw['wheel encoders'] = wheels >= WHEEL_STILL
        if not saw:
            return None
        self.told['base'] |= set(saw)
        yes = [w for w, s in saw.items() if s]
        if len(yes) <= len(saw) / 2:
            for w in yes:
                self._warn(self._row(w), '%s alone saw a turn (%s) in "%s" while %s did not: the '
                           'base did not move, so it is not judged on it'
                           % (w, self._seen(w, m), step.label(),
                              ', '.join(x for x in saw if x not in yes)))
            return False
        others = ', '.join(w for w in yes)
        tol = e.turn_tolerance * abs(c)
        if odom is not None:
            self._judge_turn('odometry', 'its yaw', odom, c, tol, still, others)
        if g is not None:
            gx, gy, gz = g
            if max(abs(gx), abs(gy), abs(gz)) < still:
                self._fail('imu', 'the gyro reads about zero while the base turned %+.2f rad (%s '
                           'saw it): integrated x %+.2f, y %+.2f, z %+.2f rad' % (c, others, gx, gy, gz))
            elif max(abs(gx), abs(gy)) > abs(gz):
                axis = 'x' if abs(gx) > abs(gy) else 'y'
                self._fail('imu', 'the turn about z was seen on the gyro\'s %s axis (integrated x '
                           '%+.2f, y %+.2f, z %+.2f rad for a %+.2f rad turn): axes swapped or the '
                           'IMU mounted differently than its frame says' % (axis, gx, gy, gz, c))
            else:
                self._judge_turn('imu', 'the integrated gyro z', gz, c, tol, still, others,
                                 odom=odom)
        if laser is not None:
            if abs(laser) < still:
                self._fail('laser', 'the scan did not change while the base turned %+.2f rad (%s '
                           'saw it): it turned %s rad' % (c, others, _r(laser)))
            elif _sign(laser) != _sign(c):
                self._fail('laser', 'the scan turned the wrong way: %+.2f rad for a %+.2f rad turn '
                           '(naoqi_driver stores the beams right to left, laser.cpp:158-161, '
                           '216-218): the beams are stored in the reverse order' % (laser, c))
            elif abs(laser - c) > tol:
                self._fail('laser', 'the scan turned %+.2f rad for a %+.2f rad turn (more than '
                           '%.0f%% off)' % (laser, c, 100 * e.turn_tolerance))
        if wheels is not None and wheels < WHEEL_STILL:
            self._fail('jointState', 'the wheel joints (%s) did not turn (%.2f rad in all) while '
                       'the base turned %+.2f rad (%s saw it)' % (', '.join(WHEELS), wheels, c, others))
        return True

    @staticmethod
    def _row(witness: str) -> str:
        return {'gyro': 'imu', 'wheel encoders': 'jointState'}.get(witness, witness)

    @staticmethod
    def _seen(witness: str, m: Dict[str, Optional[float]]) -> str:
        if witness == 'gyro':
            return 'integrated z %s rad' % _r(m['gyro_z'])
        if witness == 'wheel encoders':
            return '%.2f rad of wheel rotation' % (m['wheels'] or 0.0)
        return '%s rad' % _r(m.get(witness))

    def _judge_turn(self, row: str, what: str, v: float, c: float, tol: float, still: float,
                    others: str, odom: Optional[float] = None) -> None:
        also = '' if odom is None else ' (odometry %+.2f rad)' % odom
        if abs(v) < still:
            self._fail(row, '%s did not change (%+.2f rad) while the base turned %+.2f rad (%s saw '
                       'it)%s' % (what, v, c, others, also))
        elif _sign(v) != _sign(c):
            self._fail(row, '%s has the opposite sign: %+.2f rad for a %+.2f rad turn (%s)%s; '
                       'counter-clockwise is positive (REP 103)'
                       % (what, v, c, 'left' if c > 0 else 'right', also))
        elif abs(v - c) > tol:
            self._fail(row, '%s changed %+.2f rad for a %+.2f rad turn (more than %.0f%% off)%s'
                       % (what, v, c, 100 * self.e.turn_tolerance, also))

    # ---------------------------------------------------------------- the whole
    def judge(self) -> Tuple[List[str], List[str], Optional[str]]:
        """Put each finding on its sensor's row; return the motion row's (reasons, warnings, skip)."""
        run = self.run
        heads: List[Optional[bool]] = []
        bases: List[Optional[bool]] = []
        for i, step in enumerate(self.completed()):
            if step.part == 'head':
                heads.append(self.head_step(i, step))
            else:
                bases.append(self.base_step(i, step))
        skips: List[str] = []
        fails: List[str] = []
        warns: List[str] = []
        self.head_state = self._part('head', heads, run.head_skip, skips, fails, HEAD_CAUSES)
        self.base_state = self._part('base', bases, run.base_skip, skips, fails, BASE_CAUSES)
        for sensor in set(self.found) | set(self.warned):
            self.add(sensor, self.found.get(sensor, []), self.warned.get(sensor, []))
        if run.stopped:
            warns.append(run.stopped)
        skip = None if fails or not skips else '; '.join(skips)
        return fails, warns, skip

    def _part(self, part: str, moved: Sequence[Optional[bool]], skipped: Optional[str],
              skips: List[str], fails: List[str], causes: str) -> str:
        if skipped is not None:
            skips.append('%s part skipped: %s' % (part, skipped))
            return 'skipped: %s' % skipped
        if self.run.stopped and len(moved) < len([s for s in self.run.steps if s.part == part]):
            skips.append('%s part not finished: %s' % (part, self.run.stopped))
            return 'not finished'
        if any(m is False for m in moved):
            told = sorted(self.told[part])
            if len(told) == 1:
                who = 'its only witness that could tell (%s) saw no motion' % told[0]
                if part == 'head' and self.slow:
                    who += ' (the head cameras\' frames came too far apart to follow it)'
            else:
                who = 'its witnesses (%s) agree' % ', '.join(told)
            fails.append('the %s did not move when commanded, and %s: the actuator, not a sensor. '
                         'Usual causes: %s' % (part, who, causes))
            return 'did not move'
        if not moved or all(m is None for m in moved):
            skips.append('%s part: no witness to tell whether it moved' % part)
            return 'not judged'
        return 'moved'


Points = List[Tuple[float, Optional[float]]]


def rel_series(points: Sequence[Tuple[float, float]], t0: float, limit: int = 200) -> Points:
    """[(t, v)] with t relative to t0, thinned to at most `limit` points."""
    if not points:
        return []
    step = max(1, len(points) // limit)
    return [(round(t - t0, 3), round(v, 4) if math.isfinite(v) else None) for t, v in points[::step]]


def plot_series(run: Run, rec: Recording) -> Dict[str, List[Tuple[float, Optional[float]]]]:
    """For the report: commanded yaw against odometry, integrated gyro and the laser's turn;
    HeadYaw commanded against measured, and the picture shift (the first head camera with
    frames), each over the window (seconds from its start), each relative to its start."""
    t0 = run.started
    commanded: List[Tuple[float, Optional[float]]] = [(0.0, 0.0)]
    head_cmd: List[Tuple[float, Optional[float]]] = []
    total = 0.0
    for s in run.steps:
        if s.sent is None:
            continue
        if s.part == 'base':
            commanded.append((round(s.sent - t0, 3), round(total, 4)))
            total += s.commanded
            commanded.append((round(s.sent - t0, 3), round(total, 4)))
        else:
            head_cmd.append((round(s.sent - t0, 3), round(s.target, 4)))
    with rec.lock:
        odom = list(rec.odom_yaw)
        gyro = list(rec.gyro)
        scans = list(rec.scans)
        frames = next((list(rec.frames[c]) for c in HEAD_CAMERAS if rec.frames.get(c)), [])
    odom_rel: List[Tuple[float, float]] = []
    if odom:
        acc, last = 0.0, odom[0][1]
        for t, v in odom:
            acc += estimate.wrap(v - last)
            last = v
            odom_rel.append((t, acc))
    laser: List[Tuple[float, float]] = []
    if scans:
        step = max(1, len(scans) // 60)
        for scan in scans[::step]:
            turn = estimate.scan_turn(scans[0].ranges, scan.ranges, scans[0].increment)
            if turn is not None:
                laser.append((scan.t, turn))
    shift: List[Tuple[float, float]] = []
    acc = 0.0
    for a, b in zip(frames, frames[1:]):
        d = estimate.picture_shift(a[1], b[1])
        acc += d or 0.0
        shift.append((b[0], acc))
    ends = [pts[-1][0] for pts in (odom, gyro, rec.joints) if pts]
    if ends:       # the commands hold until the end of the window
        end = round(max(ends) - t0, 3)
        commanded.append((end, commanded[-1][1]))
        if head_cmd:
            head_cmd.append((end, head_cmd[-1][1]))
    return {'commanded_yaw': commanded, 'odometry_yaw': rel_series(odom_rel, t0),
            'gyro_yaw': rel_series(estimate.gyro_series(gyro, gyro[0][0] if gyro else 0.0), t0),
            'laser_turn': rel_series(laser, t0), 'head_commanded': head_cmd,
            'head_measured': rel_series(rec.joint_series('HeadYaw'), t0),
            'picture_shift': rel_series(shift, t0)}
