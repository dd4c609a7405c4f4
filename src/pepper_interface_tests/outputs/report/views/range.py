"""Sonar: range over time with the sensor's min_range / max_range."""
from typing import TYPE_CHECKING, List

from ....results import SensorResult
from .. import plots
from ..blocks import Block, Heading, Image
from ..values import RangeValues

if TYPE_CHECKING:
    from ..page import View


def render(r: SensorResult, v: RangeValues, ctx: 'View') -> List[Block]:
    if not v.range_m:
        return []
    return [Heading('Range over time'),
            Image(plots.range_over_time(v.range_m, v.min_range, v.max_range), 'range over time of ' + r.name)]
