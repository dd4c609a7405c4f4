"""The motion family's values: sensors/motion.py (--move), the steps of motion/sequence.py."""
from dataclasses import dataclass, field
from typing import Dict, List, Optional

from ...codec import optional, series
from . import Point


@dataclass(frozen=True)
class StepValues:
    """One motion step: what was commanded and what each witness measured (rad)."""
    part: str = ''                 # 'head' or 'base'
    commanded: float = 0.0         # the change of yaw commanded (rad)
    started_s: float = 0.0         # seconds into the window
    ended_s: float = 0.0
    settled: bool = False          # False: the step timed out or was stopped
    # witness name (odometry, gyro, laser, wheels, HeadYaw, frontCamera ...) -> measured change
    # (rad; wheels: rad of wheel rotation; cameras: pixels of sideways shift)
    measured: Dict[str, Optional[float]] = field(default_factory=dict)


@dataclass(frozen=True)
class MotionValues:
    head: Optional[str] = optional()          # 'moved', 'did not move', or why it did not run
    base: Optional[str] = optional()
    stopped: Optional[str] = optional()       # where and why a motion was stopped
    steps: List[StepValues] = field(default_factory=list)
    # what was commanded against what each witness measured, over the window
    commanded_yaw: List[Point] = series()
    odometry_yaw: List[Point] = series()
    gyro_yaw: List[Point] = series()
    laser_turn: List[Point] = series()
    head_commanded: List[Point] = series()
    head_measured: List[Point] = series()
    picture_shift: List[Point] = series()
