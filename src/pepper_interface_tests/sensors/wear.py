"""Cheap measures of how a sensor wears, for the drift from a baseline (outputs/drift.py).

`Noise`: the scatter of a reading that changes slowly (a still robot's joint positions, a sonar
facing a wall, the gyrometer at rest) without the slow change: each reading's residual from the
straight line through the readings before and after it, r = x1 - (x0 + (x2 - x0) w) with
w = (t1 - t0) / (t2 - t0) (w = 1/2 without times), whose variance for white noise of standard
deviation s is s^2 (1 + w^2 + (1 - w)^2): a slow motion, also at an uneven pace when the times
are the sampling times, adds almost nothing. The estimate is robust: the median absolute
residual / 0.6745 (the standard deviation of normal noise), so a step (a person walking past
a sonar, a turn of the robot) in a few readings does not count as noise.
`BeamNoise` does the same for every beam of a scan (numpy arrays), over all beams together.
`focus_and_noise` measures a camera frame's sharpness and noise.
"""
import math
from typing import List, Optional, Tuple

import numpy as np

MAD_TO_SD = 0.6745      # median |x| of a normal variable / its standard deviation
KEEP = 20000            # residuals kept (the first ones): a 10 s window at 50 Hz of 17 joints is 8500
MIN_RESIDUALS = 10


def _robust_sd(residuals: List[float], nd: int) -> Optional[float]:
    if len(residuals) < MIN_RESIDUALS:
        return None
    return round(float(np.median(np.abs(residuals))) / MAD_TO_SD, nd)


class Noise:
    """Standard deviation of a slowly varying reading's noise (see the module's docstring);
    `add(v, t)` with the reading's sampling time (a header stamp) when there is one."""

    __slots__ = ('prev', 'prev2', 'residuals')

    def __init__(self) -> None:
        self.prev: Optional[Tuple[float, Optional[float]]] = None
        self.prev2: Optional[Tuple[float, Optional[float]]] = None
        self.residuals: List[float] = []

    def add(self, v: float, t: Optional[float] = None) -> None:
        if not math.isfinite(v):          # a gap: start again after it
            self.prev = self.prev2 = None
            return
        if self.prev is not None and self.prev2 is not None and len(self.residuals) < KEEP:
            (x0, t0), (x1, t1) = self.prev2, self.prev
            w = 0.5
            if t is not None and t0 is not None and t1 is not None and t > t1 > t0:
                w = (t1 - t0) / (t - t0)
            r = x1 - (x0 + (v - x0) * w)
            self.residuals.append(r / math.sqrt(1.0 + w * w + (1.0 - w) ** 2))
        self.prev2, self.prev = self.prev, (v, t)

    def sd(self, nd: int = 6) -> Optional[float]:
        """The noise's standard deviation; None under 10 readings past the first two."""
        return _robust_sd(self.residuals, nd)


class BeamNoise:
    """`Noise` of every beam over consecutive scans of one layout, all beams' residuals together."""

    def __init__(self) -> None:
        self.prev: Optional[np.ndarray] = None
        self.prev2: Optional[np.ndarray] = None
        self.residuals: List[float] = []

    def add(self, ranges: np.ndarray) -> None:
        r = np.asarray(ranges, dtype=float)
        if self.prev is not None and self.prev.shape != r.shape:
            self.prev = self.prev2 = None        # another layout: start again
        if self.prev is not None and self.prev2 is not None and len(self.residuals) < KEEP:
            res = (self.prev - (self.prev2 + r) / 2.0) / math.sqrt(1.5)
            self.residuals.extend(res[np.isfinite(res)].tolist())
        self.prev2, self.prev = self.prev, r

    def sd(self, nd: int = 5) -> Optional[float]:
        """The noise's standard deviation over all beams; None under 10 residuals."""
        return _robust_sd(self.residuals, nd)


def focus_and_noise(colour: np.ndarray) -> Tuple[float, float]:
    """(sharpness, noise) of one frame (H x W x channels, 0-255), on its grey at half size, each
    pixel the mean of a 2 x 2 block (not every 2nd pixel: a 1-pixel line would then count or
    vanish by the parity of its column, and a still robot's sharpness jump threefold with a
    HeadYaw noise of one pixel). Sharpness: the variance of the 4-neighbour Laplacian, the usual focus measure (a
    blurred or smeared lens loses the fine detail it measures), over the variance of the grey
    itself, so that a darker picture of the same scene (less light, a dimmer lens) keeps its
    sharpness (0 for a flat frame). Noise: Immerkaer's estimate
    (Fast noise variance estimation, CVIU 64(2), 1996): the mean absolute response to the mask
    [[1,-2,1],[-2,4,-2],[1,-2,1]] (which cancels edges and gradients) times sqrt(pi/2) / 6.
    Cost: about 0.65 ms of a 640x480 frame: the grey at half size summed in integers, every
    later sum in place in float32 (a float copy of the whole frame and numpy's mean over its
    channel axis took 4-5 ms for the same numbers)."""
    g = _half_grey(colour)
    if g.shape[0] < 3 or g.shape[1] < 3:
        return 0.0, 0.0
    lap = g[1:-1, 1:-1] * np.float32(4)
    for side in (g[:-2, 1:-1], g[2:, 1:-1], g[1:-1, :-2], g[1:-1, 2:]):
        lap -= side
    dy2 = g[:-2] + g[2:]          # the mask is the second difference down, then across
    dy2 -= g[1:-1]
    dy2 -= g[1:-1]
    mask = dy2[:, :-2] + dy2[:, 2:]
    mask -= dy2[:, 1:-1]
    mask -= dy2[:, 1:-1]
    np.abs(mask, out=mask)
    spread = float(g.var())
    sharpness = float(lap.var()) / spread if spread > 1e-6 else 0.0
    # x 2: a 2 x 2 mean halves the sd of a pixel's own noise; the estimate is per pixel
    return sharpness, float(2.0 * math.sqrt(math.pi / 2) * mask.mean() / 6.0)


def _half_grey(pixels: np.ndarray) -> np.ndarray:
    """The grey (the mean of the channels) at half size, each pixel the mean of a 2 x 2 block
    (an odd last row or column dropped), float32. 8-bit pixels are summed in uint16 over the
    block's pixels and channels (at most 4 x 3 x 255: exact) and scaled once: 0.35 ms for a
    640x480 rgb8 frame against 0.64 ms for the float32 grey at full size, then halved (the
    same values within float32 rounding)."""
    h, w = pixels.shape[0] // 2 * 2, pixels.shape[1] // 2 * 2
    p = pixels[:h, :w]
    if p.ndim < 3:
        p = p[:, :, None]
    channels = p.shape[2]
    if p.dtype != np.uint8 or 4 * channels * 255 > np.iinfo(np.uint16).max:
        return _half_float(p)
    total = p[::2, ::2, 0].astype(np.uint16)
    for c in range(channels):
        for dy, dx in ((0, 0), (1, 0), (0, 1), (1, 1)):
            if c or dy or dx:
                total += p[dy::2, dx::2, c]
    out = total.astype(np.float32)
    out *= np.float32(1.0 / (4 * channels))
    return out


def _half_float(p: np.ndarray) -> np.ndarray:
    """_half_grey for pixels that are not 8-bit (H x W x channels, even sides), in float32."""
    g = p[:, :, 0].astype(np.float32)
    for c in range(1, p.shape[2]):
        g += p[:, :, c]
    g /= np.float32(p.shape[2])
    out = g[::2, ::2] + g[1::2, ::2]
    out += g[::2, 1::2]
    out += g[1::2, 1::2]
    out *= np.float32(0.25)
    return out
