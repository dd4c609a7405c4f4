"""The range family's values (sonars): see sensors/range.py for the rules."""
from dataclasses import dataclass
from typing import List, Optional

from ...codec import optional, series
from . import Point, Spread


@dataclass(frozen=True)
class RangeValues:
    range_m: Optional[Spread] = optional()
    infinite_ranges: Optional[int] = optional()
    field_of_view_rad: Optional[Spread] = optional()
    beyond_advertised_max: Optional[int] = optional()
    below_advertised_min: Optional[int] = optional()
    range_noise_m: Optional[float] = optional()      # sensors/wear.py Noise of the range
    range_series: List[Point] = series('range_m')
