"""The touch family's values (head, hands, bumpers): see sensors/touch.py for the rules."""
from dataclasses import dataclass, field
from typing import List, Optional


@dataclass(frozen=True)
class ZoneRow:
    """One zone of the report's table."""
    zone: str = ''                          # "the front of the head"
    id: str = ''                            # headTouch/front
    index: int = -1                         # the driver's index
    presses: int = 0
    pressed_at: Optional[float] = None      # s in the window, the first press
    released_at: Optional[float] = None     # s in the window, the release of that press
    held_s: Optional[float] = None
    # passed, touched, not touched, not pressed within 15 s, too late: pressed 4.2 s after the
    # 15 s wait, stuck, skipped by the operator
    outcome: str = ''


@dataclass(frozen=True)
class TouchValues:
    mode: str = ''                          # guided or unattended
    zones: List[ZoneRow] = field(default_factory=list)
