"""Stream statistics shared by every sensor: counts, rates, jitter, gaps, stamp sanity, delay.

One StreamStats per sensor run. `add()` is called for every message with its receive time
(monotonic seconds, or the bag's record time) and, where the message has a header, its stamp
and the ROS time at reception. Everything else is derived on demand.

Clock: rates, intervals, jitter, gaps and the rate series are measured on `clock`: 'wall'
(the receive times) or 'sim' (the simulation time at reception, `t_clock`, given when
/use_sim_time is true): a 5 Hz simulated camera at real-time factor 0.5 arrives at 2.5 Hz of
wall time but is 5 Hz on the clock its driver runs on.
'record' labels a bag's record times (receive times too): `rosbag record` takes them from
ros::Time::now(), i.e. from the simulation clock when the bag was recorded under /use_sim_time.
On 'sim', a message can arrive before this node's first /clock tick (a player sends a topic's
first message and its first /clock on separate connections: `rosbag play --clock` publishes
/clock from its own TimePublisher, ros_comm tools/rosbag/src/player.cpp, and nothing orders the
two across the node's subscriptions): rospy's ROS time is still 0 then,
so the message is counted (and its stamp checked for order) but has no place on the simulation
clock and no delay; `before_clock` counts such messages.

`StreamStats.summary()` hands the numbers over as a frozen `StreamSummary` (a sensor's
SensorResult.stats, its "stats" in the JSON, written and read back by codec.py).
"""
import math
from dataclasses import dataclass
from typing import Dict, List, Optional, Tuple

from .codec import nullable, optional_number


def _rate(times):
    if len(times) < 2 or times[-1] <= times[0]:
        return None
    return (len(times) - 1) / (times[-1] - times[0])


def _mean(values):
    return sum(values) / len(values) if values else None


def _std(values):
    if len(values) < 2:
        return None
    m = _mean(values)
    return math.sqrt(sum((v - m) ** 2 for v in values) / (len(values) - 1))


@dataclass(frozen=True)
class DelaySummary:
    """ROS time at reception minus header stamp (s)."""
    min: Optional[float] = nullable()
    mean: Optional[float] = nullable()
    max: Optional[float] = nullable()


@dataclass(frozen=True)
class StreamSummary:
    """A stream's numbers at the end of its window (JSON "stats", docs/results.md). The counts
    are None only in a JSON that lacked them (they are always measured)."""
    messages: Optional[int] = nullable()
    clock: Optional[str] = nullable()                  # 'wall', 'sim' or 'record': rates measured on it
    rate_hz: Optional[float] = nullable()              # from receive times
    stamp_rate_hz: Optional[float] = nullable()        # from header stamps
    jitter_s: Optional[float] = nullable()             # std of the receive intervals
    max_interval_s: Optional[float] = nullable()
    first_message_after_s: Optional[float] = nullable()
    zero_stamps: Optional[int] = nullable()
    backwards_stamps: Optional[int] = nullable()
    repeated_stamps: Optional[int] = nullable()
    delay_s: Optional[DelaySummary] = nullable()       # None: no headers (or no ROS time)
    # on the simulation clock only (not written otherwise); NaN: /clock not running, unknown
    real_time_factor: Optional[float] = optional_number()


class StreamStats:
    def __init__(self, start: Optional[float] = None, clock: str = 'wall',
                 clock_start: Optional[float] = None) -> None:
        self.start = start          # when listening began (same clock as receive times)
        self.clock = clock          # 'wall' or 'sim': the clock rates are measured on
        self.clock_start = clock_start   # sim time when listening began (clock 'sim')
        self.recv: List[float] = []          # receive times
        self.clock_recv: List[float] = []    # sim time at reception (clock 'sim')
        self.stamps: List[float] = []        # header stamps (s), 0.0 kept to count zero stamps
        self.delays: List[float] = []        # ROS now - stamp at reception (s)
        self.zero_stamps = 0
        self.backwards = 0          # stamp older than the previous one
        self.repeated = 0           # stamp equal to the previous one

    def add(self, t_recv: float, stamp: Optional[float] = None, ros_now: Optional[float] = None,
            t_clock: Optional[float] = None) -> None:
        self.recv.append(t_recv)
        if self.clock == 'sim':
            assert t_clock is not None, 'clock "sim" measures on t_clock: give it'
            if t_clock <= 0.0:   # ROS time not running yet: no sim time, no delay for this one
                ros_now = None
            else:
                self.clock_recv.append(t_clock)
        if stamp is None:
            return
        if stamp == 0.0:
            self.zero_stamps += 1
            return
        if self.stamps:
            if stamp < self.stamps[-1]:
                self.backwards += 1
            elif stamp == self.stamps[-1]:
                self.repeated += 1
        self.stamps.append(stamp)
        if ros_now is not None:
            self.delays.append(ros_now - stamp)

    @property
    def count(self) -> int:
        return len(self.recv)

    @property
    def before_clock(self) -> int:
        """Messages received before the first /clock tick (clock 'sim'): counted, not timed."""
        return len(self.recv) - len(self.clock_recv) if self.clock == 'sim' else 0

    @property
    def times(self) -> List[float]:
        """Receive times on the measuring clock."""
        return self.clock_recv if self.clock == 'sim' else self.recv

    @property
    def rate(self) -> Optional[float]:
        """Rate from receive times (Hz) over the span of the messages, on the measuring clock."""
        return _rate(self.times)

    @property
    def stamp_rate(self) -> Optional[float]:
        """Rate from header stamps (Hz); None without headers or with bad stamps."""
        ordered = self.stamps
        if len(ordered) < 2 or self.backwards:
            return None
        return _rate(ordered)

    def intervals(self) -> List[float]:
        t = self.times
        return [b - a for a, b in zip(t, t[1:])]

    @property
    def jitter(self) -> Optional[float]:
        """Standard deviation of the receive intervals (s)."""
        return _std(self.intervals())

    @property
    def first_latency(self) -> Optional[float]:
        """Seconds from the start of listening to the first message."""
        if not self.recv or self.start is None:
            return None
        return self.recv[0] - self.start

    def gaps(self, threshold: float) -> List[Tuple[float, float]]:
        """Pauses longer than `threshold` seconds: [(offset from first message, length)]."""
        t = self.times
        if not t:
            return []
        t0 = t[0]
        return [(a - t0, b - a) for a, b in zip(t, t[1:]) if b - a > threshold]

    @property
    def max_interval(self) -> Optional[float]:
        iv = self.intervals()
        return max(iv) if iv else None

    def delay_summary(self) -> Optional[Dict[str, float]]:
        if not self.delays:
            return None
        return {'min': min(self.delays), 'mean': _mean(self.delays), 'max': max(self.delays)}

    def rate_series(self, end: Optional[float] = None, bin_s: float = 1.0) -> List[Tuple[float, float]]:
        """Messages per second in consecutive bins since the start: [(t, Hz)] for plots
        (`end` and the bins on the measuring clock)."""
        start = self.clock_start if self.clock == 'sim' else self.start
        times = self.times
        if start is None:
            return []
        last = end if end is not None else (times[-1] if times else start)
        n_bins = max(1, int(math.ceil((last - start) / bin_s)))
        counts = [0] * n_bins
        for t in times:
            i = min(n_bins - 1, max(0, int((t - start) / bin_s)))
            counts[i] += 1
        span = last - start
        widths = [bin_s] * n_bins
        widths[-1] = max(0.0, min(bin_s, span - (n_bins - 1) * bin_s))
        if n_bins > 1 and widths[-1] < 0.5 * bin_s:
            # a short last bin says little about the rate on its own: fold it into the one before
            extra_count, extra_width = counts.pop(), widths.pop()
            counts[-1] += extra_count
            widths[-1] += extra_width
        out, start = [], 0.0
        for c, width in zip(counts, widths):
            if width > 0:
                out.append((round(start + width / 2, 3), c / width))
            start += width
        return out

    def summary(self) -> StreamSummary:
        def r(x: Optional[float], nd: int = 3) -> Optional[float]:
            return None if x is None else round(x, nd)
        delay = self.delay_summary()
        return StreamSummary(
            messages=self.count, clock=self.clock, rate_hz=r(self.rate), stamp_rate_hz=r(self.stamp_rate),
            jitter_s=r(self.jitter, 4), max_interval_s=r(self.max_interval),
            first_message_after_s=r(self.first_latency), zero_stamps=self.zero_stamps,
            backwards_stamps=self.backwards, repeated_stamps=self.repeated,
            delay_s=DelaySummary(r(delay['min'], 4), r(delay['mean'], 4), r(delay['max'], 4)) if delay else None)


# ------------------------------------------------------------------ rate of what a stream carried

@dataclass(frozen=True)
class CarriedRate:
    """Units per second a stream carried (samples of audio), and how sure the measure is."""
    rate: float
    # relative uncertainty: the farther of the stream's two halves from the line, in seconds
    # below it, over half the span (0 when both halves have a message on time; tenths when one
    # half came all late and the line could tilt that much)
    spread: float
    points: int


def _upper_hull(points: List[Tuple[float, float]]) -> List[Tuple[float, float]]:
    """The upper convex hull of (time, cumulative count) points, left to right (a later point
    at the same time with more counted replaces the earlier)."""
    hull: List[Tuple[float, float]] = []
    for x, y in sorted(points):
        if hull and hull[-1][0] == x:
            hull.pop()                 # sorted: this one counted more at the same time
        while len(hull) >= 2:
            (x1, y1), (x2, y2) = hull[-2], hull[-1]
            if (x2 - x1) * (y - y1) - (y2 - y1) * (x - x1) >= 0:   # hull[-1] on or below the chord
                hull.pop()
            else:
                break
        hull.append((x, y))
    return hull


def _hull_line(points: List[Tuple[float, float]]) -> Optional[Tuple[float, float, float]]:
    """(slope, x, y) of the upper hull's edge at the mean time (a point it passes through)."""
    hull = _upper_hull(points)
    if len(hull) < 2:
        return None
    mean_t = sum(p[0] for p in points) / len(points)
    for (x1, y1), (x2, y2) in zip(hull, hull[1:]):
        if mean_t < x2:
            return (y2 - y1) / (x2 - x1), x1, y1
    (x1, y1), (x2, y2) = hull[-2], hull[-1]
    return (y2 - y1) / (x2 - x1), x1, y1


def carried_rate(points: List[Tuple[float, float]]) -> Optional[CarriedRate]:
    """The rate a stream was produced at, from (time it was handed over, units carried so far
    including that message) per message, however late or bunched the messages came.

    A message can be handed over late (a busy network holds it, a busy PC handles it late) but
    never before its content existed: every point lies on or below the line `units = rate x
    (time - start)` of the producer, and the messages that came without delay lie on it. That
    line is the upper convex hull's edge at the mean time (the linear programme of Moon, Skelly
    and Towsley, "Estimation and removal of clock skew from network delay measurements",
    INFOCOM 1999, which finds a clock's rate from one-way delays that are only ever late).
    A catch-up burst at the start, pauses followed by the held messages, messages two or three
    at a time, a window that ends in a pause: each leaves points below that line, not its slope.
    The median of per-message rates (units / time since the previous message) did not: after a
    pause most intervals are short, and a healthy 48 kHz stream read 52-64 kHz (issue 41).

    `spread`: how far the line could tilt, relative, the larger of two measures: in each half
    of the messages the one nearest the line is some seconds below it (0: on time), over half
    the span; and each half measured alone against the whole. None with fewer than 2 distinct
    times."""
    line = _hull_line(points)
    if line is None or line[0] <= 0:
        return None
    rate, x0, y0 = line
    spread = 0.0
    ordered = sorted(points)
    span = ordered[-1][0] - ordered[0][0]
    if len(ordered) >= 8 and span > 0:
        half = len(ordered) // 2
        for part in (ordered[:half], ordered[half:]):
            late = min(((y0 + rate * (x - x0)) - y) / rate for x, y in part)
            alone = _hull_line(part)
            spread = max(spread, late / (span / 2.0),
                         abs(alone[0] - rate) / rate if alone is not None else 1.0)
    return CarriedRate(rate, spread, len(points))


class StampPlacer:
    """Where a message handled late belongs on this process's clock, by its header stamp
    (issue 41): a message that waited (a busy PC: in this process's queue or the publisher's;
    a WiFi hold; then a burst) is placed when its stamp says it was made, not when it was
    handled. The stamp's clock may be offset from this one (a driver on the robot): each message
    is placed by how much later it was handled than the least late message so far (`floor`: the
    offset plus the quickest delivery), so only a stamp within `max_late` s of this computer's
    wall clock counts (not sim time, not a clock far off). Placed times never go back (a floor
    that dropped after earlier messages were placed)."""

    def __init__(self, max_late: float = 10.0) -> None:
        self.max_late = max_late
        self.floor: Optional[float] = None
        self.behind = 0.0       # s: the most a message was handled behind the floor
        self.last = -1e18       # where the last message was placed

    def place(self, t: float, late: Optional[float]) -> float:
        """`t`: when the message was handled (any clock); `late`: this computer's wall clock
        then, less the message's stamp (None: it has none). Returns where it belongs on t's clock."""
        if late is not None and abs(late) < self.max_late:
            self.floor = late if self.floor is None else min(self.floor, late)
            self.behind = max(self.behind, late - self.floor)
            t -= late - self.floor
        self.last = max(t, self.last)
        return self.last
