"""The audio family's values (the microphones): sensors/audio.py."""
from dataclasses import dataclass
from typing import Dict, List, Optional

from ...codec import nullable, optional, series
from . import Point

CHANNELS = ('rearLeft', 'rearRight', 'frontLeft', 'frontRight')   # naoqi_driver's channel order


@dataclass(frozen=True)
class ChannelLevel:
    rms_dbfs: Optional[float] = nullable()      # None: not finite (all zero)
    peak_dbfs: Optional[float] = nullable()
    clipping_share: Optional[float] = nullable()
    all_zero: bool = False


@dataclass(frozen=True)
class WavFile:
    channels: int
    sample_rate: int
    subtype: str
    seconds: float


@dataclass(frozen=True)
class AudioValues:
    mic_mode: Optional[str] = optional()
    recordings: Optional[Dict[str, WavFile]] = optional()     # file name -> what it holds
    samples_per_channel: Optional[int] = optional()
    buffer_sizes: Optional[Dict[int, int]] = optional()       # samples per buffer -> buffers
    sample_rate_hz: Optional[float] = optional()
    sample_rate_expected_hz: Optional[int] = optional()
    message_rate_band_hz: Optional[List[float]] = optional()
    channels: Optional[Dict[str, ChannelLevel]] = optional()  # CHANNELS -> levels
    longest_identical_run: Optional[int] = optional()
    gaps: Optional[List[List[float]]] = optional()            # [t, pause s], the first 50
    # 'rearLeft-rearRight' -> mean square difference over the channels' own one-sample step
    # (sensors/channels.py; None: no step); 0 for copied channels, below 1 when dealt out
    channel_step_ratios: Optional[Dict[str, Optional[float]]] = optional()
    level_rear_left: List[Point] = series('level_dbfs_rearLeft')
    level_rear_right: List[Point] = series('level_dbfs_rearRight')
    level_front_left: List[Point] = series('level_dbfs_frontLeft')
    level_front_right: List[Point] = series('level_dbfs_frontRight')

    def level(self, channel: str) -> List[Point]:
        """The level series (dBFS over time) of one of CHANNELS."""
        return {'rearLeft': self.level_rear_left, 'rearRight': self.level_rear_right,
                'frontLeft': self.level_front_left, 'frontRight': self.level_front_right}[channel]
