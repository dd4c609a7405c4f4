"""Does a buffer's data look like the layout its frame declares (planar or interleaved)?

Publisher side only (numpy). A mislabelled buffer would be published with every field mixing
all four microphones, so the publisher checks each frame and refuses mismatches.

The rule. Read the buffer as one flat run of int16 samples z, as NAOqi sent it, with C channels,
and compare the mean absolute step between neighbours, D1 = mean|z[i+1] - z[i]|, with the step
over C samples, DC = mean|z[i+C] - z[i]|; q = DC / D1.

- Interleaved data: z[i] and z[i+C] are one microphone at consecutive sampling instants, z[i]
  and z[i+1] two different microphones. Real microphones differ by far more than one sampling
  step (gain and offset tolerances, their own noise, the sound's different arrival times), so
  q <= about 1; q = 1 for pure noise.
- Planar data: z is four continuous signals one after the other, so z[i+1] is the next instant
  of the same microphone and z[i+C] C instants later. Sound is dominated by frequencies far
  below the 48 kHz sampling rate, so the step over C samples is up to C times the step over
  one: q between 1 (noise) and C (a pure low tone: a 500 Hz tone gives 3.99 with C = 4).

A frame declared interleaved is suspect when q > ``PLANAR_Q``; declared planar, when
q < ``INTERLEAVED_Q``. Buffers with almost no signal (D1 or DC under ``MIN_STEP`` LSB: silence,
a dead microphone array) decide nothing. ``CONFIRM`` suspect frames in a row prove the stream
mislabelled: from then on every frame of that stream id is refused. Suspect frames are refused
too, one by one. What this rule has been checked against, and what still needs a robot, is in
docs/audio-bridge.md ("Layout").
"""
from typing import Dict, Optional, Set, Tuple

import numpy as np

from .frame import Frame

PLANAR_Q = 2.0
INTERLEAVED_Q = 0.5
MIN_STEP = 4.0
CONFIRM = 3


def step_ratio(payload: bytes, channels: int) -> Tuple[Optional[float], float, float]:
    """(q, D1, DC) of the raw int16 LE payload, see the module doc."""
    z = np.frombuffer(payload, dtype='<i2').astype(np.int32)
    if channels < 2 or len(z) <= 2 * channels:
        return None, 0.0, 0.0
    d1 = float(np.mean(np.abs(np.diff(z))))
    dc = float(np.mean(np.abs(z[channels:] - z[:-channels])))
    return (dc / d1 if d1 > 0 else None), d1, dc


def suspect(planar: bool, payload: bytes, channels: int) -> Optional[str]:
    """A reason string when the data contradicts the declared layout, else None."""
    q, d1, dc = step_ratio(payload, channels)
    if q is None or d1 < MIN_STEP or dc < MIN_STEP:
        return None
    if not planar and q > PLANAR_Q:
        return ('declared interleaved but looks planar (step ratio %.2f > %.1f: each run of '
                'samples is one continuous microphone signal)' % (q, PLANAR_Q))
    if planar and q < INTERLEAVED_Q:
        return ('declared planar but looks interleaved (step ratio %.2f < %.1f: neighbouring '
                'samples belong to different microphones)' % (q, INTERLEAVED_Q))
    return None


class LayoutGuard(object):
    """Per stream id: refuses suspect frames, and every frame once CONFIRM in a row were."""

    FIX = ('channels would be mixed, so it is not published. Fix: check which layout NAOqi '
           'really sends (naoqiAudio asks for interleaved, as naoqi_driver does; --planar asks '
           'for deinterleaved) and report it: docs/audio-bridge.md, "Layout"')

    def __init__(self) -> None:
        self.mismatched: Set[int] = set()
        self._run: Dict[int, int] = {}

    def check(self, frame: Frame) -> Optional[Tuple[str, str]]:
        """None when the frame may be published, else (kind, why not); kind is 'refused'
        (stream already proven mislabelled), 'confirmed' (this frame proved it) or
        'suspect planar' / 'suspect interleaved' (what the data looks like)."""
        sid = frame.stream_id
        if sid in self.mismatched:
            return 'refused', 'stream %08x is mislabelled (declared %s); %s' % (
                sid, 'planar' if frame.planar else 'interleaved', self.FIX)
        reason = suspect(frame.planar, frame.payload, frame.channels)
        if reason is None:
            self._run[sid] = 0
            return None
        self._run[sid] = self._run.get(sid, 0) + 1
        if self._run[sid] >= CONFIRM:
            self.mismatched.add(sid)
            return 'confirmed', 'stream %08x refused from now on: %s in %d frames in a row; %s' % (
                sid, reason, CONFIRM, self.FIX)
        return ('suspect interleaved' if frame.planar else 'suspect planar'), '%s; %s' % (
            reason, self.FIX)
