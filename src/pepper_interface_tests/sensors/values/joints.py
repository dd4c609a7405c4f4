"""The joints family's values: sensors/joints.py."""
from dataclasses import dataclass
from typing import Dict, Optional

from ...codec import optional
from . import Spread


@dataclass(frozen=True)
class JointsValues:
    joints: Optional[Dict[str, Dict[str, Spread]]] = optional()   # joint -> position/velocity/effort
    joint_count: Optional[int] = optional()
    position_jumps: Optional[Dict[str, int]] = optional()              # joint -> jumps (sensors/jumps.py)
    largest_position_jump_rad: Optional[Dict[str, float]] = optional()
    position_noise_rad: Optional[Dict[str, float]] = optional()   # joint -> sensors/wear.py Noise
