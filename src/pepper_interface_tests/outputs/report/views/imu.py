"""IMU: |acceleration| and |angular velocity| over time."""
from .. import plots
from ..blocks import Heading, Image


def render(r, v, ctx):
    if not v.acceleration and not v.angular_velocity:
        return []
    return [Heading('Over time'), Image(plots.imu(v.acceleration, v.angular_velocity),
                                        'IMU acceleration and angular velocity over time')]
