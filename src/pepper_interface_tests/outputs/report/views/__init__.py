"""One small renderer per sensor family.

`render(family, result, values, ctx)` returns the family's blocks (blocks.py) for the sensor's
section: a view receives the SensorResult (for its name and artifacts) and the family's typed
values (values.py); `ctx` (page.View) gives the run's files (files.RunFiles) and the anchors of
other sections. A family without a view shows only the common parts of its section.
"""
from typing import TYPE_CHECKING, List, Optional

from ....results import SensorResult
from ..blocks import Block
from ..values import FamilyValues
from . import audio, camera, depth, health, imu, joints, laser, odometry, speech, touch
from . import range as range_view

VIEWS = {'range': range_view, 'laser': laser, 'camera': camera, 'depth': depth, 'audio': audio,
         'joints': joints, 'odometry': odometry, 'imu': imu, 'speech': speech, 'touch': touch,
         'health': health}

if TYPE_CHECKING:
    from ..page import View


def render(family: Optional[str], result: SensorResult, values: Optional[FamilyValues],
           ctx: 'View') -> List[Block]:
    view = VIEWS.get(family) if family is not None else None
    if view is None or values is None:
        return []
    return view.render(result, values, ctx)
