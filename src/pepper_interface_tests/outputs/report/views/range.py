"""Sonar: range over time with the sensor's min_range / max_range."""
from typing import List

from ....results import SensorResult
from ....sensors.values.range import RangeValues
from .. import plots
from ..blocks import Block, Heading, Image
from ..context import View
from ..values import Series, number


def render(r: SensorResult, v: RangeValues, ctx: View) -> List[Block]:
    series = Series.of(v.range_series)
    if not series:
        return []
    limits = dict((k, x) for k, x in (tuple(f[:2]) for f in r.fields or [] if len(f) >= 2))
    return [Heading('Range over time'),
            Image(plots.range_over_time(series, number(limits.get('Minimum range value')),
                                        number(limits.get('Maximum range value'))), 'range over time of ' + r.name)]
