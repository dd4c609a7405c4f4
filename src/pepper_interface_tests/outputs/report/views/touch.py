"""Touch sensors and bumpers: one row per zone (pressed at, released at, held for, outcome)."""
from typing import List, Union

from ....results import SensorResult
from ....sensors.values.touch import TouchValues, ZoneRow
from ..blocks import Block, Heading, Para, Span, Table
from ..context import View
from .fmt import num


def _outcome(z: ZoneRow) -> Union[Span, str]:
    if z.outcome in ('passed', 'touched'):
        return Span(z.outcome, strong=True)
    if z.outcome.startswith(('not pressed', 'stuck', 'too late')):
        return Span(z.outcome, strong=True, cls='fail-text')
    if z.outcome.startswith('skipped') or z.outcome.startswith('pressed'):
        return Span(z.outcome, cls='warn-text')
    return Span(z.outcome, cls='muted')


def render(r: SensorResult, v: TouchValues, ctx: View) -> List[Block]:
    if not v.zones:
        return []
    rows = [[z.zone, '%s %d' % (z.id, z.index), str(z.presses), num(z.pressed_at, 2, 's'),
             num(z.released_at, 2, 's'), num(z.held_s, 2, 's'), _outcome(z)] for z in v.zones]
    mode = ('guided: each zone was asked for in turn' if v.mode == 'guided'
            else 'unattended: nobody was asked to touch; the events that arrived are judged')
    return [Heading('Zones'), Para(mode, cls='muted'),
            Table(['zone', 'id / index', 'presses', 'pressed at', 'released at', 'held for', 'outcome'],
                  rows, numeric=[2, 3, 4, 5])]
