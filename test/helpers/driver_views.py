"""What naoqi_driver and a camera make of the emulator's world, computed independently of the
emulator for the tests that hold it to the driver: the laser scan the driver builds from
ALMemory's 90 values, and how far a picture moved sideways between two frames."""
import math

import numpy as np

# ros-naoqi/naoqi_driver src/converters/laser.cpp:165-205, transcribed: each device's points
# are read back as result_value[28-i], [58-i], [88-i] (Seg15..Seg01 X, Y), rotated by the
# device's mounting yaw and shifted by its position into base_footprint; 8 blind slots (-1.0)
# lie between the devices' 15 slots each
LASER_DEVICES = ((28, (-1.757, -0.018, -0.090)), (58, (0.0, 0.056, 0.0)), (88, (1.757, -0.018, 0.090)))


def driver_scan(memory):
    """The 61 ranges laser.cpp publishes for ALMemory's 90 laser values `memory` (an array)."""
    v = [float(x) for x in memory]
    ranges, pos = [-1.0] * 61, 0
    for base, (rot, sx, sy) in LASER_DEVICES:
        for i in range(0, 30, 2):
            lx, ly = v[base - i], v[base - i + 1]
            bx = lx * math.cos(rot) - ly * math.sin(rot) + sx
            by = lx * math.sin(rot) + ly * math.cos(rot) + sy
            ranges[pos] = math.hypot(bx, by)
            pos += 1
        pos += 8
    return np.asarray(ranges)


def shift_right(before, after, reach=3):
    """Columns a picture moved right between two column profiles: the shift (within a
    `reach`-th of the width either way) whose overlap differs least on average."""
    before, after = np.asarray(before, dtype=float), np.asarray(after, dtype=float)
    n = len(before)
    best = None
    for s in range(-n // reach, n // reach + 1):
        a = after[max(0, s):n + min(0, s)]
        b = before[max(0, -s):n - max(0, s)]
        err = float(np.mean(np.abs(a - b)))
        if best is None or err < best[0]:
            best = (err, s)
    return best[1]
