"""The camera family's values (and the image fields the depth family shares): sensors/camera.py."""
from dataclasses import dataclass
from typing import Dict, List, Optional

from ...codec import nullable, optional, series
from . import Point, Spread


@dataclass(frozen=True)
class VideoSummary:
    """What the video recorder reports when it closes (media/recording.py VideoRecorder.summary)."""
    file: Optional[str] = nullable()
    codec: Optional[str] = nullable()
    fps: Optional[float] = nullable()
    width: Optional[int] = nullable()
    height: Optional[int] = nullable()
    frames_received: Optional[int] = nullable()
    frames_written: Optional[int] = nullable()
    frames_dropped: Optional[int] = nullable()
    frames_resized: Optional[int] = nullable()
    late_frames: Optional[int] = nullable()
    error: Optional[str] = nullable()
    finish_s: Optional[float] = nullable()
    encoder_cpu_s: Optional[float] = nullable()
    writer_cpu_s: Optional[float] = nullable()


@dataclass(frozen=True)
class Stereo:
    width: int
    height: int
    view_width: int
    view_height: int
    identical_views: int


@dataclass(frozen=True)
class ImageValues:
    """What every image family measures (sensors/camera.py ImageCheck)."""
    width: Optional[int] = optional()
    height: Optional[int] = optional()
    encoding: Optional[str] = optional()
    step: Optional[int] = optional()
    geometries: Optional[Dict[str, int]] = optional()   # 'WxH encoding' -> frames, when it changed
    video: Optional[VideoSummary] = optional()


@dataclass(frozen=True)
class CameraValues(ImageValues):
    brightness_mean: Optional[Spread] = optional()
    brightness_spread: Optional[Spread] = optional()
    frames_black: Optional[int] = optional()
    frames_constant: Optional[int] = optional()
    longest_identical_run: Optional[int] = optional()
    stereo: Optional[Stereo] = optional()
    sharpness: Optional[float] = optional()     # mean Laplacian variance / grey variance (sensors/wear.py)
    noise: Optional[float] = optional()         # mean noise sd, 0-255 (sensors/wear.py)
    brightness: List[Point] = series()
