"""Microphone: levels per channel, one level-over-time strip per channel (a silent one marked),
the waveform of each channel, the WAV players (linked or embedded), and whether the speech
check's sentence was heard."""
import math
from typing import List, Optional, Sequence

from ....results import SensorResult
from ....sensors.values.audio import CHANNELS, AudioValues
from ....sensors.values.speech import SpeechValues
from .. import plots
from ..blocks import Block, Heading, Image, Para, Row, Span, Table
from ..context import View
from ..values import ChannelLevel, Series
from .fmt import num
from .speech import heard_text


def channels(r: SensorResult, v: AudioValues) -> List[ChannelLevel]:
    """Each channel's levels and level series; silent when all its samples are zero, its RMS is
    not finite, its level never was, or the check failed it as silent."""
    out = []
    for name in list(v.channels or {}) or list(CHANNELS):
        lv = (v.channels or {}).get(name)
        level = Series.of(v.level(name) if name in CHANNELS else [])
        silent = (lv is not None and (lv.all_zero or lv.rms_dbfs is None)) or \
            (bool(level) and all(math.isnan(y) for y in level.v)) or \
            any('microphone %s is silent' % name in str(x) for x in r.reasons or [])
        out.append(ChannelLevel(name, lv.rms_dbfs if lv else None, lv.peak_dbfs if lv else None,
                                lv.clipping_share if lv else None, silent, level))
    return out


def _speech(ctx: View) -> Optional[SpeechValues]:
    """The speech check's values when it ran in this run (and delivered its sentence)."""
    speech = next((s for s in ctx.run.sensors if s.name == 'speech'), None) if ctx.run else None
    if speech is None or not speech.messages:
        return None
    return speech.values if isinstance(speech.values, SpeechValues) else SpeechValues()


def wavs(r: SensorResult) -> List[str]:
    """The recordings, the main file first."""
    art = r.artifacts if isinstance(r.artifacts, dict) else {}
    files = [art.get('audio') or art.get('wav')] + [n for k, n in art.items() if str(k).startswith('audio_')]
    return [w for w in files if w]


def _levels_table(channels: Sequence[ChannelLevel]) -> Table:
    rows = []
    for c in channels:
        clip = '-' if c.clipping_share is None else '%.3f%%' % (100 * c.clipping_share)
        rms = num(c.rms_dbfs, 1) if c.rms_dbfs is not None else ('-inf' if c.silent else 'not measured')
        peak = num(c.peak_dbfs, 1) if c.peak_dbfs is not None else ('-inf' if c.silent else 'not measured')
        rows.append([c.name, rms, peak, clip, Span('silent', cls='fail-text', strong=True) if c.silent else ''])
    return Table(['channel', 'RMS dBFS', 'peak dBFS', 'clipping', 'silent'], rows, numeric=[1, 2, 3])


def render(r: SensorResult, v: AudioValues, ctx: View) -> List[Block]:
    out: List[Block] = []
    levels, files = channels(r, v), wavs(r)
    if levels:
        out += [Heading('Levels per channel'), _levels_table(levels)]
    if v.sample_rate_hz is not None:
        out.append(Para(['sample rate %s Hz measured (%s Hz expected)'
                         % (num(v.sample_rate_hz, 0), num(v.sample_rate_expected_hz, 0))]))
    speech = _speech(ctx)
    if speech is not None:
        rise = ', level rose %s dB' % num(speech.level_rise_db, 1) if speech.level_rise_db is not None else ''
        out.append(Para(['Test sentence heard by the microphones: ', heard_text(speech.heard), rise + ' (see ',
                         Span('speech', href='#' + ctx.anchor('speech')), ')']))
    figures = []
    if any(c.level for c in levels):
        figures.append(Image(plots.levels_per_channel(levels), 'microphone level over time, one plot per channel',
                             caption='Level over time (RMS per buffer, dBFS), one plot per channel'))
    if files:
        try:
            wave = plots.waveform(ctx.files.path(files[0]), files[0])
        except Exception as e:        # an unreadable WAV is said in the footer
            ctx.files.problems.append('waveform of %s: %s' % (files[0], e))
            wave = None
        if wave:
            figures.append(Image(wave, 'waveform of ' + files[0], caption='Waveform of each channel (own scale)'))
    if figures:
        out += [Heading('Level over time and waveform'), Row(figures)]
    if files:
        out += [Heading('Recording'), Row([ctx.files.media('audio', w, 'audio/wav') for w in files])]
    elif 'recording off' in (r.notes or []):
        out.append(Para(['No WAV file: recording is off for this run.']))
    elif r.messages:
        out.append(Para(['No WAV file recorded.'], cls='warn-text'))
    return out
