"""Whether this PC was too busy for the motion check, in words that name it (issue 41).

The motion check's sequence (motion/sequence.py) decides from what the witnesses said within
its own clock: a part is SKIPPED when a witness said nothing in `witness_wait` ("no HeadYaw in
the joint states", "no laser scan and no sonar reading arrived"), when no witness could tell
whether it moved, or when the check's window ended before the steps did. A PC too busy to hand sensorTest the
witnesses' messages in time causes each of these as a silent robot would; such a row then says
that the PC was busy, with the load average, how long sensorTest itself did not run (the
process's stall probe, sensors/lag.py) and how late the witnesses' messages were handled
behind their stamps (motion/witnesses.py STAMPED), so nobody looks for the fault on the robot.

Busy: the load average above the cores (sensors/lag.py BUSY_LOAD_PER_CORE), or sensorTest
stalled, or its witnesses' messages handled late, for `settle_time` s or more: the sequence
ends a step once the witnesses were unchanged for settle_time, so a PC that held them back as
long decides the steps in its place.
"""
import os
from typing import Callable, Optional

from ..motion.record import Recording
from .lag import BUSY_LOAD_PER_CORE, StallProbe

# the skip reasons a busy PC can cause (motion/sequence.py, motion/safety.py, motion/rules.py,
# the check's end)
PC_CAN_CAUSE = ('no HeadYaw in the joint states', 'no laser scan and no sonar reading arrived',
                'no witness to tell whether it moved', "the check's window ended")


class PcWatch:
    """The load, the process's stalls and the witnesses' lateness over the motion check."""

    def __init__(self, clock: Callable[[], float]) -> None:
        self.clock = clock
        self.probe = StallProbe.shared()
        self.began = clock()
        self.cores = os.cpu_count() or 1
        self.load = 0.0
        self._load_at = -1e18

    def poll(self, now: float) -> None:
        """Notes the 1-minute load average, once a second."""
        if now - self._load_at >= 1.0:
            self._load_at = now
            self.load = max(self.load, os.getloadavg()[0])

    def busy(self, rec: Recording, settle_time: float) -> Optional[str]:
        """'load average 8.6 on 2 cores; ...' when the PC was busy (the module's rule); None."""
        self.poll(self.clock())
        stalled = self.probe.stalled(self.began, self.clock())
        with rec.lock:
            behind = rec.behind
        if self.load <= BUSY_LOAD_PER_CORE * self.cores and stalled < settle_time and behind < settle_time:
            return None
        return ('load average %.1f on %d cores; sensorTest did not run for %.1f s in all during the '
                'motion check; the witnesses\' messages handled up to %.2f s after their stamps'
                % (self.load, self.cores, stalled, behind))


def explain(skip: Optional[str], busy: Optional[str]) -> Optional[str]:
    """The motion row's skip reason, saying the PC was busy when that can have caused it."""
    if not skip or not busy or not any(k in skip for k in PC_CAN_CAUSE):
        return skip
    return ('%s. This PC was busy (%s): the PC, not the robot, may have kept the witnesses\' '
            'messages from sensorTest in time; test again when it is quieter' % (skip, busy))
