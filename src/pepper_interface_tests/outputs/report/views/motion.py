"""Motion (--move): each part's outcome, each step's command against what every witness
measured, and one plot: commanded vs measured over time (sensors/values/motion.py)."""
from typing import List

from ....results import SensorResult
from ....sensors.values.motion import MotionValues
from .. import plots
from ..blocks import KV, Block, Heading, Image, Table
from ..context import View
from ..values import Series


def _m(v: object) -> str:
    return '-' if v is None else '%+.2f' % v if isinstance(v, float) else str(v)


def render(r: SensorResult, v: MotionValues, ctx: View) -> List[Block]:
    rows = [('head', v.head or '-'), ('base', v.base or '-')]
    if v.stopped:
        rows.append(('stopped', v.stopped))
    out: List[Block] = [Heading('Motion'), KV(rows)]
    if v.steps:
        keys: List[str] = []
        for s in v.steps:
            keys += [k for k in s.measured if k not in keys]
        table = [[s.part, '%+.2f' % s.commanded, '%.1f-%.1f' % (s.started_s, s.ended_s),
                  'yes' if s.settled else 'no'] + [_m(s.measured.get(k)) for k in keys]
                 for s in v.steps]
        out += [Heading('Steps (rad; cameras: pixels of an 80-pixel-wide copy)'),
                Table(['part', 'commanded', 'time (s)', 'settled'] + keys, table,
                      numeric=list(range(1, 4 + len(keys))))]
    base = [('commanded', Series.of(v.commanded_yaw)), ('odometry', Series.of(v.odometry_yaw)),
            ('integrated gyro z', Series.of(v.gyro_yaw)), ('laser turn', Series.of(v.laser_turn))]
    head = [('HeadYaw commanded', Series.of(v.head_commanded)),
            ('HeadYaw measured', Series.of(v.head_measured))]
    if any(s for _, s in base) or any(s for _, s in head):
        out += [Heading('Commanded against measured'),
                Image(plots.motion(base, head, Series.of(v.picture_shift)),
                      'motion: commanded against each witness over time')]
    return out
