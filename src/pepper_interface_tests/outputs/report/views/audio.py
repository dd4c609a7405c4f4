"""Microphone: levels per channel, one level-over-time strip per channel (a silent one marked),
the waveform of each channel, the WAV players (linked or embedded), and whether the speech
check's sentence was heard."""
from typing import TYPE_CHECKING, List, Sequence

from ....results import SensorResult
from .. import plots
from ..blocks import Block, Heading, Image, Para, Row, Span, Table
from ..values import AudioValues, ChannelLevel
from .fmt import num
from .speech import heard_text

if TYPE_CHECKING:
    from ..page import View


def _levels_table(channels: Sequence[ChannelLevel]) -> Table:
    rows = []
    for c in channels:
        clip = '-' if c.clipping_share is None else '%.3f%%' % (100 * c.clipping_share)
        rms = num(c.rms_dbfs, 1) if c.rms_dbfs is not None else ('-inf' if c.silent else 'not measured')
        peak = num(c.peak_dbfs, 1) if c.peak_dbfs is not None else ('-inf' if c.silent else 'not measured')
        rows.append([c.name, rms, peak, clip, Span('silent', cls='fail-text', strong=True) if c.silent else ''])
    return Table(['channel', 'RMS dBFS', 'peak dBFS', 'clipping', 'silent'], rows, numeric=[1, 2, 3])


def render(r: SensorResult, v: AudioValues, ctx: 'View') -> List[Block]:
    out: List[Block] = []
    if v.channels:
        out += [Heading('Levels per channel'), _levels_table(v.channels)]
    if v.sample_rate_hz is not None:
        out.append(Para(['sample rate %s Hz measured (%s Hz expected)'
                         % (num(v.sample_rate_hz, 0), num(v.sample_rate_expected_hz, 0))]))
    if v.speech_in_run:
        rise = ', level rose %s dB' % num(v.level_rise_db, 1) if v.level_rise_db is not None else ''
        out.append(Para(['Test sentence heard by the microphones: ', heard_text(v.heard), rise + ' (see ',
                         Span('speech', href='#' + ctx.anchor('speech')), ')']))
    figures = []
    if any(c.level for c in v.channels):
        figures.append(Image(plots.levels_per_channel(v.channels), 'microphone level over time, one plot per channel',
                             caption='Level over time (RMS per buffer, dBFS), one plot per channel'))
    if v.wavs:
        try:
            wave = plots.waveform(ctx.files.path(v.wavs[0]), v.wavs[0])
        except Exception as e:        # an unreadable WAV is said in the footer
            ctx.files.problems.append('waveform of %s: %s' % (v.wavs[0], e))
            wave = None
        if wave:
            figures.append(Image(wave, 'waveform of ' + v.wavs[0], caption='Waveform of each channel (own scale)'))
    if figures:
        out += [Heading('Level over time and waveform'), Row(figures)]
    if v.wavs:
        out += [Heading('Recording'), Row([ctx.files.media('audio', w, 'audio/wav') for w in v.wavs])]
    elif v.recording_off:
        out.append(Para(['No WAV file: recording is off for this run.']))
    elif r.messages:
        out.append(Para(['No WAV file recorded.'], cls='warn-text'))
    return out
