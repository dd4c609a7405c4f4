"""The odometry family's values: sensors/odometry.py."""
from dataclasses import dataclass
from typing import List, Optional

from ...codec import optional, series
from . import Point, Spread


@dataclass(frozen=True)
class OdometryValues:
    pose_implied_speed_m_s: Optional[Spread] = optional()
    pose_jumps: Optional[int] = optional()             # poses that jumped (sensors/jumps.py)
    largest_pose_jump_m: Optional[float] = optional()
    x_m: Optional[Spread] = optional()
    y_m: Optional[Spread] = optional()
    speed_m_s: Optional[Spread] = optional()
    x_series: List[Point] = series('x_m')
    y_series: List[Point] = series('y_m')
    # the pose's yaw (rad): the recorded motion cross-check against the gyro (sensors/cross.py)
    yaw_series: List[Point] = series('yaw_rad')
