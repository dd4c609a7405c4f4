"""The robot's health: battery, the hottest joints and every joint the driver calls hot."""
from typing import List, Sequence, Union

from ....results import SensorResult
from ....sensors.values.health import HealthValues, JointRow
from ..blocks import KV, Block, Heading, Span, Table
from ..context import View
from .fmt import num


def _level(level: str) -> Union[Span, str]:
    if level == 'ERROR':
        return Span(level, strong=True, cls='fail-text')
    if level == 'WARN':
        return Span(level, strong=True, cls='warn-text')
    return level or '-'


def _rows(rows: Sequence[JointRow]) -> List[List[object]]:
    return [[j.joint, num(j.temperature_c, 1, '°C'), _level(j.level), j.message] for j in rows
            if isinstance(j, JointRow)]


def render(r: SensorResult, v: HealthValues, ctx: View) -> List[Block]:
    if not v.driver_arrays:
        return []
    state = ('fully charged' if v.fully_charged else 'charging' if v.charging
             else 'not charging' if v.charging is False else '-')
    blocks: List[Block] = [Heading('Battery'), KV([
        ('charge', num(v.battery_percent, 0, '%')), ('charging', state),
        ('driver level', _level(v.battery_level or '-')), ('driver message', v.battery_message or '-'),
        ('highest joint temperature', num(v.highest_temperature_c, 1, '°C')),
        ('driver status arrays read', str(v.driver_arrays))])]
    head = ['joint', 'temperature', 'driver level', 'driver message']
    blocks += [Heading('Hottest joints'), Table(head, _rows(v.hottest), numeric=[1])]
    if v.hot:
        blocks += [Heading('Hot joints (%d)' % len(v.hot)), Table(head, _rows(v.hot), numeric=[1])]
    return blocks
