"""Odometry: pose jumps (how many, the largest), x and y over time, and the path."""
from typing import Any, List, Tuple

from ....results import SensorResult
from ....sensors.values.odometry import OdometryValues
from .. import plots
from ..blocks import KV, Block, Heading, Image, Span
from ..context import View
from ..values import Series
from .fmt import num


def jump_rows(v: OdometryValues) -> List[Tuple[str, Any]]:
    """The pose jumps as KV rows; none when the jump rule was off (no max_speed)."""
    if v.pose_jumps is None:
        return []
    if not v.pose_jumps:
        return [('pose jumps', 'none')]
    return [('pose jumps', Span(num(v.pose_jumps), cls='fail-text', strong=True)),
            ('largest jump', Span(num(v.largest_pose_jump_m, 3, 'm'), cls='fail-text'))]


def render(r: SensorResult, v: OdometryValues, ctx: View) -> List[Block]:
    out: List[Block] = []
    rows = jump_rows(v)
    if rows:
        out += [Heading('Pose jumps'), KV(rows)]
    x = Series.of(v.x_series)
    if x:
        out += [Heading('Position over time'),
                Image(plots.odometry(x, Series.of(v.y_series)), 'odometry position over time')]
    return out
