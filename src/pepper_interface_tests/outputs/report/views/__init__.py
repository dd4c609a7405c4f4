"""One small renderer per sensor family.

`render(family, result, values, ctx)` returns the family's blocks (blocks.py) for the sensor's
section: a view receives the SensorResult (for its name and artifacts) and the family's typed
values (values.py); `ctx` (page.View) gives the run's files (files.RunFiles) and the anchors of
other sections. The view of a family is the module views/<Family.view>.py of the family registry
(sensors/families.py), found by name: a new family adds its module and nothing here. A family
without a view shows only the common parts of its section.
"""
import importlib
from typing import TYPE_CHECKING, List, Optional

from ....results import SensorResult
from ....sensors import families
from ..blocks import Block
from ..values import FamilyValues

if TYPE_CHECKING:
    from ..page import View


def render(family: Optional[str], result: SensorResult, values: Optional[FamilyValues],
           ctx: 'View') -> List[Block]:
    if family is None or values is None or family not in families.FAMILIES:
        return []
    view = importlib.import_module('.' + families.family(family).view, __package__)
    return view.render(result, values, ctx)
