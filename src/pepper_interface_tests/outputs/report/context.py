"""What the page hands its plots and views (a leaf: page, plots and views all import it, it
imports none of them)."""
from dataclasses import dataclass
from typing import List, Optional

from ...results import RunResult
from .files import RunFiles


def anchor(name: str) -> str:
    """The HTML id of a sensor's section."""
    return 'sensor-' + ''.join(c if c.isalnum() or c in '-_' else '-' for c in str(name))


class View:
    """What a family view may use: the run's files, the run itself (another sensor's result)
    and the anchors of other sections."""

    def __init__(self, files: RunFiles, run: Optional[RunResult] = None) -> None:
        self.files = files
        self.run = run
        self.anchor = anchor


@dataclass
class RateRow:
    """One sensor's line of the rates figure."""
    name: str
    edges: List[float]
    rates: List[float]
    start: float
    end: float
    band: Optional[list]
    nominal: Optional[float]
    in_band: Optional[bool]
    label: str
