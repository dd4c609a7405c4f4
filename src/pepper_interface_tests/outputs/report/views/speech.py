"""Speech: the sentence, who received it, whether the microphones heard it."""
from ..blocks import KV, Heading, Span
from .fmt import num


def heard_text(heard):
    if heard is True:
        return Span('yes', strong=True)
    if heard is False:
        return Span('no', strong=True, cls='fail-text')
    return 'not measured (microphones not in this run)'


def render(r, v, ctx):
    rows = [('sentence', v.text or '-'),
            ('delivered to', ', '.join(v.subscribers) or '-'),
            ('heard by the microphones', heard_text(v.heard))]
    if v.level_rise_db is not None:
        rows.append(('level rise while speaking', num(v.level_rise_db, 1, 'dB')))
    return [Heading('Speech'), KV(rows)]
