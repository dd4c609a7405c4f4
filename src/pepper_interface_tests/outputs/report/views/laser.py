"""Laser: polar plot of the last scan, blind and invalid beams marked at the edge."""
from typing import List

from ....results import SensorResult
from ....sensors.values.laser import LaserValues
from .. import plots
from ..blocks import Block, Heading, Image
from ..context import View


def render(r: SensorResult, v: LaserValues, ctx: View) -> List[Block]:
    if v.last_scan is None:
        return []
    return [Heading('Last scan'), Image(plots.laser_scan(v.last_scan), 'polar plot of the last laser scan')]
