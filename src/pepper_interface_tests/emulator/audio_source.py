"""Synthetic 4-microphone Pepper audio: the sound the emulated robot "hears".

``AudioSource(rate=48000, channels=4, pattern='tones', silent_channels=(), seed=0)`` produces a
continuous int16 stream, read block by block with ``read(n)`` -> ndarray (n, channels). Channel
order is Pepper's: rearLeft, rearRight, frontLeft, frontRight.

Patterns
  ``tones``    one sine per channel (``CHANNEL_TONES_HZ``) at about -30 dBFS plus noise at about
               -70 dBFS, so a channel is identified by its dominant frequency.
  ``counter``  a deterministic, sample-exact pattern for bit-exact transport tests. Sample k
               (index since the start) of channel c is
               ``(k * S[c] + c * 10007) % P[c] - 32768`` with ``S = COUNTER_STEPS`` (7, 11, 13,
               17: a swapped channel shows at once) and ``P = COUNTER_PERIODS``, four distinct
               primes just below 65536. Because the periods differ, the start index of any
               received block is recovered uniquely (Chinese remainder theorem) by
               ``find_counter_start``; ``expected_counter`` gives the block that must follow.

``say(text)`` renders text with ``espeak-ng --stdout`` in a background thread (or, when espeak-ng
is missing, three 1 kHz beeps), resamples it to ``rate`` and mixes it into every non-silent
channel at about -10 dBFS peak from the next ``read`` on. ``silent_channels`` (by name) are always
all-zero, speech included (a dead microphone).
"""
import io
import shutil
import subprocess
import threading
import wave
from typing import List, Optional, Sequence, Tuple, Union

import numpy as np

CHANNEL_NAMES = ('rearLeft', 'rearRight', 'frontLeft', 'frontRight')
CHANNEL_TONES_HZ = {'rearLeft': 500.0, 'rearRight': 700.0, 'frontLeft': 900.0,
                    'frontRight': 1100.0}
EXTRA_TONES_HZ = (1300.0, 1500.0, 1700.0, 1900.0)  # for channels beyond the fourth
TONE_DBFS = -30.0
NOISE_DBFS = -70.0
SPEECH_PEAK_DBFS = -10.0
COUNTER_PERIODS = (65521, 65519, 65497, 65479)
COUNTER_STEPS = (7, 11, 13, 17)
COUNTER_CHANNEL_OFFSET = 10007
BEEP_HZ = 1000.0
ESPEAK = 'espeak-ng'
FULL_SCALE = 32767.0


def _dbfs(db: float) -> float:
    return FULL_SCALE * 10.0 ** (db / 20.0)


def expected_counter(start_index: int, n: int, channels: int = 4) -> np.ndarray:
    """The ``counter`` pattern for samples start_index .. start_index+n-1: int16 (n, channels)."""
    out = np.empty((int(n), channels), dtype=np.int16)
    steps = np.arange(int(n), dtype=np.int64)
    for c in range(channels):
        p, step = COUNTER_PERIODS[c % 4], COUNTER_STEPS[c % 4]
        first = (int(start_index) % p) * step + c * COUNTER_CHANNEL_OFFSET
        out[:, c] = (first + steps * step) % p - 32768
    return out


def find_counter_start(block: np.ndarray, channel_index: Optional[int] = None) -> int:
    """Global sample index of the first row of a received ``counter`` block.

    ``block`` is (n, channels) int16, or a 1-D single channel together with its
    ``channel_index``. All-zero channels (silent) are ignored. Raises ValueError when the block is
    not an exact run of the pattern.
    """
    block = np.asarray(block)
    if block.ndim == 1:
        if channel_index is None:
            raise ValueError('a 1-D block needs channel_index')
        columns = {channel_index: block}
    else:
        columns = {c: block[:, c] for c in range(block.shape[1])}
    residues = []
    for c, col in columns.items():
        if len(col) == 0 or not col.any():
            continue
        p = COUNTER_PERIODS[c % 4]
        v = (int(col[0]) + 32768 - c * COUNTER_CHANNEL_OFFSET) % p
        residues.append((v * pow(COUNTER_STEPS[c % 4], -1, p) % p, p))
    if not residues:
        raise ValueError('no non-zero channel to locate the block')
    start, modulus = 0, 1
    for r, p in residues:  # Chinese remainder theorem, incremental
        t = ((r - start) * pow(modulus, -1, p)) % p
        start, modulus = start + modulus * t, modulus * p
    for c, col in columns.items():
        if col.any() and not np.array_equal(col, expected_counter(start, len(col), c + 1)[:, c]):
            raise ValueError('channel %d is not an exact counter run from index %d' % (c, start))
    return start


def _parse_wav(data: bytes) -> Tuple[np.ndarray, int]:
    """(samples float64 in -1..1, rate) from espeak-ng's streamed WAV (its sizes are bogus)."""
    with wave.open(io.BytesIO(data)) as w:
        rate, width, nch = w.getframerate(), w.getsampwidth(), w.getnchannels()
        frames = w.readframes(w.getnframes())
    if width != 2:
        raise ValueError('expected 16-bit WAV from espeak-ng, got %d-byte samples' % width)
    x = np.frombuffer(frames[:len(frames) // (2 * nch) * 2 * nch], dtype='<i2')
    return x.reshape(-1, nch).mean(axis=1) / 32768.0, rate


def _beeps(rate: int) -> np.ndarray:
    """Three 150 ms beeps at 1 kHz, 100 ms apart: the stand-in when espeak-ng is missing."""
    t = np.arange(int(0.15 * rate)) / float(rate)
    beep = np.sin(2 * np.pi * BEEP_HZ * t)
    gap = np.zeros(int(0.10 * rate))
    return np.concatenate([beep, gap, beep, gap, beep])


def render_speech(text: str, rate: int) -> np.ndarray:
    """Text -> mono float64 audio at ``rate``, peak 1.0 (espeak-ng, or beeps without it)."""
    exe = shutil.which(ESPEAK)
    audio = None
    if exe:
        try:
            out = subprocess.run([exe, '--stdout', text], stdout=subprocess.PIPE,
                                 stderr=subprocess.DEVNULL, timeout=30, check=True).stdout
            audio, src_rate = _parse_wav(out)
            if src_rate != rate and len(audio):
                n_out = int(round(len(audio) * rate / float(src_rate)))
                audio = np.interp(np.arange(n_out) * (src_rate / float(rate)),
                                  np.arange(len(audio)), audio)
        except (OSError, subprocess.SubprocessError, ValueError, EOFError, wave.Error):
            audio = None
    if audio is None or not len(audio) or not np.abs(audio).max():
        audio = _beeps(rate)
    return audio / np.abs(audio).max()


class AudioSource:
    """Continuous synthetic microphone stream; thread-safe ``read`` and ``say``."""

    def __init__(self, rate: int = 48000, channels: int = 4, pattern: str = 'tones',
                 silent_channels: Union[str, Sequence[str]] = (), seed: int = 0) -> None:
        if pattern not in ('tones', 'counter'):
            raise ValueError("pattern must be 'tones' or 'counter', not %r" % (pattern,))
        if isinstance(silent_channels, str):
            silent_channels = (silent_channels,)
        names = list(CHANNEL_NAMES[:channels]) + ['ch%d' % i for i in range(4, channels)]
        unknown = [s for s in silent_channels if s not in names]
        if unknown:
            raise ValueError('unknown channel name(s) %s; known: %s'
                             % (', '.join(unknown), ', '.join(names)))
        self.rate, self.channels, self.pattern = int(rate), int(channels), pattern
        self.channel_names = tuple(names)
        self.silent = np.array([n in silent_channels for n in names])
        self._rng = np.random.default_rng(seed)
        self._phase0 = self._rng.uniform(0, 2 * np.pi, channels)
        tones = [CHANNEL_TONES_HZ.get(n) or EXTRA_TONES_HZ[(i - 4) % 4] for i, n in
                 enumerate(names)]
        self._tones = np.array(tones)
        self._index = 0
        self._speech: List[np.ndarray] = []  # queue of float arrays (already scaled), consumed in order
        self._speech_pos = 0
        self._rendering = 0
        self._lock = threading.Lock()

    @property
    def index(self) -> int:
        """Global index of the next sample ``read`` will return."""
        return self._index

    @property
    def speaking(self) -> bool:
        """True while speech is queued or being mixed into the stream."""
        with self._lock:
            return bool(self._speech) or self._rendering > 0

    def say(self, text: str) -> None:
        """Queue ``text`` to be mixed into the stream; returns at once."""
        with self._lock:
            self._rendering += 1
        threading.Thread(target=self._render, args=(text,), name='say', daemon=True).start()

    def _render(self, text: str) -> None:
        try:
            audio = render_speech(text, self.rate) * _dbfs(SPEECH_PEAK_DBFS)
        finally:
            with self._lock:
                self._rendering -= 1
        with self._lock:
            self._speech.append(audio)

    def read(self, n: int) -> np.ndarray:
        """The next ``n`` samples of the stream: int16 ndarray (n, channels)."""
        n = int(n)
        with self._lock:
            start = self._index
            self._index += n
            speech = self._take_speech(n)
        if self.pattern == 'counter':
            out = expected_counter(start, n, self.channels).astype(np.float64)
        else:
            k = np.arange(start, start + n, dtype=np.float64)[:, None]
            out = _dbfs(TONE_DBFS) * np.sin(2 * np.pi * self._tones[None, :] * k / self.rate
                                             + self._phase0[None, :])
            with self._lock:
                noise = self._rng.standard_normal((n, self.channels))
            out += _dbfs(NOISE_DBFS) * noise
        if speech is not None:
            out += speech[:, None]
        out[:, self.silent] = 0
        return np.clip(np.rint(out), -32768, 32767).astype(np.int16)

    def _take_speech(self, n: int) -> Optional[np.ndarray]:
        """Next n samples of queued speech (float), or None when nothing is queued. Lock held."""
        if not self._speech:
            return None
        mix = np.zeros(n)
        filled = 0
        while filled < n and self._speech:
            cur = self._speech[0]
            take = min(n - filled, len(cur) - self._speech_pos)
            mix[filled:filled + take] = cur[self._speech_pos:self._speech_pos + take]
            filled += take
            self._speech_pos += take
            if self._speech_pos >= len(cur):
                self._speech.pop(0)
                self._speech_pos = 0
        return mix
