"""The depth family's values: sensors/depth.py."""
from dataclasses import dataclass
from typing import List, Optional

from ...codec import nullable, optional, series
from . import Point, Spread
from .camera import ImageValues


@dataclass(frozen=True)
class MedianSpread:
    min: Optional[float] = nullable()
    median: Optional[float] = nullable()
    max: Optional[float] = nullable()


@dataclass(frozen=True)
class DepthHistogram:
    edges: List[float]          # bin edges (m), one more than counts
    counts: List[float]


@dataclass(frozen=True)
class DepthValues(ImageValues):
    video_range_m: Optional[List[float]] = optional()
    frames_all_zero: Optional[int] = optional()
    valid_share: Optional[Spread] = optional()
    depth_m: Optional[MedianSpread] = optional()
    longest_identical_run: Optional[int] = optional()
    depth_histogram: Optional[DepthHistogram] = optional()
    centre_depth_m: Optional[float] = optional()   # mean depth of the middle third of the frame
    median_depth_m: List[Point] = series()
    valid_series: List[Point] = series('valid_share')
