"""Joint states: every joint's position / velocity / effort range."""
from ..blocks import Heading, Table
from .fmt import num


def _cell(s):
    if s is None or s.min is None:
        return '-'
    return '%s / %s / %s' % (num(s.min, 3), num(s.mid, 3), num(s.max, 3))


def render(r, v, ctx):
    if not v.joints:
        return []
    rows = [[j.name, _cell(j.position), _cell(j.velocity), _cell(j.effort)] for j in v.joints]
    return [Heading('Joints (%d)' % len(v.joints)),
            Table(['joint', 'position rad (min / mean / max)', 'velocity rad/s', 'effort'], rows, numeric=[1, 2, 3])]
