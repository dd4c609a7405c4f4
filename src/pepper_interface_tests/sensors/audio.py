"""Microphones: AudioCustomMsg (int16[] rearLeft, rearRight, frontLeft, frontRight; the
CSSR4Africa naoqi_driver fork, msg/AudioCustomMsg.msg) or naoqi_bridge_msgs/AudioBuffer (stock
naoqi_driver: interleaved int16 `data`, `frequency` 48000, `channelMap`;
ros-naoqi/naoqi_driver src/event/audio.cpp:175-186).

Channel order everywhere (WAV channels, reports) is NAOqi's:
0 rearLeft, 1 rearRight, 2 frontLeft, 3 frontRight. An AudioBuffer is de-interleaved and each
column named by its channelMap code (naoqi_msgs.CHANNEL_NAMES: 3 rear left, 5 rear right,
0 front left, 2 front right; audio.cpp:63-66), then put in that order: a dead microphone is
named right whatever the order of the map, and the WAV is the same either way.

Per message (counted): the four arrays have the same, non-zero length; an AudioBuffer has a
channelMap naming Pepper's four microphones once each, data that splits into them, and
`frequency` equal to `sample_rate`.
Over the window (FAIL at the end):
  * sample rate: the samples per channel the stream carried over the time it covered, must be
    `sample_rate` (48000) within `sample_rate_tolerance` (0.05 = 5 %); needs 3 buffers or more.
    Measured on the buffers' header stamps where the message has them (stock naoqi_driver's
    AudioBuffer: processRemote leaves NAOqi's capture time `altimestamp` unused and stamps
    `ros::Time::now()` when NAOqi hands the driver a buffer, ros-naoqi/naoqi_driver
    src/event/audio.cpp:175-178: as bursty as the network between NAOqi and the driver, but not
    moved by sensorTest's own queue), on receive times where it has none (AudioCustomMsg), by stats.carried_rate: a
    buffer can come late, never early, so the rate is the slope of the line the buffers that
    came on time lie on, whatever bursts and pauses the network or the PC made. A rate outside
    the tolerance by more than the measure's own spread (the two halves of the stream measured
    alone) fails; one outside it by less is not judged: a warning saying the buffers came too
    unevenly to tell, with the spread and the longest pause (NOT JUDGED on a busy PC, and so is
    a rate below it when sensorTest fell BEHIND s or more behind on the topic, or could not
    keep up with it at all: buffers are dropped then; sensors/lag.py);
  * silent channel: a channel whose RMS is below `silence_dbfs` (default -70 dBFS) or whose
    samples are all zero fails, named by its place (e.g. "frontLeft");
  * message rate: no fixed band; NAOqi delivers a buffer when it is full, so the rate follows
    from the sample rate and the buffer size (samples per channel per message, the most
    common one seen): sample_rate / buffer within +-`buffer_rate_tolerance` (0.5 = +-50 %,
    room for NAOqi's irregular delivery; the sample rate itself is checked at 5 %), e.g.
    4096 samples (CSSR bridge) -> 11.7 Hz, 5.9-17.6 Hz accepted. A `rate` band, if given, wins;
  * stuck: `stuck_buffers` identical consecutive buffers (all four channels, every sample):
    a microphone's samples carry noise, so two real buffers never match; a bridge that
    resends its last buffer does;
  * a channel that dies partway: silent (below `silence_dbfs`, or all zero) in every buffer
    from some time to the end of the window, for at least `channel_death_s` seconds and 3
    buffers, fails as "microphone frontLeft went silent from t = 2.1 s";
  * copied channels: channels identical sample for sample in every buffer with sound fail,
    naming which carry whose samples; four nearly identical channels (every pair's difference
    below `similar_channels_ratio` of a channel's own one-sample step: one microphone's samples
    dealt out over four channels) are a warning. The rules and their margin: sensors/channels.py.
Reported: RMS and peak per channel in dBFS (0 dBFS = full scale 32768), clipping share per
channel (|sample| >= 32767; above `max_clipping_share`, default 0.01, a warning), gaps (a pause
between buffers longer than 3 buffer periods; a warning), buffer size.

Recording (unless record is off), in ctx.output_dir:
  * mic_mode 'together' (default): microphoneOutput.wav, 4 channels in the order above,
    sample_rate Hz, PCM_16, written incrementally;
  * mic_mode 'sequential' (the D4.1 behaviour): the window is 4 x duration; each microphone in
    turn (rearLeft, rearRight, frontLeft, frontRight) is recorded for `duration` seconds into
    microphoneOutput_<place>.wav (mono), and microphoneOutput.wav holds the four slots one
    after another (mono), as the original did. A buffer belongs to the slot in which it was
    received.
Files are finished in finish() (the runner calls it at the end of the window, on Ctrl-C and on
errors). With play_audio the recording is then played (playback.py).

LevelMonitor: a separate subscriber used by the speech check to tell whether the robot's
sentence was heard (level rise over the baseline before speaking).
"""
import collections
import dataclasses
import math
import os
import threading
import time
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Tuple

import numpy as np

from ..media.recording import WavWriter
from ..sources.naoqi_msgs import CHANNEL_NAMES, message_class_from_definition
from ..stats import CarriedRate, StampPlacer, carried_rate
from .base import Check, StuckRun, TrailingRun, fmt
from .channels import ChannelSimilarity, copy_reasons, similar_warning
from .lag import starved_hint
from .values import Point
from .values.audio import AudioValues, ChannelLevel, WavFile

if TYPE_CHECKING:
    import subprocess

    import genpy

    from ..plan.expectations import AudioExpect
    from ..plan.settings import SensorPlan
    from .base import RunContext

CHANNELS = ('rearLeft', 'rearRight', 'frontLeft', 'frontRight')
FULL_SCALE = 32768.0
SERIES_MAX = 2000
# s sensorTest fell behind on the microphones' topic from which it counts as evidence that this PC
# starved the audio path: a starved capture or bridge loses buffers from its queues (the emulated
# NAOqi keeps 8 per subscriber) as sensorTest's own queue backs up; beside six busy loops
# sensorTest was 2.4 s behind and 75 of ~130 buffers arrived
BEHIND = 0.5


def dbfs(rms: float) -> float:
    return 20.0 * math.log10(rms / FULL_SCALE) if rms > 0 else float('-inf')


def _db_value(x):
    return None if not math.isfinite(x) else round(x, 2)


class LayoutError(ValueError):
    """An AudioBuffer whose channelMap or data cannot be split into Pepper's four microphones."""


def _channel_map(msg):
    cmap = msg.channelMap
    return list(bytearray(cmap)) if isinstance(cmap, (bytes, bytearray)) else [int(c) for c in cmap]


def channels_of(msg: 'genpy.Message') -> List[np.ndarray]:
    """The four channel arrays of a message as int16 numpy arrays, in NAOqi order.
    AudioCustomMsg: its four fields. AudioBuffer: `data` de-interleaved, columns named by
    `channelMap` (raises LayoutError when that is impossible)."""
    if not hasattr(msg, 'channelMap'):
        return [np.asarray(getattr(msg, name), dtype=np.int16) for name in CHANNELS]
    cmap = _channel_map(msg)
    names = [CHANNEL_NAMES.get(c, 'code %d' % c) for c in cmap]
    if sorted(names) != sorted(CHANNELS):
        raise LayoutError('channelMap %s (%s) is not Pepper\'s four microphones (%s)'
                          % (cmap, ', '.join(names) or 'empty', ', '.join(CHANNELS)))
    data = np.asarray(msg.data, dtype=np.int16)
    if len(data) % len(cmap):
        raise LayoutError('%d samples do not split into %d interleaved channels'
                          % (len(data), len(cmap)))
    frames = data.reshape(-1, len(cmap))
    return [np.ascontiguousarray(frames[:, names.index(name)]) for name in CHANNELS]


class AudioCheck(Check):
    family = 'audio'
    expect: 'AudioExpect'
    queue_size = 200
    # the samples as numpy views of the message's bytes: genpy's deserialize unpacks each of an
    # AudioBuffer's 32768 int16 into a Python int (a tuple numpy then copies back, ~1.5 ms)
    numpy_arrays = True

    def __init__(self, plan: 'SensorPlan', ctx: 'RunContext') -> None:
        super().__init__(plan, ctx)
        self.rate = self.expect.sample_rate
        self.tolerance = self.expect.sample_rate_tolerance
        self.buffer_tolerance = self.expect.buffer_rate_tolerance
        self.silence = self.expect.silence_dbfs
        self.max_clipping = self.expect.max_clipping_share
        self.mode = getattr(ctx.options, 'mic_mode', None) or 'together'
        self.slot = 10.0            # seconds per microphone in sequential mode (window / 4)
        self.recording = getattr(ctx.options, 'record', None) is not False
        self.energy = np.zeros(4)   # sum of squares per channel
        self.peak = np.zeros(4, dtype=np.int64)
        self.clipped = np.zeros(4, dtype=np.int64)
        self.nonzero = np.zeros(4, dtype=np.int64)
        self.samples = 0            # per channel, all buffers
        self.first_len: Optional[int] = None
        self.first_t: Optional[float] = None
        self.last_t: Optional[float] = None
        # (receive time, samples so far) and (header stamp, samples so far) per buffer
        self.carried: List[Tuple[float, float]] = []
        self.stamped: List[Tuple[float, float]] = []
        self.stamps_ok = True       # header stamps never went backwards
        self.prev_t: Optional[float] = None
        self.lengths: collections.Counter = collections.Counter()
        self.gaps: List[Tuple[float, float]] = []   # (t, pause)
        self.writers: Dict[str, WavWriter] = {}
        self.player: Optional[subprocess.Popen] = None   # playing the recording (--play-audio)
        self.level_series: Dict[str, List[Point]] = {name: [] for name in CHANNELS}   # dBFS over time
        self.found: Optional[AudioValues] = None
        self.stuck = StuckRun(self.expect.stuck_buffers)
        self.last_block = None
        self.dying = [TrailingRun() for _ in CHANNELS]
        self.similar = ChannelSimilarity(CHANNELS, self.silence)   # copied channels (channels.py)

    # ---- set-up -------------------------------------------------------------------------
    def window(self, duration: float) -> float:
        self.slot = float(duration)
        return 4 * duration if self.mode == 'sequential' else duration

    def start(self) -> None:
        for stale in self._file_names():
            path = os.path.join(self.ctx.output_dir, stale)
            if os.path.exists(path):
                os.unlink(path)

    def _file_names(self):
        return ['microphoneOutput.wav'] + ['microphoneOutput_%s.wav' % c for c in CHANNELS]

    def _writer(self, name, channels):
        w = self.writers.get(name)
        if w is None:
            w = self.writers[name] = WavWriter(os.path.join(self.ctx.output_dir, name), self.rate, channels)
        return w

    def fields(self, msg: 'genpy.Message') -> List[Tuple[str, Any]]:
        if not hasattr(msg, 'channelMap'):
            return [('Samples per channel', len(msg.rearLeft)),
                    ('Channels', '4 (%s)' % ', '.join(CHANNELS))]
        cmap = _channel_map(msg)
        return [('Message', 'AudioBuffer (interleaved)'), ('Frequency', msg.frequency),
                ('Channel map', '%s (%s)' % (cmap, ', '.join(CHANNEL_NAMES.get(c, '?') for c in cmap))),
                ('Samples per channel', len(msg.data) // max(1, len(cmap)))]

    def rate_band(self) -> Optional[List[float]]:
        band = self.expect.rate
        if band:
            return list(band)
        if self.buffer_tolerance is None or not self.lengths:
            return None
        nominal = self.rate / float(self.lengths.most_common(1)[0][0])
        tol = float(self.buffer_tolerance)
        return [round(nominal * (1 - tol), 2), round(nominal * (1 + tol), 2)]

    def settled(self) -> bool:
        return self.count >= 12

    # ---- per message --------------------------------------------------------------------
    def on_message(self, msg: 'genpy.Message', t: float) -> None:
        try:
            chans = channels_of(msg)
        except LayoutError as e:
            self.failures.add('layout', str(e))
            return
        freq = getattr(msg, 'frequency', None)
        if freq is not None and freq != self.rate:
            self.failures.add('frequency', 'AudioBuffer frequency %d Hz, expected sample_rate %d Hz'
                              % (freq, self.rate))
        lengths = [len(c) for c in chans]
        if len(set(lengths)) != 1:
            self.failures.add('lengths', 'channel arrays of different lengths',
                              ' '.join('%s=%d' % (n, k) for n, k in zip(CHANNELS, lengths)))
            return
        n = lengths[0]
        if n == 0:
            self.failures.add('empty', 'empty audio buffer')
            return
        self.lengths[n] += 1
        if self.first_t is None:
            self.first_t, self.first_len = t, n
        elif self.prev_t is not None and self.rate:
            period = n / float(self.rate)
            if t - self.prev_t > 3 * period:
                self.gaps.append((self.prev_t, t - self.prev_t))
        self.prev_t = self.last_t = t
        self.samples += n
        if len(self.carried) < 20000:
            self.carried.append((t, float(self.samples)))
            self._stamp(msg)
        block = np.stack(chans, axis=1)          # (n, 4) int16
        wide = block.astype(np.int32)
        sq = np.einsum('ij,ij->j', wide, wide, dtype=np.float64)
        self.energy += sq
        absval = np.abs(wide)
        self.peak = np.maximum(self.peak, absval.max(axis=0))
        self.clipped += np.count_nonzero(absval >= 32767, axis=0)
        self.nonzero += np.count_nonzero(block, axis=0)
        if self.stuck.limit:
            last = self.last_block
            same = last is not None and last.shape == block.shape and np.array_equal(last, block)
            self.last_block = block
            self.stuck.repeat(same, t)
        self.similar.add(block, sq)
        for i, run in enumerate(self.dying):
            run.add(sq[i] == 0 or dbfs(math.sqrt(sq[i] / n)) < self.silence, t)
        if len(self.level_series['rearLeft']) < SERIES_MAX:
            for i, name in enumerate(CHANNELS):
                self.level_series[name].append(
                    (round(t, 3), _db_value(dbfs(math.sqrt(sq[i] / n)))))
        if self.recording:
            self._record(block, t)

    def _stamp(self, msg):
        header = getattr(msg, 'header', None)
        stamp = header.stamp.to_sec() if header is not None else 0.0
        if not stamp or not self.stamps_ok:
            return
        if self.stamped and stamp < self.stamped[-1][0]:
            self.stamps_ok = False      # not a clock to measure on (the stream rules fail it)
            return
        self.stamped.append((stamp, float(self.samples)))

    def _record(self, block, t):
        if self.mode == 'sequential':
            slot = int(t // self.slot) if self.slot > 0 else 0
            if slot >= 4:
                return
            mono = np.ascontiguousarray(block[:, slot])
            self._writer('microphoneOutput_%s.wav' % CHANNELS[slot], 1).write(mono)
            self._writer('microphoneOutput.wav', 1).write(mono)
        else:
            self._writer('microphoneOutput.wav', 4).write(block)

    # ---- end ----------------------------------------------------------------------------
    def measured(self) -> Optional[CarriedRate]:
        """Samples per second per channel the stream carried (module docstring), on the header
        stamps when every buffer had one in order, else on the receive times."""
        if self.stamps_ok and self.stamped and len(self.stamped) == len(self.carried):
            return carried_rate(self.stamped)
        return carried_rate(self.carried)

    def measured_rate(self) -> Optional[float]:
        found = self.measured()
        return found.rate if found is not None else None

    def measured_on(self) -> str:
        return 'header stamps' if self.stamps_ok and self.stamped and len(self.stamped) == len(self.carried) \
            else 'receive times'

    def finish(self) -> None:
        for w in self.writers.values():
            w.close()
        recordings = self._report_files()
        series = self.level_series
        found = AudioValues(mic_mode=self.mode, recordings=recordings, level_rear_left=list(series['rearLeft']),
                            level_rear_right=list(series['rearRight']), level_front_left=list(series['frontLeft']),
                            level_front_right=list(series['frontRight']))
        self.found = found
        if not self.samples:
            return
        found_rate = self.measured()
        rate = found_rate.rate if found_rate is not None else None
        band = self.rate_band()
        derived_band = None
        if band and self.buffer_tolerance is not None and not self.expect.rate:
            size = self.lengths.most_common(1)[0][0]
            derived_band = band
            self.notes.append('Message rate band %s-%s Hz from %d Hz / %d samples per buffer '
                              '+- %s%%' % (fmt(band[0], 2), fmt(band[1], 2), self.rate, size,
                                           fmt(100 * float(self.buffer_tolerance), 1)))
        if rate is None or self.count < 3:
            self.fail('too few audio buffers (%d) to measure the sample rate' % self.count)
        else:
            self._judge_rate(rate, found_rate.spread if found_rate is not None else 0.0)
        levels: Dict[str, ChannelLevel] = collections.OrderedDict()
        for i, name in enumerate(CHANNELS):
            rms = math.sqrt(self.energy[i] / self.samples)
            level = ChannelLevel(_db_value(dbfs(rms)), _db_value(dbfs(float(self.peak[i]))),
                                 round(float(self.clipped[i]) / self.samples, 6), bool(self.nonzero[i] == 0))
            levels[name] = level
            if level.all_zero:
                self.fail('microphone %s is silent: all samples are zero' % name)
            elif dbfs(rms) < self.silence:
                self.fail('microphone %s is silent: RMS %s dBFS below silence_dbfs %s'
                          % (name, fmt(dbfs(rms), 1), fmt(self.silence, 1)))
            else:
                self._judge_death(name, i)
            share = level.clipping_share or 0.0
            if share > self.max_clipping:
                self.warn('microphone %s clips in %.2f%% of its samples (max_clipping_share %s%%)'
                          % (name, 100 * share, fmt(100 * self.max_clipping, 2)))
        stuck = self.stuck.finding('buffers', 'stuck_buffers')
        if stuck:
            self.fail('microphone stream stuck: ' + stuck)
        for reason in copy_reasons(self.similar):
            self.fail(reason)
        similar = similar_warning(self.similar, self.expect.similar_channels_ratio)
        if similar:
            self.warn(similar)
        self.notes.append('Levels (RMS / peak dBFS): ' + ', '.join(
            '%s %s / %s' % (n, fmt(v.rms_dbfs, 1), fmt(v.peak_dbfs, 1)) for n, v in levels.items()))
        gaps = None
        if self.gaps:
            longest = max(g for _, g in self.gaps)
            gaps = [[round(a, 3), round(b, 3)] for a, b in self.gaps[:50]]
            self.warn('%d gap%s in the audio stream (pause > 3 buffer periods), longest %.2f s'
                      % (len(self.gaps), '' if len(self.gaps) == 1 else 's', longest))
        self.found = dataclasses.replace(
            found, samples_per_channel=self.samples, buffer_sizes=dict(self.lengths),
            sample_rate_hz=round(rate, 1) if rate else None, sample_rate_expected_hz=self.rate,
            message_rate_band_hz=derived_band, channels=levels, longest_identical_run=self.stuck.longest,
            gaps=gaps, channel_step_ratios=self.similar.ratios())
        self._play()

    def _judge_rate(self, rate: float, spread: float) -> None:
        off = abs(rate - self.rate) / float(self.rate)
        lag = self.own_lag
        span = self.carried[-1][0] - self.carried[0][0] if self.carried else 0.0
        if off > self.tolerance and rate < self.rate and lag is not None and lag.probe is not None and \
                (lag.longest >= BEHIND or lag.saturated(span)):
            # fewer samples than the rate makes, on a PC too busy to take them all: the bridge's
            # publisher and sensorTest's queue drop buffers there (a wrong rate may hide: not judged)
            self.not_judged('PC busy: sample rate %.0f Hz is below %d Hz +- %s%%, but this PC was too busy to '
                            'take every buffer (%s): buffers are lost on it; test again when it is quieter'
                            % (rate, self.rate, fmt(100 * self.tolerance, 1), lag.describe()))
            return
        if off - spread > self.tolerance:
            # below it on a busy PC: the audio bridge, when it runs here, may have been starved
            self.fail('sample rate %.0f Hz, expected %d Hz +- %s%%%s'
                      % (rate, self.rate, fmt(100 * self.tolerance, 1),
                         starved_hint(lag) if rate < self.rate else ''))
        elif off > self.tolerance:
            longest = max((g for _, g in self.gaps), default=0.0)
            lag = self.own_lag
            if lag is not None and lag.busy:
                self.not_judged('PC busy: sample rate %.0f Hz is outside %d Hz +- %s%%, but the buffers came '
                                'too unevenly to tell (the two halves of the stream differ by %s%%) while this '
                                'PC was busy (%s); test again when it is quieter'
                                % (rate, self.rate, fmt(100 * self.tolerance, 1), fmt(100 * spread, 1),
                                   lag.describe()))
                return
            self.warn('sample rate not judged: %.0f Hz is outside %d Hz +- %s%%, but the buffers came '
                      'too unevenly to tell (the two halves of the stream differ by %s%%; longest pause '
                      '%.2f s): test again when the PC and the network are quieter'
                      % (rate, self.rate, fmt(100 * self.tolerance, 1), fmt(100 * spread, 1), longest))
        else:
            self.notes.append('Sample rate %.0f Hz (expected %d; on %s)' % (rate, self.rate, self.measured_on()))

    def _judge_death(self, name, i):
        """A channel alive at first and silent from some time to the end of the window."""
        limit = self.expect.channel_death_s
        since = self.dying[i].since()
        if limit is None or since is None or since[1] < 3 or since[2] < limit:
            return
        self.fail('microphone %s went silent from t = %s s to the end of the window (%d buffers, '
                  '%s s below silence_dbfs %s)' % (name, fmt(since[0], 2), since[1], fmt(since[2], 1),
                                                   fmt(self.silence, 1)))

    def _report_files(self) -> Optional[Dict[str, WavFile]]:
        """The WAV files written (file name -> what it holds; None: none), as artifacts and a note."""
        files: Dict[str, WavFile] = collections.OrderedDict()
        for name, w in self.writers.items():
            if w.error:
                self.warn(w.error)
            elif w.written:
                files[name] = WavFile(w.channels, w.samplerate, w.subtype, round(w.seconds, 3))
        if files:
            self.artifacts['audio'] = 'microphoneOutput.wav' if 'microphoneOutput.wav' in files else next(iter(files))
            for c in CHANNELS:
                key = 'microphoneOutput_%s.wav' % c
                if key in files:
                    self.artifacts['audio_' + c] = key
            self.notes.append('audio: ' + ', '.join('%s (%d ch, %s s)' % (n, f.channels, fmt(f.seconds, 1))
                                                    for n, f in files.items()))
            return files
        if not self.recording:
            self.notes.append('recording off')
        return None

    def _play(self):
        if not getattr(self.ctx.options, 'play_audio', None):
            return
        main = self.writers.get('microphoneOutput.wav')
        if main is None or not main.written:
            return
        from ..media.playback import play_channels
        self.player, line = play_channels(main.path, CHANNELS if main.channels == 4 else None,
                                          delete_after=bool(getattr(self.ctx.options, 'delete_file', None)))
        self.notes.append(line)


class LevelMonitor:
    """Microphone level history for the speech check.

    `start()` subscribes to the microphone topic (its own subscriber, AudioCustomMsg or AudioBuffer, any package
    name), and keeps the last `history` seconds of per-buffer levels (RMS over the four
    channels, dBFS) with their time.monotonic() receive times. `heard(t0, t1)` compares the
    loudest buffer in [t0, t1] with the room's floor in the `baseline` seconds before t0: a rise
    of `rise_db` (default 6 dB) or more counts as heard.

    The floor is the FLOOR_SHARE quantile of those levels, not their median: in a guided run the
    guide's prompts ("Touch the front of my head") go out through the same loudspeaker while the
    baseline is taken, and a prompt filling half of it raised the median by 4-7 dB (the speech
    check then measured 5.8-6.5 dB for a sentence that rose 11-13 dB above the quiet room). The
    gaps between words and prompts still show the floor in the quieter fifth of the buffers.
    `has_baseline` wants MIN_BASELINE s of levels, so that there are such gaps to find.

    Each level is placed at its buffer's header stamp where it has one (stats.StampPlacer:
    naoqi_driver's AudioBuffer, stamped when NAOqi hands the driver a buffer, event/audio.cpp:
    175-178), not where sensorTest handled it: a sentence whose buffers waited in a busy PC's
    queue and came after the listening window was "not heard" (issue 41). AudioCustomMsg has no
    header: its levels are placed on arrival. `covered(t)` says whether the stream has reached t
    (the speech check waits for it), `longest_pause(a, b)` how long it said nothing in [a, b].
    """

    FLOOR_SHARE = 0.2
    # s of levels before the sentence may go out: 9 of NAOqi's 8192-sample buffers at 48 kHz
    # (naoqi_driver's stock AudioBuffer), 18 of the bridge's 4096
    MIN_BASELINE = 1.5

    def __init__(self, topic: str, history: float = 120.0, baseline: float = 3.0, rise_db: float = 6.0) -> None:
        self.topic = topic
        self.history = float(history)
        self.baseline = float(baseline)
        self.rise_db = float(rise_db)
        self._levels: collections.deque = collections.deque()
        self._lock = threading.Lock()
        self._sub: Any = None   # the subscription while started (rosapi.any_subscriber)
        self.placer = StampPlacer()

    def start(self) -> 'LevelMonitor':
        from .. import rosapi
        self._sub = rosapi.any_subscriber(self.topic, self._callback, queue_size=50)
        return self

    def stop(self) -> None:
        if self._sub is not None:
            self._sub.unregister()
            self._sub = None

    def _callback(self, type_name: str, buff: bytes, conn: Dict[str, Any]) -> None:
        try:   # AudioCustomMsg or AudioBuffer, built from the definition the connection carries
            msg = message_class_from_definition(type_name, conn['message_definition'])().deserialize(buff)
            chans = channels_of(msg)
        except Exception:   # another type or a broken buffer: not a level
            return
        header = getattr(msg, 'header', None)
        stamp = header.stamp.to_sec() if header is not None else 0.0
        with self._lock:
            t = self.placer.place(time.monotonic(), time.time() - stamp if stamp > 0 else None)
        self.add(chans, t)

    def add(self, chans: List[np.ndarray], now: float) -> None:
        """One buffer (list of channel arrays) received at monotonic time `now`."""
        total, n = 0.0, 0
        for c in chans:
            if len(c):
                w = c.astype(np.int64)          # exact; no BLAS call (its threads wake per buffer)
                total += float(np.einsum('i,i->', w, w))
                n += len(c)
        if not n:
            return
        level = dbfs(math.sqrt(total / n))
        with self._lock:
            self._levels.append((now, level))
            while self._levels and self._levels[0][0] < now - self.history:
                self._levels.popleft()

    def _window(self, a, b):
        """(time, level) of the buffers received in [a, b]."""
        with self._lock:
            return [(t, lv) for t, lv in self._levels if a <= t <= b]

    def _between(self, a, b):
        return [lv for _, lv in self._window(a, b)]

    def covered(self, t: float) -> bool:
        """The stream has a level placed at `t` or later."""
        with self._lock:
            return bool(self._levels) and self._levels[-1][0] >= t

    def longest_pause(self, a: float, b: float) -> float:
        """The longest stretch of [a, b] with no level placed in it (s)."""
        times = [a] + [t for t, _ in self._window(a, b)] + [b]
        return max(y - x for x, y in zip(times, times[1:]))

    def has_baseline(self, now: Optional[float] = None) -> bool:
        """At least 5 levels, the oldest MIN_BASELINE s or more before `now`."""
        now = time.monotonic() if now is None else now
        levels = self._window(now - self.baseline, now)
        return len(levels) >= 5 and now - levels[0][0] >= self.MIN_BASELINE

    def heard(self, t0: float, t1: float) -> Dict[str, Any]:
        before = self._between(t0 - self.baseline, t0)
        during = self._between(t0, t1)
        if not during:
            return {'heard': False, 'rise_db': None, 'why': 'no microphone data while speaking'}
        if not before:
            return {'heard': False, 'rise_db': None, 'why': 'no microphone data before speaking'}
        base = float(sorted(before)[int(self.FLOOR_SHARE * (len(before) - 1))])   # -inf too
        loud = max(during)
        if not math.isfinite(loud):
            return {'heard': False, 'rise_db': None, 'why': 'microphones silent while speaking'}
        rise = loud - base if math.isfinite(base) else float('inf')
        rise_value = round(rise, 1) if math.isfinite(rise) else 99.0
        if rise >= self.rise_db:
            return {'heard': True, 'rise_db': rise_value, 'why': 'level rose %.1f dB' % rise_value}
        return {'heard': False, 'rise_db': rise_value,
                'why': 'level rose only %.1f dB (needs %.0f dB)' % (rise_value, self.rise_db)}
