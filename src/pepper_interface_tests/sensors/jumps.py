"""Jumps in a stream of positions (odometry poses, joint angles), judged on every reading.

A speed computed only from two readings at least a baseline apart, the anchor then moved to
the second, never looks at the readings in between: a value that leaps away for one message
and comes straight back between two anchors is invisible (aliasing). `JumpWatch` instead
compares each reading with every accepted reading of the last `baseline` seconds and with the
last accepted one older than that:

  * two readings less than `baseline` apart may differ by at most `max_rate` x `baseline`:
    the baseline still absorbs stamp jitter (a short dt does not inflate a speed) and small
    motions on top of the real one (a torso swaying on the base);
  * readings further apart may imply at most `max_rate`.

A reading that breaks either is a jump: it is counted and kept out of the references, so one
spike is one jump (its return is judged against the readings before it) and a real jump that
stays (a relocalised pose) ends once no accepted reading is left within `baseline`: the
readings after it start afresh. A run of consecutive jumping readings counts as one jump.
"""
import math
from collections import deque
from typing import Deque, Optional, Sequence, Tuple

MAX_REFS = 128     # 0.5 s at 250 Hz: more than any stream of Pepper's needs


class JumpWatch:
    __slots__ = ('max_rate', 'baseline', 'refs', 'jumps', 'in_jump', 'largest', 'largest_t',
                 'largest_dt')

    def __init__(self, max_rate: float, baseline: float) -> None:
        self.max_rate, self.baseline = max_rate, baseline
        # (when, value) of the accepted readings; bounded, so that stamps that stop moving (a
        # fault of their own, said by the stream statistics) cannot make it grow without end
        self.refs: Deque[Tuple[float, Tuple[float, ...]]] = deque(maxlen=MAX_REFS)
        self.jumps = 0                  # runs of consecutive jumping readings
        self.in_jump = False
        self.largest = 0.0              # the largest jump: a jumping reading's distance from the
        self.largest_t: Optional[float] = None      # last accepted reading, its time in the
        self.largest_dt = 0.0           # window (s) and the time between the two (s)

    def add(self, when: float, value: Sequence[float], t: float) -> bool:
        """One reading at `when` (stamp or receive time, s) and `t` (s in the window) -> True
        when accepted, False when it jumped."""
        value = tuple(value)
        worst: Optional[Tuple[float, float]] = None      # (distance, dt) of the worst excess
        excess = 0.0
        rate, baseline = self.max_rate, self.baseline
        for rw, rv in self.refs:
            dt = abs(when - rw)
            d = math.dist(value, rv)      # hypot of the differences, in C (Python 3.8)
            over = d - rate * (dt if dt > baseline else baseline)
            if over > excess:
                excess, worst = over, (d, dt)
        if worst is not None:
            if not self.in_jump:        # a jump's size: its first reading from the last accepted
                self.jumps += 1
                self.in_jump = True
                last_when, last = self.refs[-1]
                size = math.dist(value, last)
                if size > self.largest:
                    self.largest, self.largest_t, self.largest_dt = size, t, abs(when - last_when)
            if all(abs(when - rw) > self.baseline for rw, _ in self.refs):
                self.refs.clear()           # nothing accepted is left close by: start afresh
                self.refs.append((when, value))
            return False
        self.in_jump = False
        self.refs.append((when, value))
        # keep the readings of the last baseline and the last one older than that
        while len(self.refs) >= 2 and when - self.refs[1][0] >= self.baseline:
            self.refs.popleft()
        return True
