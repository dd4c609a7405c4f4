"""Odometry (nav_msgs/Odometry): frame ids, unit quaternion, finite pose, twist and covariances."""
import math

from .base import Acc, Check, finite, fmt, quaternion_norm


def _pose_text(p):
    return 'position (%s, %s, %s) orientation (%s, %s, %s, %s)' % (
        fmt(p.position.x), fmt(p.position.y), fmt(p.position.z),
        fmt(p.orientation.x), fmt(p.orientation.y), fmt(p.orientation.z), fmt(p.orientation.w))


def _twist_text(t):
    return 'linear (%s, %s, %s) angular (%s, %s, %s)' % (
        fmt(t.linear.x), fmt(t.linear.y), fmt(t.linear.z),
        fmt(t.angular.x), fmt(t.angular.y), fmt(t.angular.z))


class OdometryCheck(Check):
    family = 'odometry'

    def __init__(self, plan, ctx):
        super().__init__(plan, ctx)
        self.x, self.y, self.speed = Acc(), Acc(), Acc()
        self.series['x_m'], self.series['y_m'] = [], []

    def fields(self, msg):
        return [('Header', 'frame id %s, stamp %d.%09d, seq %d' % (
                    msg.header.frame_id, msg.header.stamp.secs, msg.header.stamp.nsecs, msg.header.seq)),
                ('Child frame id', msg.child_frame_id),
                ('Pose', _pose_text(msg.pose.pose)),
                ('Twist', _twist_text(msg.twist.twist))]

    def on_message(self, msg, t):
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
        self.speed.add(math.hypot(twist.linear.x, twist.linear.y))
        if len(self.series['x_m']) < 2000:
            self.series['x_m'].append((round(t, 3), p.x if math.isfinite(p.x) else None))
            self.series['y_m'].append((round(t, 3), p.y if math.isfinite(p.y) else None))

    def finish(self):
        self.values['x_m'] = self.x.as_dict()
        self.values['y_m'] = self.y.as_dict()
        self.values['speed_m_s'] = self.speed.as_dict()
        if self.count:
            self.notes.append('Position x: %s; y: %s; speed: %s'
                              % (self.x.text('m'), self.y.text('m'), self.speed.text('m/s')))
