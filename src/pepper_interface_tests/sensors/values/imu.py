"""The IMU family's values: sensors/imu.py."""
from dataclasses import dataclass
from typing import List, Optional

from ...codec import optional, series
from . import Point, Spread


@dataclass(frozen=True)
class ImuValues:
    longest_identical_run: Optional[int] = optional()
    acceleration_norm_median_m_s2: Optional[float] = optional()
    acceleration_norm_m_s2: Optional[Spread] = optional()
    angular_velocity_norm_rad_s: Optional[Spread] = optional()
    angular_velocity_noise_rad_s: Optional[float] = optional()   # sensors/wear.py Noise of |w|
    acceleration_m_s2: List[Point] = series()
    angular_velocity_rad_s: List[Point] = series()
    # the gyro's z (rad/s): the recorded motion cross-check against odometry (sensors/cross.py)
    angular_velocity_z_rad_s: List[Point] = series()
