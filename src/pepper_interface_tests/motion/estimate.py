"""What a witness measured over a step, from the recorded series (pure functions: numpy;
OpenCV for small_grey's area reduction).

- yaw_of: the yaw of a quaternion (rad, about z, counter-clockwise positive: REP 103).
- change: a series' change between two times, angles unwrapped.
- integrated_gyro: the gyro's rates integrated over a step, per axis (trapezoids).
- scan_turn: how far the robot turned between two scans, from how far the picture of the room
  slid along the beams. A robot turning counter-clockwise by a sees a point at angle p at p - a,
  so the later scan b holds at beam j what the earlier a held at j + a / angle_increment; the
  shift with the least mean difference (refined between beams by a parabola) times the
  increment is the turn. naoqi_driver stores the beams right to left, angle_min -2.0944 first,
  with a positive increment (src/converters/laser.cpp:158-161, 216-218): a scan stored in the
  other order gives the opposite turn. Blind slots (-1.0, laser.cpp:221), NaN and readings
  below range_min take no part.
- picture_shift: the sideways shift (pixels, positive: the picture moved right) between two
  small grey frames: the shift whose overlap differs least (see its docstring).
  A head yawing left (positive yaw) moves the scene right in a forward-looking camera.
"""
import math
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

BLUR = 0.04     # the sideways blur of picture_shift, a share of the picture's width
TEXTURE_LAG = 4  # pixels of the ~80-wide copy still_texture moves a picture by (~0.05 rad)


def yaw_of(x: float, y: float, z: float, w: float) -> float:
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def wrap(a: float) -> float:
    return math.atan2(math.sin(a), math.cos(a))


def value_at(series: Sequence[Tuple[float, float]], t: float) -> Optional[float]:
    """The last value at or before t (the first one when none is that early); None: empty."""
    if not series:
        return None
    best = series[0][1]
    for ts, v in series:
        if ts > t:
            break
        best = v
    return best


def change(series: Sequence[Tuple[float, float]], t0: float, t1: float, angle: bool = True) -> Optional[float]:
    """How much the series changed from t0 to t1, summed step by step (angles unwrapped); None
    when it has no value at or before t1."""
    pts = [(t, v) for t, v in series if t <= t1]
    if not pts:
        return None
    start = value_at(pts, t0)
    inside = [v for t, v in pts if t > t0]
    if start is None:
        return None
    total, last = 0.0, start
    for v in inside:
        d = v - last
        total += wrap(d) if angle else d
        last = v
    return total


def integrated_gyro(gyro: Sequence[Tuple[float, float, float, float]], t0: float,
                    t1: float) -> Optional[Tuple[float, float, float]]:
    pts = [g for g in gyro if t0 <= g[0] <= t1]
    if len(pts) < 2:
        return None
    out = [0.0, 0.0, 0.0]
    for a, b in zip(pts, pts[1:]):
        dt = b[0] - a[0]
        for k in range(3):
            out[k] += 0.5 * (a[k + 1] + b[k + 1]) * dt
    return out[0], out[1], out[2]


def gyro_series(gyro: Sequence[Tuple[float, float, float, float]], t0: float) -> List[Tuple[float, float]]:
    """The integrated gyro z from t0 on: [(t, rad)]."""
    out: List[Tuple[float, float]] = []
    total = 0.0
    prev = None
    for g in gyro:
        if g[0] < t0:
            continue
        if prev is not None:
            total += 0.5 * (prev[3] + g[3]) * (g[0] - prev[0])
        out.append((g[0], total))
        prev = g
    return out


def valid_ranges(ranges: Sequence[float], range_min: float) -> np.ndarray:
    """Ranges with blind slots (-1.0), NaN, +-inf and readings below range_min as NaN; raw
    readings beyond range_max are real distances (naoqi_driver does not clip: laser.cpp:165-205)."""
    r = np.asarray(ranges, dtype=float)
    bad = ~np.isfinite(r) | (r < max(range_min, 0.0))
    return np.where(bad, np.nan, r)


def scan_turn(a: np.ndarray, b: np.ndarray, increment: float, max_turn: float = 1.2) -> Optional[float]:
    """The robot's turn (rad) from scan a to scan b (see the module's docstring); None when the
    scans share too few valid beams to tell."""
    n = min(len(a), len(b))
    if n < 10 or increment == 0:
        return None
    kmax = min(n // 3, int(abs(max_turn / increment)) + 1)
    errors = {}
    fa, fb = np.isfinite(a[:n]), np.isfinite(b[:n])
    least = max(5, n // 6)
    for k in range(-kmax, kmax + 1):    # called on every pair of scans: numpy's reductions direct
        if k >= 0:
            x, y, ok = a[k:n], b[:n - k], fa[k:] & fb[:n - k]
        else:
            x, y, ok = a[:n + k], b[-k:n], fa[:n + k] & fb[-k:]
        count = int(np.count_nonzero(ok))
        if count < least:
            continue
        errors[k] = float(np.add.reduce(np.abs(x[ok] - y[ok])) / count)    # the mean, as np.mean
    if not errors:
        return None
    return best_offset(errors) * increment


def best_offset(errors: Dict[int, float]) -> float:
    """The offset whose error is least (the smaller one on a tie), refined between whole
    offsets by the parabola through it and its two neighbours."""
    k = min(errors, key=lambda j: (errors[j], abs(j)))
    frac = 0.0
    if k - 1 in errors and k + 1 in errors:
        e0, e1, e2 = errors[k - 1], errors[k], errors[k + 1]
        den = e0 - 2 * e1 + e2
        if den > 1e-12:
            frac = max(-0.5, min(0.5, 0.5 * (e0 - e2) / den))
    return k + frac


def small_grey(data: np.ndarray, width: int = 80) -> np.ndarray:
    """A frame (h x w or h x w x c, integer pixels) as a small float grey picture about `width`
    wide, each pixel the mean of a block of the frame (an average, not every n-th pixel: a fine
    periodic texture such as floorboards would otherwise alias into a false shift). The blocks
    are averaged by OpenCV's area reduction (INTER_AREA, which averages whole blocks when the
    factor is an integer, rounding to the frame's own integers: within half a grey level),
    then the channels of the small picture: about 0.3 ms of a 640x480 rgb8 frame, where a float
    copy of the whole frame averaged in numpy took 5-8 ms. OpenCV is imported here, on the
    first frame, not with the module: its import costs more CPU than a recording without
    head motion ever needs."""
    import cv2
    step = max(1, data.shape[1] // width)
    h, w = (data.shape[0] // step) * step, (data.shape[1] // step) * step
    img = data[:h, :w]
    if step > 1:
        img = cv2.resize(img, (w // step, h // step), interpolation=cv2.INTER_AREA)
    small = img.astype(np.float32)
    return small.mean(axis=2) if small.ndim == 3 else small


def _blur_x(img: np.ndarray, sigma: float) -> np.ndarray:
    k = np.arange(-int(3 * sigma), int(3 * sigma) + 1)
    kernel = np.exp(-0.5 * (k / sigma) ** 2)
    kernel /= kernel.sum()
    pad = np.pad(img, ((0, 0), (len(k) // 2, len(k) // 2)), mode='edge')
    return np.apply_along_axis(lambda r: np.convolve(r, kernel, mode='valid'), 1, pad)


def _prepared(a: np.ndarray) -> np.ndarray:
    """A small grey frame as picture_shift compares it: its mean taken away, blurred sideways
    (sigma BLUR of the width), the blur's edges (padding, not picture) left out."""
    w = a.shape[1]
    sigma = max(1.0, BLUR * w)
    m = int(3 * sigma)
    return _blur_x(a - a.mean(), sigma)[:, m:w - m]


def still_texture(frames: Sequence[np.ndarray], lag: int = TEXTURE_LAG) -> Optional[float]:
    """How much the still picture differs from itself moved `lag` pixels sideways (mean grey
    levels, as picture_shift compares frames): the texture a turning head's picture can be
    followed by. The frames are ones taken while the head stood still; their per-pixel median
    leaves out what moves on its own (a person walking by, a ball), which a shift would
    otherwise follow instead of the room. None: no frame, or frames of different sizes."""
    if not frames or any(f.shape != frames[0].shape for f in frames):
        return None
    still = np.median(np.stack(frames), axis=0) if len(frames) > 1 else frames[0]
    f = _prepared(still)
    if f.shape[1] <= lag:
        return None
    return float(np.mean(np.abs(f[:, lag:] - f[:, :-lag])))


def picture_shift(a: np.ndarray, b: np.ndarray) -> Optional[float]:
    """Sideways shift (pixels of a and b's scale) from frame a to frame b: positive when the
    picture moved right; None when a frame is flat (nothing to follow). Both are blurred
    sideways (sigma BLUR of the width: a fine periodic texture, floorboards or tiles, would
    otherwise match one period off), then the shift d (within a third of the width) whose
    overlap differs least, b[:, x + d] against a[:, x], refined between pixels by a parabola."""
    if a.shape != b.shape or a.std() < 1e-3 or b.std() < 1e-3:
        return None
    fa, fb = _prepared(a), _prepared(b)
    w = fa.shape[1]
    errors = {}
    for d in range(-(w // 3), w // 3 + 1):
        if d >= 0:
            x, y = fa[:, :w - d], fb[:, d:]
        else:
            x, y = fa[:, -d:], fb[:, :w + d]
        errors[d] = float(np.mean(np.abs((x - x.mean()) - (y - y.mean()))))   # brightness aside
    return best_offset(errors)
