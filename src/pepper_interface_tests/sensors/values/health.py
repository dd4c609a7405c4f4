"""The health family's values (the driver's own /diagnostics): see sensors/health.py for the rules."""
from dataclasses import dataclass, field
from typing import Dict, List, Optional

from ...codec import optional


@dataclass(frozen=True)
class JointRow:
    joint: str = ''
    temperature_c: Optional[float] = None   # the highest seen in the window
    level: str = ''                         # the driver's worst level for it: OK, WARN, ERROR
    message: str = ''                       # the driver's words: OK, Hot, Too hot


@dataclass(frozen=True)
class HealthValues:
    driver_arrays: int = 0
    battery_percent: Optional[int] = None
    charging: Optional[bool] = None
    fully_charged: Optional[bool] = None
    battery_level: Optional[str] = None
    battery_message: Optional[str] = None
    highest_temperature_c: Optional[float] = None
    hottest: List[JointRow] = field(default_factory=list)   # the HOTTEST hottest joints
    hot: List[JointRow] = field(default_factory=list)       # every joint at WARN or ERROR
    temperatures: Optional[Dict[str, float]] = optional()   # joint -> the highest seen (drift)
