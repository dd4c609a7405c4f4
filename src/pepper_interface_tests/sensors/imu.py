"""IMU (sensor_msgs/Imu): a finite unit quaternion, finite rates and accelerations, finite
covariances.

naoqi_driver fills the orientation from ALMemory's angles and sets covariance[0] = -1 for the
orientation, the angular velocity and the linear acceleration ("Covariances unknown",
ros-naoqi/naoqi_driver src/converters/imu.cpp:123-126) while publishing all three. So -1 here
means "covariance unknown", never "skip the check": a NaN or non-unit attitude and NaN rates or
accelerations fail whatever the covariance says. The accelerometer includes gravity
(imu.cpp:119-121, raw ALMemory values), so |a| is about 9.8 m/s^2 at rest.
"""
import math

from .base import Acc, Check, finite, fmt, quaternion_norm


def _v3(v):
    return '(%s, %s, %s)' % (fmt(v.x), fmt(v.y), fmt(v.z))


class ImuCheck(Check):
    family = 'imu'

    def __init__(self, plan, ctx):
        super().__init__(plan, ctx)
        self.acc_norm, self.gyro_norm = Acc(), Acc()
        self.series['acceleration_m_s2'], self.series['angular_velocity_rad_s'] = [], []

    def fields(self, msg):
        q = msg.orientation
        return [('Header', 'frame id %s, stamp %d.%09d, seq %d' % (
                    msg.header.frame_id, msg.header.stamp.secs, msg.header.stamp.nsecs, msg.header.seq)),
                ('Orientation', '(%s, %s, %s, %s)' % (fmt(q.x), fmt(q.y), fmt(q.z), fmt(q.w))),
                ('Angular velocity', _v3(msg.angular_velocity)),
                ('Linear acceleration', _v3(msg.linear_acceleration))]

    def on_message(self, msg, t):
        for label, cov in (('orientation', msg.orientation_covariance),
                           ('angular velocity', msg.angular_velocity_covariance),
                           ('linear acceleration', msg.linear_acceleration_covariance)):
            if len(cov) != 9:
                self.failures.add('covlen_' + label, '%s covariance has %d values, not 9' % (label, len(cov)))
            elif not finite(cov):
                self.failures.add('covnan_' + label, '%s covariance holds NaN or inf' % label)
        q = msg.orientation
        unknown = len(msg.orientation_covariance) == 9 and msg.orientation_covariance[0] == -1
        why = ' (covariance -1 means unknown covariance, not absent data)' if unknown else ''
        if not finite([q.x, q.y, q.z, q.w]):
            self.failures.add('quatnan', 'orientation holds NaN or inf' + why)
        else:
            norm = quaternion_norm(q)
            if not abs(norm - 1.0) <= 0.01:
                self.failures.add('quat', 'orientation is not a unit quaternion (norm %s)%s'
                                  % (fmt(norm), why), norm)
        a, w = msg.linear_acceleration, msg.angular_velocity
        if not finite([a.x, a.y, a.z, w.x, w.y, w.z]):
            self.failures.add('nan', 'angular velocity or linear acceleration holds NaN or inf')
            return
        an, wn = math.sqrt(a.x ** 2 + a.y ** 2 + a.z ** 2), math.sqrt(w.x ** 2 + w.y ** 2 + w.z ** 2)
        self.acc_norm.add(an)
        self.gyro_norm.add(wn)
        if len(self.series['acceleration_m_s2']) < 2000:
            self.series['acceleration_m_s2'].append((round(t, 3), an))
            self.series['angular_velocity_rad_s'].append((round(t, 3), wn))

    def finish(self):
        self.values['acceleration_norm_m_s2'] = self.acc_norm.as_dict()
        self.values['angular_velocity_norm_rad_s'] = self.gyro_norm.as_dict()
        if self.count:
            self.notes.append('|linear acceleration|: %s; |angular velocity|: %s'
                              % (self.acc_norm.text('m/s^2'), self.gyro_norm.text('rad/s')))
