"""Odometry (nav_msgs/Odometry): frame ids, unit quaternion, finite pose, twist and covariances,
and a motion Pepper can make.

naoqi_driver fills the pose from ALMotion getPosition("Torso", FRAME_WORLD) and the twist from
getRobotVelocity (src/converters/odom.cpp:56, 59, 82-93), so both describe one motion:
  * every pose is judged against the poses of the last BASELINE s and the last one before
    (jumps.JumpWatch; header stamps, receive times when the stamps are zero): two poses less
    than BASELINE apart more than `max_speed` x BASELINE apart in space, or further apart in
    time implying more than `max_speed`, are a jump and fail, naming how many, the largest
    and when. A pose that leaps away for one message and comes back is a jump. Pepper's base
    drives at most ~0.55 m/s (Aldebaran's NAOqi 2.5 documentation); `max_speed` adds room for
    the torso swaying on top of the base, and the baseline for stamp jitter;
  * |twist linear| differing from the pose-implied speed (poses at least BASELINE s apart,
    jumps left out) by more than `twist_tolerance` in more than half of the pose pairs fails:
    the twist contradicts the pose (a share of pairs, so sampling pairs cannot hide it).
No stuck rule: a robot standing still publishes the same pose and a zero twist every time.
"""
import math
from typing import TYPE_CHECKING, Any, List, Optional, Tuple

from .base import Acc, Check, finite, fmt, quaternion_norm
from .jumps import JumpWatch
from .values import Point
from .values.odometry import OdometryValues

if TYPE_CHECKING:
    import genpy

    from ..plan.expectations import OdometryExpect
    from ..plan.settings import SensorPlan
    from .base import RunContext


def _pose_text(p):
    return 'position (%s, %s, %s) orientation (%s, %s, %s, %s)' % (
        fmt(p.position.x), fmt(p.position.y), fmt(p.position.z),
        fmt(p.orientation.x), fmt(p.orientation.y), fmt(p.orientation.z), fmt(p.orientation.w))


def _twist_text(t):
    return 'linear (%s, %s, %s) angular (%s, %s, %s)' % (
        fmt(t.linear.x), fmt(t.linear.y), fmt(t.linear.z),
        fmt(t.angular.x), fmt(t.angular.y), fmt(t.angular.z))


BASELINE = 0.5      # s between the two poses a speed is computed from


class OdometryCheck(Check):
    family = 'odometry'
    expect: 'OdometryExpect'

    def __init__(self, plan: 'SensorPlan', ctx: 'RunContext') -> None:
        super().__init__(plan, ctx)
        self.x, self.y, self.speed = Acc(), Acc(), Acc()
        self.x_series: List[Point] = []
        self.yaw_series: List[Point] = []
        self.y_series: List[Point] = []
        # (time, x, y, |twist|) the next pose pair starts from
        self.anchor: Optional[Tuple[float, float, float, float]] = None
        self.pairs = 0
        self.mismatch = 0
        self.mismatch_example: Optional[Tuple[float, float, float]] = None
        self.implied = Acc()
        limit = self.expect.max_speed
        self.jump = JumpWatch(limit, BASELINE) if limit is not None else None
        self.found: Optional[OdometryValues] = None      # what finish() measured

    def fields(self, msg: 'genpy.Message') -> List[Tuple[str, Any]]:
        return [('Header', 'frame id %s, stamp %d.%09d, seq %d' % (
                    msg.header.frame_id, msg.header.stamp.secs, msg.header.stamp.nsecs, msg.header.seq)),
                ('Child frame id', msg.child_frame_id),
                ('Pose', _pose_text(msg.pose.pose)),
                ('Twist', _twist_text(msg.twist.twist))]

    def on_message(self, msg: 'genpy.Message', t: float) -> None:
        pose, twist = msg.pose.pose, msg.twist.twist
        if not msg.header.frame_id:
            self.failures.add('frame', 'header.frame_id is empty')
        if not msg.child_frame_id:
            self.failures.add('child', 'child_frame_id is empty')
        want_child = self.expect.child_frame_id
        if want_child and msg.child_frame_id and msg.child_frame_id != want_child:
            self.failures.add('child_id', 'child_frame_id is "%s", expected "%s"'
                              % (msg.child_frame_id, want_child))
        norm = quaternion_norm(pose.orientation)
        if not (abs(norm - 1.0) <= 0.01):
            self.failures.add('quat', 'orientation is not a unit quaternion (norm %s)' % fmt(norm), norm)
        p = pose.position
        values = [p.x, p.y, p.z, twist.linear.x, twist.linear.y, twist.linear.z,
                  twist.angular.x, twist.angular.y, twist.angular.z]
        if not finite(values):
            self.failures.add('nan', 'pose or twist holds NaN or inf')
        if not (finite(msg.pose.covariance) and finite(msg.twist.covariance)):
            self.failures.add('cov', 'a covariance holds NaN or inf')
        self.x.add(p.x)
        self.y.add(p.y)
        if finite(values):
            self._judge_motion(p.x, p.y, math.hypot(twist.linear.x, twist.linear.y), t,
                               msg.header.stamp.to_sec() or None)
        self.speed.add(math.hypot(twist.linear.x, twist.linear.y))
        if len(self.x_series) < 2000:
            self.x_series.append((round(t, 3), p.x if math.isfinite(p.x) else None))
            self.y_series.append((round(t, 3), p.y if math.isfinite(p.y) else None))
            q = msg.pose.pose.orientation
            yaw = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
            self.yaw_series.append((round(t, 3), yaw if math.isfinite(yaw) else None))

    def _judge_motion(self, x, y, speed, t, stamp):
        when = stamp if stamp is not None else t
        if self.jump is not None and not self.jump.add(when, (x, y), t):
            return                          # a jump: not a pose the twist is compared with
        a = self.anchor
        if a is None or when < a[0]:
            self.anchor = (when, x, y, speed)
            return
        dt = when - a[0]
        if dt < BASELINE:
            return
        implied = math.hypot(x - a[1], y - a[2]) / dt
        self.anchor = (when, x, y, speed)
        self.pairs += 1
        self.implied.add(implied)
        tol = self.expect.twist_tolerance
        twist = (speed + a[3]) / 2.0
        if tol is not None and abs(twist - implied) > tol:
            self.mismatch += 1
            if self.mismatch_example is None:
                self.mismatch_example = (twist, implied, t)

    def finish(self) -> None:
        jump = self.jump
        if jump is not None and jump.jumps:
            self.fail('pose jumps: consecutive poses imply more than max_speed %s m/s (Pepper '
                      'drives at most ~0.55 m/s): %d %s, the largest %s m from the pose %s s '
                      'before at t = %s s (poses under %.1f s apart may differ by %s m)'
                      % (fmt(jump.max_rate), jump.jumps, 'jump' if jump.jumps == 1 else 'jumps',
                         fmt(jump.largest, 2), fmt(jump.largest_dt, 3), fmt(jump.largest_t, 2),
                         BASELINE, fmt(jump.max_rate * BASELINE)))
        tol = self.expect.twist_tolerance
        if tol is not None and self.pairs and self.mismatch > self.pairs / 2.0:
            tw, im, at = self.mismatch_example or (0.0, 0.0, 0.0)   # set with the first mismatch
            self.fail('twist contradicts the pose: |twist| and the speed the poses imply differ by '
                      'more than twist_tolerance %s m/s in %d of %d pose pairs %.1f s apart (e.g. '
                      'twist %s m/s, poses %s m/s at t = %s s)'
                      % (fmt(tol), self.mismatch, self.pairs, BASELINE, fmt(tw, 3), fmt(im, 3), fmt(at, 2)))
        elif self.mismatch:
            self.notes.append('twist and pose-implied speed differ by more than %s m/s in %d of %d '
                              'pose pairs' % (fmt(tol), self.mismatch, self.pairs))
        if self.count:
            self.notes.append('Position x: %s; y: %s; speed: %s'
                              % (self.x.text('m'), self.y.text('m'), self.speed.text('m/s')))
        self.found = OdometryValues(
            pose_implied_speed_m_s=self.implied.spread(),
            pose_jumps=jump.jumps if jump is not None else None,
            largest_pose_jump_m=round(jump.largest, 3) if jump is not None else None,
            x_m=self.x.spread(), y_m=self.y.spread(), speed_m_s=self.speed.spread(),
            x_series=self.x_series, y_series=self.y_series, yaw_series=self.yaw_series)

