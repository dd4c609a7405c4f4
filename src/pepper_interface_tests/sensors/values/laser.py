"""The laser family's values: the counts of sensors/laser.py and its last scan, beam by beam."""
from dataclasses import dataclass
from enum import Enum
from typing import Dict, List, Optional

from ...codec import optional, series_optional
from . import Spread


class BeamKind(str, Enum):
    """What one beam of a scan is, as the laser check judges it (the report's scan plot draws
    each kind with its description as the legend)."""
    RETURN = 'return'
    BLIND = 'blind'
    NO_RETURN = 'no return'
    INVALID = 'invalid'

    def __str__(self) -> str:
        return self.value

    @property
    def description(self) -> str:
        return _DESCRIPTIONS[self]


_DESCRIPTIONS = {
    BeamKind.RETURN: 'returns: finite, at or above range_min (also beyond range_max)',
    BeamKind.BLIND: "blind: a slot of the driver's blind layout holding blind_value",
    BeamKind.NO_RETURN: 'no return: NaN (nan_is_no_return) or +inf, nothing seen',
    BeamKind.INVALID: 'invalid: NaN, negative, or below range_min',
}


@dataclass(frozen=True)
class LastScan:
    angle_min: float
    angle_increment: float
    ranges: List[float]            # NaN where the reading was not finite
    range_min: float
    range_max: float
    blind_value: Optional[float]
    kinds: List[BeamKind]          # per beam


@dataclass(frozen=True)
class LaserValues:
    beams: Optional[int] = optional()
    blind_beams: Optional[int] = optional()
    no_return_beams: Optional[int] = optional()
    invalid_beams: Optional[int] = optional()
    invalid_share: Optional[float] = optional()
    beyond_advertised_max: Optional[int] = optional()
    range_m: Optional[Spread] = optional()
    longest_identical_run: Optional[int] = optional()
    other_layout_scans: Optional[int] = optional()       # scans laid out otherwise than the profile
    dead_boards: Optional[List[str]] = optional()        # boards with no valid reading in the window
    longest_identical_board_run: Optional[Dict[str, int]] = optional()   # board -> scans
    # the driver's joint stiffness on /diagnostics (sensors/stiffness.py): True when every joint
    # was at 0 (a resting robot), False when one was above; absent without a report
    robot_resting: Optional[bool] = optional()
    board_valid_share: Optional[Dict[str, float]] = optional()   # board -> returns / non-blind slots
    range_noise_m: Optional[float] = optional()     # sensors/wear.py BeamNoise of the returns
    last_scan: Optional[LastScan] = series_optional()
