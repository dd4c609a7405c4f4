"""The speech family's values: sensors/speech.py."""
from dataclasses import dataclass
from typing import List, Optional

from ...codec import nullable, optional


@dataclass(frozen=True)
class SpeechValues:
    text: Optional[str] = optional()
    subscribers: Optional[List[str]] = optional()
    heard: Optional[bool] = nullable()        # None: no microphone listened
    level_rise_db: Optional[float] = optional()
