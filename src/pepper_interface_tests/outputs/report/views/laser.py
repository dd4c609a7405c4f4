"""Laser: polar plot of the last scan, blind and invalid beams marked at the edge."""
from typing import TYPE_CHECKING, List

from ....results import SensorResult
from .. import plots
from ..blocks import Block, Heading, Image
from ..values import LaserScanValues

if TYPE_CHECKING:
    from ..page import View


def render(r: SensorResult, scan: LaserScanValues, ctx: 'View') -> List[Block]:
    return [Heading('Last scan'), Image(plots.laser_scan(scan), 'polar plot of the last laser scan')]
