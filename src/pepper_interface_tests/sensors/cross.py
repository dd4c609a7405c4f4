"""Cross-checks between sensors that need no motion, in every live run and every bag: each
finding is a WARNING on a row (never a failure: both sensors may be right about different
things), added once every window is judged (runner.py, before the outputs are written).

- Front sonar against the laser's front sector: the last sonar reading against the nearest
  laser return within +-FRONT_SECTOR rad of straight ahead in the last scan, when the two windows
  ended within SAME_TIME s of each other (parallel mode, a bag; in sequential mode the robot may
  have moved between them, and they are not compared). Apart by more than SONAR_MARGIN m is a
  warning naming both distances. The margin: the sonar sits higher than the laser (Pepper's
  front sonar at the knee, the laser's front board near the floor) and sees a cone of about 60
  degrees, the laser a few beams, so tenths of a metre are normal; glass and black or soft
  surfaces are the usual honest cause of a larger difference (the laser's infrared passes
  through glass or is absorbed; the ultrasound echoes off it).
- Header clocks: each sensor's smallest delay (receive time minus header stamp, stats.delay_s:
  its freshest message) against the median of all sensors' smallest delays; a clock moves every
  stamp, a queue only the messages that waited in it (on a busy PC sensorTest's own, rclpy's
  one thread on ROS 2: jointState's mean delay 1.9-2.9 s against the others' 0.2-1.0 s in the
  ROS 2 demo beside two busy processes, issue 41); a sensor more than CLOCK_SPREAD s off is a
  warning naming the offset: its stamps come from another clock (a robot clock and a host
  clock that differ: naoqi_driver stamps with the host's ros::Time::now(), e.g.
  src/converters/laser.cpp:154, while a bridge or a camera driver on the robot uses the
  robot's). The spread: a loaded robot's 1.3 fps VGA frames arrive up to ~0.7 s after their
  stamp; one second more is a clock, not a queue. Needs three sensors with stamps.
- A recorded turn (a bag, or a live run where the robot turns on its own): odometry's yaw change
  against the gyro's z integrated over the same stretch of time (both windows together, as in
  a bag), when either saw a turn of at least RECORDED_TURN rad. The opposite sign, or apart by
  more than RECORDED_TOLERANCE of the larger, is a warning on both rows with both numbers (two
  witnesses cannot tell which one is wrong: --move adds the wheels and the laser and votes).
  Integrating a gyro drifts: a few hundredths of a rad over a minute, far below the margin.
  Not made when the recorded motion below judged a turn (three or more witnesses voted).
- The recorded motion (a bag or a ROS 2 recording, not a live run): motion/recorded.py finds
  the recording's base turns and head yaw moves and judges them with the --move rules, the
  witnesses' vote in place of the command. A witness the majority outvotes FAILS on its row,
  as live: the vote of three or more independent sensors is the same evidence a --move run
  judges on (there the command only sets the size, and the vote decides whether the base
  turned); a recording without a turn gets no finding. The motion found is a note on the
  witnesses' rows.
"""
import math
import statistics
from typing import List, Optional, Sequence, Tuple

from ..motion import recorded
from ..motion.record import Recording
from ..results import FAIL, PASS, SensorResult
from .values.imu import ImuValues
from .values.laser import LaserValues
from .values.odometry import OdometryValues
from .values.range import RangeValues

FRONT_SONAR = 'frontSonar'
FRONT_SECTOR = 0.26     # rad either side of straight ahead (15 degrees)
SONAR_MARGIN = 0.5      # m
SAME_TIME = 1.0         # s between the two windows' ends
CLOCK_SPREAD = 1.0      # s
RECORDED_TURN = 0.3     # rad: a turn, not a wobble
RECORDED_TOLERANCE = 0.35   # share of the larger of the two (as MotionExpect.turn_tolerance)


def _laser_front(values: LaserValues) -> Optional[float]:
    scan = values.last_scan
    if scan is None:
        return None
    near = [r for i, r in enumerate(scan.ranges)
            if abs(scan.angle_min + i * scan.angle_increment) <= FRONT_SECTOR
            and math.isfinite(r) and r >= max(scan.range_min, 0.0)]
    return min(near) if near else None


def sonar_against_laser(results: Sequence[SensorResult]) -> None:
    sonar = next((r for r in results if r.name == FRONT_SONAR and isinstance(r.values, RangeValues)), None)
    laser = next((r for r in results if isinstance(r.values, LaserValues)), None)
    if sonar is None or laser is None:
        return
    sv, lv = sonar.values, laser.values
    assert isinstance(sv, RangeValues) and isinstance(lv, LaserValues)
    if not sv.range_series or sonar.ended_at is None or laser.ended_at is None \
            or abs(sonar.ended_at - laser.ended_at) > SAME_TIME:
        return
    s = sv.range_series[-1][1]
    front = _laser_front(lv)
    if s is None or front is None or not math.isfinite(s):
        return
    if abs(s - front) > SONAR_MARGIN:
        text = ('the front sonar reads %.2f m and the laser\'s front sector %.2f m: more than %.1f m '
                'apart (glass or a black or soft surface in front is the usual honest cause: %s)'
                % (s, front, SONAR_MARGIN, 'the laser sees through glass' if s < front
                   else 'the sonar\'s echo is lost on soft or slanted surfaces'))
        sonar.warnings.append(text)
        laser.warnings.append(text)


def header_clocks(results: Sequence[SensorResult]) -> None:
    delays = [(r, r.stats.delay_s.min) for r in results
              if r.stats is not None and r.stats.delay_s is not None and r.stats.delay_s.min is not None]
    if len(delays) < 3:
        return
    middle = statistics.median(d for _, d in delays)
    for r, d in delays:
        off = d - middle
        if abs(off) > CLOCK_SPREAD:
            r.warnings.append('header stamps %.2f s %s the other sensors\' (freshest delay %.2f s, the '
                              'others\' median %.2f s): stamped by another clock (a robot clock and '
                              'a host clock that differ)' % (abs(off), 'behind' if off > 0 else 'ahead of',
                                                            d, middle))


def _points(r: SensorResult, series: List[Tuple[float, Optional[float]]]) -> List[Tuple[float, float]]:
    start = r.started_at or 0.0
    return [(start + t, v) for t, v in series if v is not None and math.isfinite(v)]


def recorded_turn(results: Sequence[SensorResult]) -> None:
    odom = next((r for r in results if isinstance(r.values, OdometryValues)), None)
    imu = next((r for r in results if isinstance(r.values, ImuValues)), None)
    if odom is None or imu is None:
        return
    ov, iv = odom.values, imu.values
    assert isinstance(ov, OdometryValues) and isinstance(iv, ImuValues)
    yaw, wz = _points(odom, ov.yaw_series), _points(imu, iv.angular_velocity_z_rad_s)
    if len(yaw) < 2 or len(wz) < 2:
        return
    t0, t1 = max(yaw[0][0], wz[0][0]), min(yaw[-1][0], wz[-1][0])
    if t1 - t0 < 1.0:
        return
    turn, last = 0.0, None
    for t, v in yaw:
        if t0 <= t <= t1:
            if last is not None:
                turn += math.atan2(math.sin(v - last), math.cos(v - last))
            last = v
    inside = [(t, v) for t, v in wz if t0 <= t <= t1]
    gyro = sum(0.5 * (a[1] + b[1]) * (b[0] - a[0]) for a, b in zip(inside, inside[1:]))
    big = max(abs(turn), abs(gyro))
    if big < RECORDED_TURN:
        return
    if turn * gyro < 0 or abs(turn - gyro) > RECORDED_TOLERANCE * big:
        text = ('in the %.0f s both recorded, odometry\'s yaw changed %+.2f rad and the gyro\'s z '
                'integrates to %+.2f rad: %s' % (t1 - t0, turn, gyro,
                                                 'opposite signs' if turn * gyro < 0 else 'they disagree'))
        odom.warnings.append(text)
        imu.warnings.append(text)


def recorded_motion(results: Sequence[SensorResult], rec: Recording) -> bool:
    """The --move rules on the recording's own motion (motion/recorded.py), on the rows; True
    when a base turn was judged by the vote."""
    found, warned, notes = recorded.judge(rec)
    rows = {r.name: r for r in results}
    for sensor, texts in found.items():
        r = rows.get(sensor)
        if r is not None and r.verdict in (PASS, FAIL):
            r.verdict = FAIL
            r.reasons.extend(texts)
    for sensor, texts in warned.items():
        r = rows.get(sensor)
        if r is not None and r.verdict in (PASS, FAIL):
            r.warnings.extend(texts)
    for sensor, texts in notes.items():
        if sensor in rows:
            rows[sensor].notes.extend(texts)
    return any(n.startswith('recorded base turn') for texts in notes.values() for n in texts)


def apply(results: List[SensorResult], rec: Optional[Recording] = None) -> None:
    """Every cross-check over the run's judged rows (warnings added in place); `rec`: the
    recording's motion witnesses (a bag run)."""
    sonar_against_laser(results)
    header_clocks(results)
    voted = rec is not None and recorded_motion(results, rec)
    if not voted:
        recorded_turn(results)
