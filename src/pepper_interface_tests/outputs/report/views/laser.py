"""Laser: its boards (a dead one named), and a polar plot of the last scan, blind and invalid
beams marked at the edge."""
from typing import Any, List, Optional

from ....results import SensorResult
from ....sensors.values.laser import LaserValues
from .. import plots
from ..blocks import KV, Block, Heading, Image, Span
from ..context import View


def _named(names: List[str]) -> str:
    """'front board', 'front and left boards', 'right, front and left boards'."""
    if len(names) == 1:
        return names[0] + ' board'
    return '%s and %s boards' % (', '.join(names[:-1]), names[-1])


def boards_text(v: LaserValues) -> Optional[Any]:
    """The boards in words: which are dead (no valid reading in the window) and which gave
    readings; None when the driver's layout has no boards (the simulator's)."""
    if v.dead_boards is None:
        return None
    dead = list(v.dead_boards)
    alive = [b for b in (v.longest_identical_board_run or {}) if b not in dead]
    if not dead:
        return 'all gave valid readings' + (' (%s)' % ', '.join(alive) if alive else '')
    out: List[Any] = [Span(_named(dead) + ' dead', cls='fail-text', strong=True),
                      ': no valid reading in the window']
    if alive:
        out.append('; the %s gave readings' % _named(alive))
    return out


def render(r: SensorResult, v: LaserValues, ctx: View) -> List[Block]:
    out: List[Block] = []
    boards = boards_text(v)
    if boards is not None:
        out += [Heading('Boards'), KV([('boards', boards)])]
    if v.last_scan is not None:
        out += [Heading('Last scan'), Image(plots.laser_scan(v.last_scan), 'polar plot of the last laser scan')]
    return out
