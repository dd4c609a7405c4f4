"""Typed values per sensor family: what each view in views/ receives.

A view reads these dataclasses, never string keys out of `SensorResult.values` / `.series`.
Today adapters.py builds them from the checks' dicts; a check may later produce its dataclass
directly (then its adapter goes, and the view does not change).
"""
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Dict, Iterable, List, Optional, Tuple, Union

if TYPE_CHECKING:
    from ...sensors.health import HealthValues
    from ...sensors.touch import TouchValues

CHANNELS = ('rearLeft', 'rearRight', 'frontLeft', 'frontRight')   # sensors/audio.py order


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


def mapping(v: Any) -> Dict[Any, Any]:
    return v if isinstance(v, dict) else {}


@dataclass
class Spread:
    """min / mean (or median) / max of something; any of them may be unknown."""
    min: Optional[float] = None
    mid: Optional[float] = None
    max: Optional[float] = None

    @classmethod
    def of(cls, d: Any, mid: str = 'mean') -> Optional['Spread']:
        d = mapping(d)
        return cls(number(d.get('min')), number(d.get(mid)), number(d.get('max'))) if d else None


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
class RangeValues:
    range_m: Series
    min_range: Optional[float] = None
    max_range: Optional[float] = None


@dataclass
class LaserScanValues:
    angle_min: float
    angle_increment: float
    ranges: List[float]
    range_min: float
    range_max: float
    blind_value: Optional[float]
    kinds: List[str]        # per beam, as the check judged it (sensors/laser.py)


@dataclass
class VideoInfo:
    """What the recorder said (recording.VideoRecorder.summary) plus the video notes."""
    file: Optional[str] = None
    codec: Optional[str] = None
    fps: Optional[float] = None
    frames_received: Optional[int] = None
    frames_written: Optional[int] = None
    error: Optional[str] = None
    notes: List[str] = field(default_factory=list)
    recording_off: bool = False


@dataclass
class CameraValues:
    frames: List[tuple]                    # [(file, caption)]
    video: Optional[VideoInfo]
    width: Optional[int] = None
    height: Optional[int] = None
    encoding: Optional[str] = None
    brightness_mean: Optional[Spread] = None
    brightness_spread: Optional[Spread] = None
    frames_black: Optional[int] = None
    frames_constant: Optional[int] = None
    longest_identical_run: Optional[int] = None
    stereo: Optional[dict] = None
    brightness: Series = field(default_factory=Series)


@dataclass
class Histogram:
    edges: List[float]
    counts: List[float]
    unit: str = 'depth (m)'


@dataclass
class DepthValues:
    camera: CameraValues
    video_range_m: tuple = (0.0, 5.0)
    depth_m: Optional[Spread] = None
    valid_share: Optional[Spread] = None
    frames_all_zero: Optional[int] = None
    histogram: Optional[Histogram] = None
    median_depth_m: Series = field(default_factory=Series)
    valid: Series = field(default_factory=Series)


@dataclass
class ChannelLevel:
    name: str
    rms_dbfs: Optional[float] = None
    peak_dbfs: Optional[float] = None
    clipping_share: Optional[float] = None
    silent: bool = False
    level: Series = field(default_factory=Series)


@dataclass
class AudioValues:
    channels: List[ChannelLevel]
    sample_rate_hz: Optional[float] = None
    sample_rate_expected_hz: Optional[float] = None
    wavs: List[str] = field(default_factory=list)     # main file first
    recording_off: bool = False
    heard: Optional[bool] = None                       # by the speech check of the same run
    speech_in_run: bool = False
    level_rise_db: Optional[float] = None


@dataclass
class Joint:
    name: str
    position: Optional[Spread] = None
    velocity: Optional[Spread] = None
    effort: Optional[Spread] = None


@dataclass
class JointValues:
    joints: List[Joint]


@dataclass
class OdometryValues:
    x: Series
    y: Series


@dataclass
class ImuValues:
    acceleration: Series
    angular_velocity: Series


@dataclass
class SpeechValues:
    text: Optional[str] = None
    subscribers: List[str] = field(default_factory=list)
    heard: Optional[bool] = None
    level_rise_db: Optional[float] = None


# what adapters.adapt returns and views.render takes: one family's values
# (the touch and health families' values are their checks' own frozen dataclasses)
FamilyValues = Union[RangeValues, LaserScanValues, CameraValues, DepthValues, AudioValues, JointValues,
                     OdometryValues, ImuValues, SpeechValues, 'TouchValues', 'HealthValues']
