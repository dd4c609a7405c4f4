"""IMU: |acceleration| and |angular velocity| over time."""
from typing import List

from ....results import SensorResult
from ....sensors.values.imu import ImuValues
from .. import plots
from ..blocks import Block, Heading, Image
from ..context import View
from ..values import Series


def render(r: SensorResult, v: ImuValues, ctx: View) -> List[Block]:
    acc, gyro = Series.of(v.acceleration_m_s2), Series.of(v.angular_velocity_rad_s)
    if not acc and not gyro:
        return []
    return [Heading('Over time'), Image(plots.imu(acc, gyro), 'IMU acceleration and angular velocity over time')]
