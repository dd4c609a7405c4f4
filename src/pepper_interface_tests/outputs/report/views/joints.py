"""Joint states: every joint's position / velocity / effort range."""
from typing import List, Optional

from ....results import SensorResult
from ....sensors.values import Spread
from ....sensors.values.joints import JointsValues
from ..blocks import Block, Heading, Table
from ..context import View
from .fmt import num


def _cell(s: Optional[Spread]) -> str:
    if s is None or s.min is None:
        return '-'
    return '%s / %s / %s' % (num(s.min, 3), num(s.mean, 3), num(s.max, 3))


def render(r: SensorResult, v: JointsValues, ctx: View) -> List[Block]:
    if not v.joints:
        return []
    rows = [[name, _cell(d.get('position')), _cell(d.get('velocity')), _cell(d.get('effort'))]
            for name, d in v.joints.items()]
    return [Heading('Joints (%d)' % len(v.joints)),
            Table(['joint', 'position rad (min / mean / max)', 'velocity rad/s', 'effort'], rows, numeric=[1, 2, 3])]
