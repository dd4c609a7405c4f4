"""One small renderer per sensor family.

`render(family, result, values, ctx)` returns the family's blocks (blocks.py) for the sensor's
section: a view receives the SensorResult (for its name, notes and artifacts) and the family's
values as its check handed them over (sensors/values/<family>.py); `ctx` (context.View) gives
the run, its files (files.RunFiles) and the anchors of other sections. A family without a view
shows only the common parts of its section.
"""
from typing import Any, List, Optional

from ....results import SensorResult
from ..blocks import Block
from ..context import View
from . import audio, camera, depth, imu, joints, laser, odometry, speech
from . import range as range_view

VIEWS = {'range': range_view, 'laser': laser, 'camera': camera, 'depth': depth, 'audio': audio,
         'joints': joints, 'odometry': odometry, 'imu': imu, 'speech': speech}


def render(family: Optional[str], result: SensorResult, values: Any, ctx: View) -> List[Block]:
    view = VIEWS.get(family) if family is not None else None
    if view is None or values is None:
        return []
    return view.render(result, values, ctx)
