"""How this process handles each message of a live source, measured on the thread that runs
its callback, for sensorTest's own lag (sensors/lag.py, issue 41).

rospy runs a topic's callbacks on that topic's connection thread; rclpy's executor runs every
topic's on its one spinning thread (sources/live2.py). Both live sources wrap each callback,
of every listener alike, in `begin` and `finish` and hand the `Handling` to the listener's
feed_raw (sources.Listener): a message whose callback starts less than GAP s after the
previous one on its thread returned was already waiting, so it may have waited as long as the
thread has been busy without a break. Every other subscription of the process (rosapi's)
is wrapped alike (`timed`), so the thread's busy time counts them too.
"""
import threading
import time
from typing import Any, Callable, NamedTuple, Optional

# s between one callback's return and the next one's start below which the next message was
# already waiting: two of CPython's 5 ms interpreter-lock switch intervals (a topic at 50 Hz,
# the fastest naoqi_driver publishes, leaves ~19 ms between its callbacks when keeping up)
GAP = 0.01


class Handling(NamedTuple):
    """One callback as its source measured it when it began (`begin`)."""
    t0: float           # monotonic time the callback began (the message's receive time)
    since: float        # since when its thread had been busy without a break (t0 after a break)
    cpu0: float         # the thread's CPU time then
    thread_busy: float  # s every callback on this thread had taken before this one


class _Thread:
    """The callbacks of one thread: when the last one returned, since when it has been busy."""

    __slots__ = ('busy_since', 'last_end', 'busy')

    def __init__(self) -> None:
        self.busy_since = 0.0
        self.last_end: Optional[float] = None
        self.busy = 0.0


_local = threading.local()     # .thread: the calling thread's _Thread (a new thread starts afresh)


def current() -> Optional[_Thread]:
    """The calling thread's callbacks so far (None before its first)."""
    return getattr(_local, 'thread', None)


def begin(now: float) -> Handling:
    """A callback begins at `now` (monotonic) on the calling thread: its Handling."""
    th = current()
    if th is None:
        th = _local.thread = _Thread()
    if th.last_end is None or now - th.last_end > GAP:
        th.busy_since = now
    return Handling(now, th.busy_since, time.thread_time(), th.busy)


def finish(handling: Handling, now: float) -> None:
    """The callback `begin` gave `handling` for returned at `now`, on the same thread."""
    th = current()
    if th is not None:
        th.last_end = now
        th.busy += max(0.0, now - handling.t0)


class measured:
    """`with measured() as own:` a callback's body between begin and finish (the live sources'
    callbacks hand `own` to feed_raw; `timed` wraps the others). A class, not a generator: it
    runs once per message."""

    __slots__ = ('own',)

    def __enter__(self) -> Handling:
        self.own = begin(time.monotonic())
        return self.own

    def __exit__(self, *exc: Any) -> None:
        finish(self.own, time.monotonic())


def timed(callback: Callable[..., None]) -> Callable[..., None]:
    """`callback` between begin and finish: a subscription that feeds no window (rosapi's: the
    motion check's witnesses, the guide's) keeps its thread busy all the same, and on ROS 2 that
    thread is every topic's."""
    def wrapped(*args: Any) -> None:
        with measured():
            callback(*args)
    return wrapped
