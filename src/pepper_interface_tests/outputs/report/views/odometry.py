"""Odometry: x and y over time, and the path."""
from typing import TYPE_CHECKING, List

from ....results import SensorResult
from .. import plots
from ..blocks import Block, Heading, Image
from ..values import OdometryValues

if TYPE_CHECKING:
    from ..page import View


def render(r: SensorResult, v: OdometryValues, ctx: 'View') -> List[Block]:
    if not v.x:
        return []
    return [Heading('Position over time'), Image(plots.odometry(v.x, v.y), 'odometry position over time')]
