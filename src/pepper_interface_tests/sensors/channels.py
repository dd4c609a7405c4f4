"""Do the four microphone channels carry four microphones? Copied and near-identical channels.

Pepper's four microphones sit at four places on the head: each carries its own self-noise and
hears a sound at its own time and gain, so two channels never carry the same samples. Two
broken-bridge shapes make them do so (emulator faults microphone:copied_channels and
microphone:planar_as_interleaved, docs/emulator.md):

* Copied: one microphone's buffer written into several channels (a bridge that fills every
  channel from one buffer). Channels identical sample for sample in every buffer of the window
  that carries sound (see Silence) FAIL, naming which channels carry which one's samples: the
  copies were never measured. One real buffer clears a pair (a copy only part of the time is
  left to the other rules).
* Dealt out: one microphone's consecutive samples dealt over the four channels, channel c
  getting samples c, c+4, c+8 ... of it (a planar NAOqi buffer read as interleaved: the four
  "channels" of the first quarter of each buffer are all rearLeft, of the next quarter all
  rearRight, ...). The channels are then nearly identical: any two differ by a step of 1 to 3
  samples of one signal, less than each channel's own step from one of its samples to the next
  (4 samples of that signal). So, per pair of channels a, b over the window,

      ratio(a, b) = mean (a[n] - b[n])^2 / mean of the two channels' (x[n+1] - x[n])^2.

  Dealt-out samples give (k / 4)^2 for a step of k samples of a smooth sound (well below the
  sampling rate) and k / 4 for rougher sound (noise low-passed to a few kHz), so every pair is at
  most 0.56-0.75 (k = 3); white noise gives 1 (undetectable, and then harmless). Real
  microphones: one pair may come close to 0 when a sound reaches both at the same instant with
  matched gains, but not all six pairs of four microphones at four places: a sound arrives at
  them at different times (tens of samples at 48 kHz), with their gain tolerances, the room's
  reverberation and each microphone's own noise (independent noise alone gives 1 / (1 - rho1)
  >= 1, rho1 the noise's correlation between neighbouring samples). Measured on the emulator's
  audio and on robot-shaped recordings (one sound heard at four places on the head with their
  delays, +-0.5 dB gains and their own noise; test/sensors/test_channels.py): the largest pair of
  healthy audio 46-297 (speech from every side 46-77, a 100 Hz hum 93-168, the emulator's tones
  and speech 40-297), 1.00 for a quiet room's independent noise; of dealt-out samples 0.56-0.75
  (the emulator's tones 0.56, its speech 0.59, noise low-passed to a few kHz 0.75).
  When every pair of the four channels is below `similar_channels_ratio` (0.8: above the
  0.56-0.75 of dealt-out samples, below the 1 of a quiet room), the stream is a WARNING naming
  the likely cause, not a failure: a sound reaching all four microphones at once with matched
  gains, dominating their noise and the room's reverberation, could in principle do the same.
  The same step-ratio reasoning is the audio bridge's layout check (audio_bridge/layout.py),
  which refuses such frames at the bridge.

Silence: a buffer in which both channels of a pair are below `silence_dbfs` (a quiet room, or
digital silence: all zero, equal by being zero) is no evidence of a copy and is not judged for
that pair; a pair with no judged buffer is not judged at all (the silence rules of
sensors/audio.py speak for such channels). A quiet room's real microphones carry their own
noise: ratio >= 1, so a dark quiet room PASSES. Channels with no step at all (constant) give no
ratio.
"""
import math
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

FULL_SCALE = 32768.0
PAIRS = [(i, j) for i in range(4) for j in range(i + 1, 4)]


class ChannelSimilarity:
    """Per buffer (`add`), the six pairs of four channels: identical buffers, difference energy,
    and each channel's one-sample step energy; `copies()` and `ratios()` at the end."""

    def __init__(self, names: Sequence[str], silence_dbfs: float) -> None:
        self.names = list(names)
        self.quiet_sq = (FULL_SCALE * 10.0 ** (silence_dbfs / 20.0)) ** 2    # mean square
        self.judged = np.zeros(len(PAIRS), dtype=np.int64)      # buffers judged per pair
        self.same = np.zeros(len(PAIRS), dtype=np.int64)        # of them, identical
        self.cross = np.zeros(len(PAIRS))                       # sum (a - b)^2
        self.step = np.zeros(len(self.names))                   # sum (x[n+1] - x[n])^2
        self.samples = 0
        self.steps = 0

    def add(self, block: np.ndarray, energy: np.ndarray) -> None:
        """One buffer: `block` (n, 4) int16, `energy` its per-channel sum of squares."""
        n = block.shape[0]
        if n < 2:
            return
        wide = block.astype(np.int64)
        d = np.diff(wide, axis=0)
        self.step += np.einsum('ij,ij->j', d, d).astype(np.float64)
        self.samples += n
        self.steps += n - 1
        quiet = energy / n < self.quiet_sq
        for k, (i, j) in enumerate(PAIRS):
            diff = wide[:, i] - wide[:, j]
            cross = int(np.dot(diff, diff))
            self.cross[k] += cross
            if quiet[i] and quiet[j]:
                continue
            self.judged[k] += 1
            if cross == 0:
                self.same[k] += 1

    def copies(self) -> List[Tuple[str, List[str], int]]:
        """Groups of channels identical sample for sample in every judged buffer: (the first
        channel of the group, the channels that carry its samples, judged buffers)."""
        parent = list(range(len(self.names)))

        def root(i: int) -> int:
            while parent[i] != i:
                i = parent[i]
            return i
        copied = [k for k, _ in enumerate(PAIRS) if self.judged[k] and self.same[k] == self.judged[k]]
        for k in copied:
            a, b = root(PAIRS[k][0]), root(PAIRS[k][1])
            parent[max(a, b)] = min(a, b)
        groups: Dict[int, List[str]] = {}
        for i in range(len(self.names)):
            if root(i) != i:
                groups.setdefault(root(i), []).append(self.names[i])
        return [(self.names[r], members,
                 max(int(self.judged[k]) for k in copied if root(PAIRS[k][0]) == r))
                for r, members in sorted(groups.items())]

    def ratios(self) -> Dict[str, Optional[float]]:
        """'rearLeft-rearRight' -> ratio (module doc); None where the channels have no step."""
        out: Dict[str, Optional[float]] = {}
        for k, (i, j) in enumerate(PAIRS):
            own = (self.step[i] + self.step[j]) / 2.0 / max(1, self.steps)
            value = self.cross[k] / max(1, self.samples) / own if own > 0 else None
            out['%s-%s' % (self.names[i], self.names[j])] = (
                round(value, 4) if value is not None and math.isfinite(value) else None)
        return out


def copy_reasons(sim: ChannelSimilarity) -> List[str]:
    """FAIL reasons: one per group of copied channels."""
    out = []
    for first, copies, buffers in sim.copies():
        out.append('%s %s %s\'s samples, sample for sample, in all %d buffers with sound: one '
                   'microphone copied into %s, which %s never measured (a bridge or driver filling '
                   'several channels from one buffer)'
                   % (_and(copies), 'carry' if len(copies) > 1 else 'carries', first, buffers,
                      'the others' if len(copies) > 1 else 'another channel',
                      'were' if len(copies) > 1 else 'was'))
    return out


def similar_warning(sim: ChannelSimilarity, limit: Optional[float]) -> Optional[str]:
    """The WARNING of four nearly identical channels, or None (module doc)."""
    if limit is None or sim.copies():
        return None
    ratios = sim.ratios()
    values = [v for v in ratios.values() if v is not None]
    if len(values) < len(PAIRS) or max(values) >= limit:
        return None
    return ('the four channels are nearly identical, as when planar NAOqi buffers are read as '
            'interleaved by the bridge or driver (one microphone\'s consecutive samples dealt out '
            'over the four channels): any two differ by at most %.2f of a channel\'s own step '
            'from one sample to the next (similar_channels_ratio %s; two real microphones differ '
            'by more: their own noise, gains and the sound\'s arrival times)'
            % (max(values), _num(limit)))


def _and(names: List[str]) -> str:
    return names[0] if len(names) == 1 else '%s and %s' % (', '.join(names[:-1]), names[-1])


def _num(v: float) -> str:
    return ('%.4f' % v).rstrip('0').rstrip('.')
