"""Odometry: x and y over time, and the path."""
from typing import List

from ....results import SensorResult
from ....sensors.values.odometry import OdometryValues
from .. import plots
from ..blocks import Block, Heading, Image
from ..context import View
from ..values import Series


def render(r: SensorResult, v: OdometryValues, ctx: View) -> List[Block]:
    x = Series.of(v.x_series)
    if not x:
        return []
    return [Heading('Position over time'),
            Image(plots.odometry(x, Series.of(v.y_series)), 'odometry position over time')]
