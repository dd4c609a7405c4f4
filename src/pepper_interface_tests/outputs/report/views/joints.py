"""Joint states: every joint's position / velocity / effort range."""
from typing import TYPE_CHECKING, List, Optional

from ....results import SensorResult
from ..blocks import Block, Heading, Table
from ..values import JointValues, Spread
from .fmt import num

if TYPE_CHECKING:
    from ..page import View


def _cell(s: Optional[Spread]) -> str:
    if s is None or s.min is None:
        return '-'
    return '%s / %s / %s' % (num(s.min, 3), num(s.mid, 3), num(s.max, 3))


def render(r: SensorResult, v: JointValues, ctx: 'View') -> List[Block]:
    if not v.joints:
        return []
    rows = [[j.name, _cell(j.position), _cell(j.velocity), _cell(j.effort)] for j in v.joints]
    return [Heading('Joints (%d)' % len(v.joints)),
            Table(['joint', 'position rad (min / mean / max)', 'velocity rad/s', 'effort'], rows, numeric=[1, 2, 3])]
