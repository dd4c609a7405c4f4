"""One small renderer per sensor family.

`render(family, result, values, ctx)` returns the family's blocks (blocks.py) for the sensor's
section: the view module is the family's row's `view` in sensors/families.py (views/<view>.py,
found by name); it receives the SensorResult (for its name, notes and artifacts) and the
family's values as its check handed them over (sensors/values/<family>.py); `ctx`
(context.View) gives the run, its files (files.RunFiles) and the anchors of other sections. A
family without a view shows only the common parts of its section.
"""
import importlib
from typing import Any, List, Optional

from ....results import SensorResult
from ....sensors import families
from ..blocks import Block
from ..context import View


def render(family: Optional[str], result: SensorResult, values: Any, ctx: View) -> List[Block]:
    row = families.FAMILIES.get(family) if family is not None else None
    if row is None or values is None:
        return []
    view = importlib.import_module('.' + row.view, __package__)
    return view.render(result, values, ctx)
