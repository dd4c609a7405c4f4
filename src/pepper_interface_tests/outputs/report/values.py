"""What the report alone derives for its plots and views; the families' own values are the
dataclasses of sensors/values/, which the views receive as they are.

A view turns a family's [(t, value)] points into a `Series`, the camera's recorder summary and
notes into a `VideoInfo`, the microphone's levels into `ChannelLevel`s, a depth histogram into
a `Histogram`.
"""
from dataclasses import dataclass, field
from typing import Any, Iterable, List, Optional, Tuple


def xy(points: Optional[Iterable[Any]]) -> Tuple[List[float], List[float]]:
    """[(t, v), ...] with None values -> (times, values) float lists (None -> nan)."""
    xs, ys = [], []
    for p in points or []:
        try:
            t, v = float(p[0]), p[1]
        except (TypeError, IndexError, ValueError):
            continue
        try:
            ys.append(float('nan') if v is None else float(v))
        except (TypeError, ValueError):
            continue
        xs.append(t)
    return xs, ys


def number(v: Any) -> Optional[float]:
    try:
        f = float(v)
    except (TypeError, ValueError):
        return None
    return f


@dataclass
class Series:
    t: List[float] = field(default_factory=list)
    v: List[float] = field(default_factory=list)

    @classmethod
    def of(cls, points: Optional[Iterable[Any]]) -> 'Series':
        return cls(*xy(points))

    def __bool__(self) -> bool:
        return bool(self.t)


@dataclass
class VideoInfo:
    """What the recorder said (sensors/values/camera.py VideoSummary) plus the video notes."""
    file: Optional[str] = None
    codec: Optional[str] = None
    fps: Optional[float] = None
    frames_received: Optional[int] = None
    frames_written: Optional[int] = None
    error: Optional[str] = None
    notes: List[str] = field(default_factory=list)
    recording_off: bool = False


@dataclass
class Histogram:
    edges: List[float]
    counts: List[float]
    unit: str = 'depth (m)'


@dataclass
class ChannelLevel:
    name: str
    rms_dbfs: Optional[float] = None
    peak_dbfs: Optional[float] = None
    clipping_share: Optional[float] = None
    silent: bool = False
    level: Series = field(default_factory=Series)
