"""What the motion check's witnesses saw (pure data, fed from subscriber threads under a lock).

Each series is (t, value) with t in seconds of the check's clock (time.monotonic)."""
import threading
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Tuple

import numpy as np

# naoqi_driver's wheel joints (pepper_description: WheelFL, WheelFR, WheelB)
WHEELS = ('WheelFL', 'WheelFR', 'WheelB')


@dataclass
class Scan:
    t: float
    ranges: np.ndarray          # float, invalid beams NaN
    increment: float            # angle_increment (rad; negative: beams stored clockwise)


@dataclass
class Recording:
    lock: threading.Lock = field(default_factory=threading.Lock)
    joints: List[Tuple[float, Dict[str, float]]] = field(default_factory=list)
    odom_yaw: List[Tuple[float, float]] = field(default_factory=list)
    odom_xy: List[Tuple[float, float, float]] = field(default_factory=list)   # t, x, y (m)
    gyro: List[Tuple[float, float, float, float]] = field(default_factory=list)   # t, x, y, z
    scans: List[Scan] = field(default_factory=list)
    sonar: Dict[str, Tuple[float, float]] = field(default_factory=dict)   # name -> (t, range)
    laser_front: Optional[Tuple[float, float]] = None     # (t, nearest range within +-0.2 rad)
    laser_nearest: Optional[Tuple[float, float, float]] = None   # (t, range, angle)
    bumpers: Dict[int, bool] = field(default_factory=dict)         # bumper id -> pressed
    stiffness: Dict[str, float] = field(default_factory=dict)      # joint -> Stiffness
    health_error: Optional[str] = None      # a status at ERROR from naoqi_driver
    # camera name -> [(t, small grey frame)]
    frames: Dict[str, List[Tuple[float, np.ndarray]]] = field(default_factory=dict)
    # topic -> its latest header stamp and receive time (the clock cross-check)
    stamps: Dict[str, Tuple[float, float]] = field(default_factory=dict)
    heard: Dict[str, int] = field(default_factory=dict)     # witness -> messages
    # live, placed by their stamps (witnesses.STAMPED): the most a message was handled behind
    # its witness's least late one (s; stats.StampPlacer)
    behind: float = 0.0

    def count(self, what: str) -> None:
        self.heard[what] = self.heard.get(what, 0) + 1

    def joint_series(self, name: str, t0: float = -1e18, t1: float = 1e18) -> List[Tuple[float, float]]:
        with self.lock:
            return [(t, p[name]) for t, p in self.joints if name in p and t0 <= t <= t1]

    def latest_joint(self, name: str) -> Optional[float]:
        with self.lock:
            for _, p in reversed(self.joints):
                if name in p:
                    return p[name]
        return None
