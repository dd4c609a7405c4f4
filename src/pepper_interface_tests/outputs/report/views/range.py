"""Sonar: range over time with the sensor's min_range / max_range."""
from .. import plots
from ..blocks import Heading, Image


def render(r, v, ctx):
    if not v.range_m:
        return []
    return [Heading('Range over time'),
            Image(plots.range_over_time(v.range_m, v.min_range, v.max_range), 'range over time of ' + r.name)]
