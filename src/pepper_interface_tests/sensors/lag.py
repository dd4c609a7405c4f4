"""sensorTest's own lag on a topic, told apart from the sensor's (issue 41).

On a busy PC (naoqi_driver converting images, a recording, a build) sensorTest itself handles
what has arrived late: rospy reads each topic's connection in a thread of its own and calls
the window's callback there, so while a callback waits for the CPU, the next messages wait in
the socket; once it runs again they come one after the other. Their header stamps then look
old ("stale data: header stamps up to 5.58 s behind ROS time" beside six CPU-bound processes
on 2 cores) and their pace bunched, although the sensor sent them on time.

Measured on the thread that runs the callbacks: rospy runs a topic's callbacks on that topic's
connection thread, rclpy's executor (sources/live2.py) every topic's on its one spinning thread.
Every live source, ROS 1 and ROS 2 alike, wraps each callback in `begin` and `finish`
(sources/handling.py) and hands the `Handling` that `begin` returns to the listener's feed_raw
(sources.Listener); a sensor's window keeps its topic's share of it in an OwnLag:
  * own wait: how long the thread has been busy without a break when a callback starts: a
    callback that starts less than GAP s after the previous one on its thread returned found
    its message already waiting, so the message may have waited as long as the thread has been
    busy; one after a break was read as it came;
  * CPU share: the callbacks' CPU time over their wall time: below 1 when the thread waited
    for a core (or for the interpreter lock held by another thread);
  * the thread's load: the time every callback on the thread took while this topic was
    listened to (on ROS 2 the other topics' callbacks delay this one's as much as its own);
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

from ..sources.handling import Handling

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
    """One topic's lag in this process (module docstring), kept by its window from the
    Handling of each of its callbacks."""

    def __init__(self, probe: Optional[StallProbe] = None) -> None:
        self.probe = probe
        self.longest = 0.0          # s: the longest a message may have waited in this process
        self.wall = 0.0             # s the callbacks took
        self.cpu = 0.0              # s of CPU they used
        self.thread_wall = 0.0      # s every callback on their thread took meanwhile
        self.load = 0.0             # the highest 1-minute load average seen while listening
        self.cores = os.cpu_count() or 1
        self._load_at = -1.0
        self._first = 0.0           # the first callback's start
        self._thread0: Optional[float] = None   # the thread's callbacks' time before the first

    def start(self, handling: Handling) -> None:
        """One of this topic's callbacks began (`handling`: its source's measure, `begin`)."""
        if self.probe is None:      # listening live: the process's stall probe runs
            self.probe = StallProbe.shared()
        now = handling.t0
        self.longest = max(self.longest, now - handling.since)
        if now - self._load_at >= 1.0:
            self._load_at = now
            self.load = max(self.load, os.getloadavg()[0])
        if not self._first:
            self._first = now
        if self._thread0 is None:
            self._thread0 = handling.thread_busy

    def end(self, handling: Handling, now: float) -> None:
        """That callback returns at `now` (monotonic), on the thread it began on."""
        took = max(0.0, now - handling.t0)
        self.wall += took
        self.cpu += max(0.0, time.thread_time() - handling.cpu0)
        self.thread_wall = handling.thread_busy + took - (self._thread0 or 0.0)

    def wait(self, t: float, since: float) -> float:
        """How long a message handled at `t`, by a thread busy without a break since `since`,
        may have waited in this process: that long, and through a stall just before it."""
        wait = (t - since) + (self.probe.waited(since) if self.probe is not None else 0.0)
        self.longest = max(self.longest, wait)
        return wait

    def saturated(self, elapsed: float) -> bool:
        """The callbacks on this topic's thread (its own, and on ROS 2 every other topic's) took
        SATURATED of the window or more: sensorTest could not keep up with it (messages dropped
        from its queue), or it waited through stalls as long."""
        stalled = 0.0
        if self.probe is not None and self._first:
            stalled = self.probe.stalled(self._first, self._first + elapsed)
        return elapsed > 0 and (max(self.wall, self.thread_wall) + stalled) >= SATURATED * elapsed

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
        callbacks busy 3.1 s, its callbacks on a CPU 31 % of their time' (and, when its thread
        serves other topics too, as rclpy's executor does, how long all of them took)."""
        share = self.cpu_share
        shared = self.thread_wall - self.wall
        return 'load average %.1f on %d cores; sensorTest up to %.2f s behind on this topic, its callbacks ' \
            'busy %.1f s%s%s' % (
                self.load, self.cores, self.longest, self.wall,
                ' (%.1f s with the other topics\' on their thread)' % self.thread_wall if shared >= 0.1 else '',
                ', its callbacks on a CPU %.0f %% of their time' % (100 * share) if share is not None else '')


def starved_hint(lag: Optional[OwnLag]) -> str:
    """For a rate below its band while this PC was busy (load average above the cores) and
    sensorTest kept up (otherwise the row is NOT JUDGED): the publisher may be the starved one,
    if it runs here (naoqi_driver or the emulator on this laptop: a converter that waits for a
    core publishes less). The FAIL stays: a robot's driver may as well be slow on its own, and
    only the operator knows where it runs. '' when the PC was not busy or not measured (a bag)."""
    if lag is None or lag.probe is None or lag.load <= BUSY_LOAD_PER_CORE * lag.cores:
        return ''
    return ('; this PC was busy while listening (load average %.1f on %d cores, sensorTest kept up): '
            'if the driver or the emulator publishing it runs on this PC, it may have been starved of '
            'CPU and published less; test again when the PC is quieter before replacing anything'
            % (lag.load, lag.cores))


def load_now() -> str:
    """The load average now against the cores, in the words every busy-PC reason uses."""
    return 'load average %.1f on %d cores' % (os.getloadavg()[0], os.cpu_count() or 1)


# seconds of a window during which this process did not run that explain a 1 Hz topic's silence
# (robotHealth: naoqi_driver's /diagnostics at 1 Hz, share/boot_config.json "diag")
STALLED_EXPLAINS = 1.0


def pc_busy(lag: Optional[OwnLag], began: float, now: float) -> str:
    """Why this PC counts as busy for a live window that began at `began` (monotonic), in the
    words every busy-PC reason uses; '' when it does not: the load average now above the cores,
    the topic's callbacks on a CPU less than half of their time (OwnLag.busy), or this process
    not running for STALLED_EXPLAINS s or more since `began` (the stall probe, started here if
    no callback of the topic has started it)."""
    probe = lag.probe if lag is not None and lag.probe is not None else StallProbe.shared()
    if lag is not None:
        lag.probe = probe
    stalled = probe.stalled(began, now)
    load, cores = os.getloadavg()[0], os.cpu_count() or 1
    if load <= BUSY_LOAD_PER_CORE * cores and stalled < STALLED_EXPLAINS and not (lag is not None and lag.busy):
        return ''
    return '%s; sensorTest did not run for %.1f s of the %.1f s listened%s' % (
        load_now(), stalled, now - began,
        ', its callbacks on a CPU %.0f %% of their time' % (100 * lag.cpu_share)
        if lag is not None and lag.cpu_share is not None else '')
