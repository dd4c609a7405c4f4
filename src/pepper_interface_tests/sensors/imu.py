"""IMU (sensor_msgs/Imu): a finite unit quaternion, finite rates and accelerations, finite
covariances.

naoqi_driver fills the orientation from ALMemory's angles and sets covariance[0] = -1 for the
orientation, the angular velocity and the linear acceleration ("Covariances unknown",
ros-naoqi/naoqi_driver src/converters/imu.cpp:123-126) while publishing all three. So -1 here
means "covariance unknown", never "skip the check": a NaN or non-unit attitude and NaN rates or
accelerations fail whatever the covariance says. The accelerometer includes gravity
(imu.cpp:119-121, raw ALMemory values), so |a| is about 9.8 m/s^2 at rest.

Data that cannot be real:
  * stuck: `stuck_messages` readings in a row with the same angular velocity and linear
    acceleration, to the last bit. The inertial board's raw values carry sensor noise, and
    naoqi_driver reads them from ALMemory at 10 Hz (imu.cpp) while the board updates them
    every DCM cycle (~100 Hz), so two consecutive messages never repeat all six values on a
    healthy robot; a converter republishing a cached message does;
  * the median |linear acceleration| outside `acceleration_norm`: a dead accelerometer reads
    0, one reporting in g reads 1, a saturated one ~2 g (the accelerometer's range, Aldebaran
    "Pepper - Inertial unit"); single messages outside it are a warning (a bump);
  * |angular velocity| above `max_angular_velocity`: beyond the gyrometer's ~500 deg/s range
    (same page), the sensor cannot report it.
"""
import math
from typing import TYPE_CHECKING, Any, List, Optional, Tuple

from .base import Acc, Check, StuckRun, finite, fmt, quaternion_norm
from .values import Point
from .values.imu import ImuValues
from .wear import Noise

if TYPE_CHECKING:
    import genpy

    from ..plan.expectations import ImuExpect
    from ..plan.settings import SensorPlan
    from .base import RunContext


def _v3(v):
    return '(%s, %s, %s)' % (fmt(v.x), fmt(v.y), fmt(v.z))


class ImuCheck(Check):
    family = 'imu'
    expect: 'ImuExpect'

    def __init__(self, plan: 'SensorPlan', ctx: 'RunContext') -> None:
        super().__init__(plan, ctx)
        self.acc_norm, self.gyro_norm = Acc(), Acc()
        self.acc_series: List[Point] = []
        self.gyro_series: List[Point] = []
        self.gyro_z_series: List[Point] = []
        self.found: Optional[ImuValues] = None
        self.stuck = StuckRun(self.expect.stuck_messages)
        self.acc_values: List[float] = []
        self.gyro_noise = Noise()

    def fields(self, msg: 'genpy.Message') -> List[Tuple[str, Any]]:
        q = msg.orientation
        return [('Header', 'frame id %s, stamp %d.%09d, seq %d' % (
                    msg.header.frame_id, msg.header.stamp.secs, msg.header.stamp.nsecs, msg.header.seq)),
                ('Orientation', '(%s, %s, %s, %s)' % (fmt(q.x), fmt(q.y), fmt(q.z), fmt(q.w))),
                ('Angular velocity', _v3(msg.angular_velocity)),
                ('Linear acceleration', _v3(msg.linear_acceleration))]

    def on_message(self, msg: 'genpy.Message', t: float) -> None:
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
        self.gyro_noise.add(wn, msg.header.stamp.to_sec() or None)     # the sampling time
        self.acc_values.append(an)
        self.stuck.add((a.x, a.y, a.z, w.x, w.y, w.z), t)
        band = self.expect.acceleration_norm
        if band is not None and not (band[0] <= an <= band[1]):
            self.warnings.add('acc_band', '|linear acceleration| outside acceleration_norm [%s, %s] '
                              'm/s^2 (gravity included)' % (fmt(band[0]), fmt(band[1])),
                              '%s m/s^2 at t = %s s' % (fmt(an, 3), fmt(t, 2)))
        top = self.expect.max_angular_velocity
        if top is not None and wn > top:
            self.failures.add('gyro_range', '|angular velocity| beyond the gyrometer\'s range '
                              '(max_angular_velocity %s rad/s, ~500 deg/s)' % fmt(top),
                              '%s rad/s, first at t = %s s' % (fmt(wn, 2), fmt(t, 2)))
        if len(self.acc_series) < 2000:
            self.acc_series.append((round(t, 3), an))
            self.gyro_series.append((round(t, 3), wn))
            wz = msg.angular_velocity.z
            self.gyro_z_series.append((round(t, 3), wz if math.isfinite(wz) else None))

    def finish(self) -> None:
        stuck = self.stuck.finding('readings (angular velocity and linear acceleration)',
                                   'stuck_messages')
        if stuck:
            self.fail('IMU stuck: ' + stuck)
        band = self.expect.acceleration_norm
        median_value = None
        if band is not None and self.acc_values:
            median = sorted(self.acc_values)[len(self.acc_values) // 2]
            median_value = round(median, 4)
            if not (band[0] <= median <= band[1]):
                self.fail('median |linear acceleration| %s m/s^2 outside acceleration_norm [%s, %s] '
                          '(an upright robot measures g = 9.81 m/s^2: %s)'
                          % (fmt(median, 3), fmt(band[0]), fmt(band[1]),
                             'a dead accelerometer reads 0' if median < 0.5 else
                             'values in g instead of m/s^2?' if median < 2 else
                             'not the gravity an upright robot measures'))
        self.found = ImuValues(self.stuck.longest, median_value, self.acc_norm.spread(), self.gyro_norm.spread(),
                               self.gyro_noise.sd(), list(self.acc_series), list(self.gyro_series),
                               list(self.gyro_z_series))
        if self.count:
            self.notes.append('|linear acceleration|: %s; |angular velocity|: %s'
                              % (self.acc_norm.text('m/s^2'), self.gyro_norm.text('rad/s')))

