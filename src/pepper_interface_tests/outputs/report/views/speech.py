"""Speech: the sentence, who received it, whether the microphones heard it."""
from typing import List, Optional, Union

from ....results import SensorResult
from ....sensors.values.speech import SpeechValues
from ..blocks import KV, Block, Heading, Span
from ..context import View
from .fmt import num


def heard_text(heard: Optional[bool]) -> Union[Span, str]:
    if heard is True:
        return Span('yes', strong=True)
    if heard is False:
        return Span('no', strong=True, cls='fail-text')
    return 'not measured (microphones not in this run)'


def render(r: SensorResult, v: SpeechValues, ctx: View) -> List[Block]:
    rows = [('sentence', v.text or '-'),
            ('delivered to', ', '.join(v.subscribers or []) or '-'),
            ('heard by the microphones', heard_text(v.heard))]
    if v.level_rise_db is not None:
        rows.append(('level rise while speaking', num(v.level_rise_db, 1, 'dB')))
    return [Heading('Speech'), KV(rows)]
