"""Cheap measures of how a sensor wears, for the drift from a baseline (outputs/drift.py).

`Noise`: the scatter of a reading that changes slowly (a still robot's joint positions, a sonar
facing a wall, the gyrometer at rest) without the slow change: the second difference of
consecutive readings, d2 = x[i] - 2 x[i-1] + x[i-2], cancels a straight-line trend, and for white
noise of standard deviation s its variance is 6 s^2, so s = sqrt(mean(d2^2) / 6). A slow
sinusoid of amplitude A and frequency f sampled at r Hz adds only about A (2 pi f / r)^2.
`BeamNoise` does the same for every beam of a scan (numpy arrays), the median over beams.
`focus_and_noise` measures a camera frame's sharpness and noise.
"""
import math
from typing import List, Optional, Tuple

import numpy as np


class Noise:
    """Standard deviation of a slowly varying reading's noise (see the module's docstring). With
    the times of the readings (`add(v, t)`: the header stamps, when they are the sampling
    times) the residual of each reading from the straight line through its neighbours is used
    instead, r = x1 - (x0 + (x2 - x0) w), w = (t1 - t0) / (t2 - t0), whose variance for white
    noise is s^2 (1 + w^2 + (1 - w)^2): readings that move (an arm's slow motion) at an uneven
    pace then add no false noise."""

    __slots__ = ('prev', 'prev2', 'total', 'n')

    def __init__(self) -> None:
        self.prev: Optional[Tuple[float, Optional[float]]] = None
        self.prev2: Optional[Tuple[float, Optional[float]]] = None
        self.total, self.n = 0.0, 0

    def add(self, v: float, t: Optional[float] = None) -> None:
        if not math.isfinite(v):          # a gap: start again after it
            self.prev = self.prev2 = None
            return
        if self.prev is not None and self.prev2 is not None:
            (x0, t0), (x1, t1) = self.prev2, self.prev
            if t is not None and t0 is not None and t1 is not None and t > t1 > t0:
                w = (t1 - t0) / (t - t0)
                r = x1 - (x0 + (v - x0) * w)
                self.total += r * r / (1.0 + w * w + (1.0 - w) ** 2)
            else:
                d2 = v - 2.0 * x1 + x0
                self.total += d2 * d2 / 6.0
            self.n += 1
        self.prev2, self.prev = self.prev, (v, t)

    def sd(self, nd: int = 6) -> Optional[float]:
        """The noise's standard deviation; None under 10 readings past the first two."""
        return round(math.sqrt(self.total / self.n), nd) if self.n >= 10 else None


class BeamNoise:
    """`Noise` per beam of consecutive scans of one layout; the median over the beams."""

    def __init__(self) -> None:
        self.prev: Optional[np.ndarray] = None
        self.prev2: Optional[np.ndarray] = None
        self.total: Optional[np.ndarray] = None
        self.n: Optional[np.ndarray] = None

    def add(self, ranges: np.ndarray) -> None:
        r = np.asarray(ranges, dtype=float)
        if self.prev is not None and self.prev.shape != r.shape:
            self.prev = self.prev2 = self.total = self.n = None    # another layout: start again
        if self.prev is not None and self.prev2 is not None:
            d2 = r - 2.0 * self.prev + self.prev2
            ok = np.isfinite(d2)
            if self.total is None or self.n is None:
                self.total, self.n = np.zeros(r.shape), np.zeros(r.shape)
            self.total[ok] += d2[ok] ** 2
            self.n[ok] += 1
        self.prev2, self.prev = self.prev, r

    def sd(self, nd: int = 5) -> Optional[float]:
        """The median over beams with 10 or more second differences; None when none has."""
        if self.total is None or self.n is None:
            return None
        enough = self.n >= 10
        if not enough.any():
            return None
        per_beam: List[float] = list(np.sqrt(self.total[enough] / self.n[enough] / 6.0))
        return round(float(np.median(per_beam)), nd)


def focus_and_noise(colour: np.ndarray) -> Tuple[float, float]:
    """(sharpness, noise) of one frame (H x W x channels, 0-255), on every 2nd row and column of
    its grey. Sharpness: the variance of the 4-neighbour Laplacian, the usual focus measure (a
    blurred or smeared lens loses the fine detail it measures). Noise: Immerkaer's estimate
    (Fast noise variance estimation, CVIU 64(2), 1996): the mean absolute response to the mask
    [[1,-2,1],[-2,4,-2],[1,-2,1]] (which cancels edges and gradients) times sqrt(pi/2) / 6."""
    g = colour[::2, ::2].astype(np.float32).mean(axis=2) if colour.ndim == 3 else \
        colour[::2, ::2].astype(np.float32)
    if g.shape[0] < 3 or g.shape[1] < 3:
        return 0.0, 0.0
    lap = 4 * g[1:-1, 1:-1] - g[:-2, 1:-1] - g[2:, 1:-1] - g[1:-1, :-2] - g[1:-1, 2:]
    dy2 = g[:-2] - 2 * g[1:-1] + g[2:]
    mask = dy2[:, :-2] - 2 * dy2[:, 1:-1] + dy2[:, 2:]
    return float(lap.var()), float(math.sqrt(math.pi / 2) * np.abs(mask).mean() / 6.0)
