"""IMU: |acceleration| and |angular velocity| over time."""
from typing import TYPE_CHECKING, List

from ....results import SensorResult
from .. import plots
from ..blocks import Block, Heading, Image
from ..values import ImuValues

if TYPE_CHECKING:
    from ..page import View


def render(r: SensorResult, v: ImuValues, ctx: 'View') -> List[Block]:
    if not v.acceleration and not v.angular_velocity:
        return []
    return [Heading('Over time'), Image(plots.imu(v.acceleration, v.angular_velocity),
                                        'IMU acceleration and angular velocity over time')]
