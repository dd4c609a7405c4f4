"""sensorTest's own lag on a topic, told apart from the sensor's (issue 41).

On a busy PC (naoqi_driver converting images, a recording, a build) sensorTest itself handles
what has arrived late: rospy reads each topic's connection in a thread of its own and calls
the window's callback there, so while a callback waits for the CPU, the next messages wait in
the socket; once it runs again they come one after the other. Their header stamps then look
old ("stale data: header stamps up to 5.58 s behind ROS time" beside six CPU-bound processes
on 2 cores) and their pace bunched, although the sensor sent them on time.

Measured per topic, on the subscriber's thread (the live source calls `start` as a callback
begins and `end` as it returns):
  * own wait: how long the thread has been busy without a break when a callback starts: a
    callback that starts less than GAP s after the previous one returned found its message
    already waiting, so the message may have waited as long as the thread has been busy;
    one after a break was read as it came;
  * CPU share: the callbacks' CPU time over their wall time: below 1 when the thread waited
    for a core (or for the interpreter lock held by another topic's thread);
  * stalls: a thread of this process wakes every TICK s and notes how late it woke (STALL or
    more: the process got no CPU, or was stopped, for that long). A message handled right
    after a stall may have waited through it: the socket held it while nothing here ran, and
    the callback that reads it starts "after a break" all the same;
  * the load average (os.getloadavg, once a second) against the cores (os.cpu_count).
A delay or a rate that this lag explains is the PC's, not the sensor's: the row says NOT
JUDGED, naming the load and the lag (`describe`), instead of failing the sensor.
"""
import collections
import os
import threading
import time
from typing import Deque, Optional, Tuple

# s between one callback's return and the next one's start below which the next message was
# already waiting: two of CPython's 5 ms interpreter-lock switch intervals (a topic at 50 Hz,
# the fastest naoqi_driver publishes, leaves ~19 ms between its callbacks when keeping up)
GAP = 0.01
# share of the window a topic's callbacks took above which sensorTest could not keep up with it:
# rospy then drops the oldest messages of a full subscriber queue, and the rate reads low
SATURATED = 0.8
# load average per core above which the PC counts as busy: more runnable processes than cores
BUSY_LOAD_PER_CORE = 1.0
# the stall probe: wakes every TICK s; a wake-up STALL s late or more is a stall of the process
TICK, STALL = 0.05, 0.05


class StallProbe:
    """One thread per process noting when the process did not run (module docstring)."""

    _lock = threading.Lock()
    _probe: Optional['StallProbe'] = None

    def __init__(self) -> None:
        self.stalls: Deque[Tuple[float, float]] = collections.deque(maxlen=10000)   # (began, ended)
        thread = threading.Thread(target=self._loop, daemon=True, name='stall-probe')
        thread.start()

    @classmethod
    def shared(cls) -> 'StallProbe':
        with cls._lock:
            if cls._probe is None:
                cls._probe = StallProbe()
            return cls._probe

    def _loop(self) -> None:
        due = time.monotonic() + TICK
        while True:
            time.sleep(max(0.0, due - time.monotonic()))
            now = time.monotonic()
            if now - due >= STALL:
                self.stalls.append((due, now))
            due = now + TICK

    def stalled(self, a: float, b: float) -> float:
        """Seconds of [a, b] (monotonic) during which the process did not run."""
        return sum(max(0.0, min(b, ended) - max(a, began)) for began, ended in list(self.stalls))

    def waited(self, t: float) -> float:
        """How long something handled at `t` may have waited through a stall: from the start
        of a stall that covers `t` or ended at most 2 TICKs before it (0.0: none)."""
        return max([t - began for began, ended in list(self.stalls) if began <= t <= ended + 2 * TICK] or [0.0])


class OwnLag:
    """One topic's lag in this process (module docstring)."""

    def __init__(self, probe: Optional[StallProbe] = None) -> None:
        self.probe = probe
        self.busy_since: Optional[float] = None
        self.last_end: Optional[float] = None
        self.longest = 0.0          # s: the longest a message may have waited in this process
        self.wall = 0.0             # s the callbacks took
        self.cpu = 0.0              # s of CPU they used
        self.load = 0.0             # the highest 1-minute load average seen while listening
        self.cores = os.cpu_count() or 1
        self._load_at = -1.0
        self._first = 0.0           # the first callback's start
        self._cpu0 = 0.0
        self._t0 = 0.0

    def start(self, now: float) -> float:
        """A callback begins at `now` (monotonic): since when this topic's thread has been busy
        without a break (`now` itself after a break); `wait` turns it into a wait."""
        if self.probe is None:      # listening live: the process's stall probe runs
            self.probe = StallProbe.shared()
        if self.busy_since is None or self.last_end is None or now - self.last_end > GAP:
            self.busy_since = now
        self.longest = max(self.longest, now - self.busy_since)
        if now - self._load_at >= 1.0:
            self._load_at = now
            self.load = max(self.load, os.getloadavg()[0])
        self._t0, self._cpu0 = now, time.thread_time()
        if not self._first:
            self._first = now
        return self.busy_since

    def end(self, now: float) -> None:
        self.last_end = now
        self.wall += max(0.0, now - self._t0)
        self.cpu += max(0.0, time.thread_time() - self._cpu0)

    def wait(self, t: float, since: float) -> float:
        """How long a message handled at `t`, by a thread busy without a break since `since`,
        may have waited in this process: that long, and through a stall just before it."""
        wait = (t - since) + (self.probe.waited(since) if self.probe is not None else 0.0)
        self.longest = max(self.longest, wait)
        return wait

    def saturated(self, elapsed: float) -> bool:
        """This topic's callbacks took SATURATED of the window or more: sensorTest could not
        keep up with it (messages dropped from its queue), or it waited through stalls as long."""
        stalled = 0.0
        if self.probe is not None and self._first:
            stalled = self.probe.stalled(self._first, self._first + elapsed)
        return elapsed > 0 and (self.wall + stalled) >= SATURATED * elapsed

    @property
    def cpu_share(self) -> Optional[float]:
        return self.cpu / self.wall if self.wall > 0.05 else None

    @property
    def busy(self) -> bool:
        """The PC was busy while this topic was listened to: load above the cores, or this
        topic's callbacks got the CPU for less than half of their time."""
        share = self.cpu_share
        return self.load > BUSY_LOAD_PER_CORE * self.cores or (share is not None and share < 0.5)

    def describe(self) -> str:
        """'load average 7.9 on 2 cores; sensorTest up to 5.20 s behind on this topic, its
        callbacks on a CPU 31 % of their time'."""
        share = self.cpu_share
        return 'load average %.1f on %d cores; sensorTest up to %.2f s behind on this topic, its callbacks ' \
            'busy %.1f s%s' % (
            self.load, self.cores, self.longest, self.wall,
            ', its callbacks on a CPU %.0f %% of their time' % (100 * share) if share is not None else '')
