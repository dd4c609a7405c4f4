"""What every sensor check shares: the Check base class, counted problems and value summaries.

A Check validates one sensor's messages and owns all of its state (no globals, no locks
needed: the runner feeds one check from one subscriber thread, and reads it only after the
window has closed). Subclasses override `fields`, `on_message`, and optionally `finish`,
`settled`, `start`, `poll`; a check that measures values puts its family's values dataclass
in `self.found`, which `result_values` hands over.
"""
import dataclasses
import math
from collections import OrderedDict
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable, Dict, Hashable, List, Mapping, Optional, Protocol, Sequence, Tuple

from ..results import FAIL, NOT_JUDGED, PASS, SKIPPED, Verdict
from .values import Spread

if TYPE_CHECKING:
    import genpy
    import numpy as np

    from ..media.viewer import Viewer
    from ..plan.options import Options
    from ..plan.settings import SensorPlan
    from .lag import OwnLag
    from .tree import Tree


def fmt(value: Any, nd: int = 4) -> str:
    """Short, readable text for numbers, sequences and the rest; "-" for a missing value (no
    Python None in any output)."""
    if value is None:
        return '-'
    if isinstance(value, float):
        if math.isnan(value) or math.isinf(value):
            return str(value)
        return ('%.*f' % (nd, value)).rstrip('0').rstrip('.') if value != 0 else '0'
    if isinstance(value, (list, tuple)):
        return '[' + ', '.join(fmt(v, nd) for v in value) + ']'
    return str(value)


class Acc:
    """Running min / mean / max of a numeric quantity (NaN and inf counted apart)."""

    __slots__ = ('n', 'total', 'lo', 'hi', 'nonfinite')

    def __init__(self) -> None:
        self.n, self.total, self.nonfinite = 0, 0.0, 0
        self.lo: Optional[float] = None
        self.hi: Optional[float] = None

    def add(self, v: float) -> None:
        v = float(v)
        if not math.isfinite(v):
            self.nonfinite += 1
            return
        self.n += 1
        self.total += v
        self.lo = v if self.lo is None or v < self.lo else self.lo
        self.hi = v if self.hi is None or v > self.hi else self.hi

    def as_dict(self, nd: int = 4) -> Dict[str, Optional[float]]:
        if not self.n:
            return {'min': None, 'mean': None, 'max': None}
        lo, hi = float(self.lo or 0.0), float(self.hi or 0.0)    # set once n > 0
        return {'min': round(lo, nd), 'mean': round(self.total / self.n, nd), 'max': round(hi, nd)}

    def spread(self, nd: int = 4) -> Spread:
        """`as_dict` as the values' Spread."""
        return Spread(**self.as_dict(nd))

    def text(self, unit: str = '') -> str:
        if not self.n:
            return 'no finite values'
        d = self.as_dict()
        return 'min %s, mean %s, max %s%s' % (fmt(d['min']), fmt(d['mean']), fmt(d['max']),
                                              (' ' + unit) if unit else '')


class Tally:
    """Problems counted per kind: 'range outside [0.25, 2.55] m in 12 of 100 messages (e.g. 3.1)'."""

    def __init__(self) -> None:
        self._items: Dict[str, List[Any]] = OrderedDict()   # key -> [text, count, example]

    def add(self, key: str, text: str, example: Any = None) -> None:
        item = self._items.get(key)
        if item is None:
            self._items[key] = [text, 1, example]
        else:
            item[1] += 1

    def __bool__(self):
        return bool(self._items)

    def keys(self) -> List[str]:
        return list(self._items)

    def reasons(self, total: int) -> List[str]:
        out = []
        for text, count, example in self._items.values():
            line = text
            if total and total > 1:
                line += ' in %d of %d messages' % (count, total)
            if example is not None:
                line += ' (e.g. %s)' % fmt(example)
            out.append(line)
        return out


@dataclass
class Judgement:
    """What one check found at the end of a window: FAIL reasons, warnings, and a reason to
    skip the sensor instead of judging it (e.g. a touch sensor nobody touched, unattended)."""
    reasons: List[str]
    warnings: List[str]
    skip: Optional[str] = None
    # what could not be judged because the PC running sensorTest was too busy (sensors/lag.py):
    # NOT JUDGED unless something failed
    unjudged: List[str] = dataclasses.field(default_factory=list)

    def merged(self, other: 'Judgement') -> 'Judgement':
        """Both checks' findings; the verdict is the worse of the two
        (FAIL > NOT JUDGED > SKIPPED > PASS)."""
        return Judgement(self.reasons + other.reasons, self.warnings + other.warnings,
                         self.skip or other.skip, self.unjudged + other.unjudged)

    @property
    def verdict(self) -> Verdict:
        return FAIL if self.reasons else NOT_JUDGED if self.unjudged else SKIPPED if self.skip else PASS


class Hearing(Protocol):
    """What the speech check asks of the microphones (sensors/audio.py LevelMonitor)."""

    def has_baseline(self) -> bool:
        """True once the room's level before speaking is known."""

    def heard(self, t0: float, t1: float) -> Dict[str, Any]:
        """Whether the level rose between `t0` and `t1` (monotonic seconds)."""

    def covered(self, t: float) -> bool:
        """The microphones' stream has reached `t` (monotonic seconds)."""

    def longest_pause(self, a: float, b: float) -> float:
        """The longest stretch of [a, b] the microphones said nothing (s)."""


class RestWitness(Protocol):
    """What the laser check asks: whether the robot rests (sensors/stiffness.py)."""

    def stiffness(self) -> Optional[Tuple[int, float]]:
        """(joints the driver reported, the highest latest stiffness), None: no report yet."""


class Operator(Protocol):
    """A person asked to act, zone by zone (sensors/guide.py Guide): one sensor asks at a time."""

    budget: float   # seconds the guided part may take in all (every zone of every touch sensor)

    def turn(self, owner: str) -> bool:
        """True when sensor `owner` may ask now (no other sensor is asking)."""

    def publishing(self, topic: str) -> Optional[bool]:
        """Whether anything publishes `topic` now (False: nobody to touch it for); None: unknown."""

    def ask(self, zone_id: str, text: str) -> None:
        """Ask for one zone: on the terminal, on /sensorTest/prompt, through the loudspeaker."""

    def skipped(self) -> bool:
        """True once the person asked to skip the zone being asked (from the keyboard)."""

    def moved_on(self, zone_id: str, why: str, more: bool) -> None:
        """The zone being asked is given up without its touch (`why`: its wait ended, it is
        stuck): said on the terminal and on /sensorTest/prompt before the next zone is asked;
        `more`: the asking sensor has zones left to ask."""

    def finished(self, owner: str) -> None:
        """Sensor `owner` has asked all its zones: the next one may ask."""


@dataclass
class Services:
    """Shared helpers a run offers its checks; each is None when the run has none, and a check
    copes with that. Filled and cleared by the observers that own them (outputs/observers.py)."""
    viewer: Optional['Viewer'] = None                  # live camera windows (media/viewer.py)
    microphone_levels: Optional[Hearing] = None  # what the microphones hear (speech)
    debug: Optional[Callable[[str], None]] = None      # --debug: one line per received message
    operator: Optional[Operator] = None                # guided mode: a person who touches the robot
    stiffness: Optional[RestWitness] = None            # the joints' stiffness: is the robot resting?
    tree: Optional['Tree'] = None                      # the run's /tf (sensors/tree.py)


class Findings:
    """What a check found about OTHER sensors, put on their rows when their windows are judged
    (the motion check: a gyro that did not see the turn fails on the imu row). Written by a
    leading check (Traits.leads) before the other windows open; read by sensors/window.py."""

    def __init__(self) -> None:
        self._by: Dict[str, Judgement] = {}

    def add(self, sensor: str, reasons: Sequence[str] = (), warnings: Sequence[str] = ()) -> None:
        old = self._by.get(sensor, Judgement([], []))
        self._by[sensor] = old.merged(Judgement(list(reasons), list(warnings)))

    def of(self, sensor: str) -> Judgement:
        """The findings on `sensor`'s row (none: an empty Judgement)."""
        return self._by.get(sensor, Judgement([], []))

    def sensors(self) -> List[str]:
        return list(self._by)


class RunContext:
    """What checks may use from the run: output folder, options, shared services, every
    sensor's topic (`topics`: a check that watches other sensors, the motion check) and the
    findings checks put on other sensors' rows."""

    def __init__(self, output_dir: str, platform: str, options: 'Options',
                 services: Optional[Services] = None,
                 topics: Optional[Mapping[str, str]] = None) -> None:
        self.output_dir = output_dir
        self.platform = platform
        self.options = options
        self.services = services if services is not None else Services()
        self.topics: Mapping[str, str] = dict(topics or {})
        self.findings = Findings()
        # each image stream's first (width, height, frame_id) by sensor name, as its check saw it
        # (sensors/camera.py): an aligned depth is judged against its colour stream (sensors/depth.py)
        self.images: Dict[str, Tuple[int, int, str]] = {}
        # why the run was interrupted (Ctrl-C, SIGTERM, the master gone), once it is: a check
        # that acts on the robot (the motion check) says why it stopped
        self.interrupted_by: Optional[str] = None


class Check:
    family: Optional[str] = None
    expect: Any             # the family's own Expect (plan/expectations.py); a subclass names it
    found: Any = None       # the family's values dataclass once finish() built it; a subclass types it
    queue_size = 100        # subscriber queue (messages); cameras size it to their stream
    buff_size = 1 << 16     # subscriber receive buffer (bytes); images need 2**24
    numpy_arrays = False    # numeric arrays decoded as numpy views (genpy's deserialize_numpy)
    waits_for_answer = False   # True while the check waits for a person's answer on the terminal
    own_lag: Optional['OwnLag'] = None   # sensorTest's own lag on the topic (set by the window)

    def __init__(self, plan: 'SensorPlan', ctx: RunContext) -> None:
        self.plan = plan
        self.expect = plan.expect
        self.ctx = ctx
        self.count = 0
        self.failures = Tally()     # each kind is a FAIL reason
        self.warnings = Tally()     # reported, do not fail
        self.notes: List[str] = []              # plain information lines
        self.artifacts: Dict[str, str] = OrderedDict()   # kind -> file name in the output folder
        # [(label, value)] of the first message, the spec's fields
        self.first_fields: Optional[List[Tuple[str, Any]]] = None
        self._extra_fail: List[str] = []        # reasons found at the end (finish)
        self._unjudged: List[str] = []          # what the PC was too busy to judge (not_judged)
        self._end_warnings: List[str] = []      # warnings found at the end
        self._finished = False

    # --- called by the runner -----------------------------------------------------------
    def feed(self, msg: 'genpy.Message', t: float) -> None:
        """One valid message; t = seconds since listening began."""
        self.count += 1
        if self.first_fields is None:
            self.first_fields = self.fields(msg)
        self.on_message(msg, t)

    def window(self, duration: float) -> float:
        """Seconds this sensor listens for, given the run's --duration."""
        return duration

    def start(self) -> None:
        """Before listening begins."""

    def observe_connections(self, n: int) -> None:
        """The live source's count of the topic's publishers, every poll (robotHealth reads it)."""

    def poll(self, elapsed: float) -> None:
        """Called about every 50 ms from the runner's thread while the window is open (never at
        the same time as feed: the window holds its lock)."""

    def done(self) -> bool:
        """True when the check has finished by itself (speech has spoken, a guided check has asked
        every zone): the window then ends before its time."""
        return False

    def settled(self) -> bool:
        """With --quick: True when this check has seen enough to give its verdict."""
        return True

    def close(self) -> None:
        """Finish once: summaries, closing writers. Safe to call twice."""
        if not self._finished:
            self._finished = True
            self.finish()

    # --- for subclasses ------------------------------------------------------------------
    def fields(self, msg: 'genpy.Message') -> List[Tuple[str, Any]]:
        return []

    def rate_band(self) -> Optional[List[float]]:
        """Accepted message rate [lo, hi] Hz or None: the expectations' `rate`; a family may
        derive it from the data (the microphone, from its buffer size). Asked after close()."""
        band = self.expect.rate
        return list(band) if band else None

    def on_message(self, msg: 'genpy.Message', t: float) -> None:
        pass

    def finish(self) -> None:
        pass

    def said_on_interrupt(self) -> List[str]:
        """What an interrupted window says beside "interrupted after ..." (the motion check:
        where its motion stopped and what was sent to stop it)."""
        return []

    def fail(self, text: str) -> None:
        """A failure found once, at the end (not counted per message)."""
        self._extra_fail.append(text)

    def warn(self, text: str) -> None:
        """A warning found once, at the end (not counted per message)."""
        self._end_warnings.append(text)

    def not_judged(self, text: str) -> None:
        """Something the PC running sensorTest was too busy to judge (NOT JUDGED, never a FAIL)."""
        self._unjudged.append(text)

    # --- results ---------------------------------------------------------------------------
    def failure_reasons(self) -> List[str]:
        return self.failures.reasons(self.count) + self._extra_fail

    def warning_reasons(self) -> List[str]:
        return self.warnings.reasons(self.count) + self._end_warnings

    def result_values(self) -> Optional[Any]:
        """What the check measured: its family's frozen values dataclass (its row's `values` in
        sensors/families.py), which the check builds itself into `self.found` (typed there by the
        subclass) and which is asked after close(); the JSON and the report are written from it
        (codec.py). None (the default): nothing measured."""
        return self.found

    def skip_reason(self) -> Optional[str]:
        """Why the sensor is SKIPPED instead of judged (asked after close()); None: judge it."""
        return None

    def judgement(self) -> Judgement:
        """This check's findings at the end of the window (after close())."""
        return Judgement(self.failure_reasons(), self.warning_reasons(), self.skip_reason(),
                         list(self._unjudged))


def header_fields(header: Any) -> List[Tuple[str, Any]]:
    return [('Header frame id', header.frame_id),
            ('Header stamp', '%d.%09d' % (header.stamp.secs, header.stamp.nsecs)),
            ('Header seq', header.seq)]


def quaternion_norm(q: Any) -> float:
    return math.sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w)


def finite(values: Any) -> bool:
    return all(math.isfinite(v) for v in values)


class StuckRun:
    """Consecutive identical readings (stuck data): the longest run and where it lies.

    `add(key, t)` takes a value that compares equal exactly when two readings are identical
    (bytes, a tuple of floats) and the reading's time in the window (s). `finding()` gives
    None or the text of a run of at least `limit` identical readings, naming when it began
    ("from t = 4.1 s to the end of the window"): a stream that stops changing partway through
    says so. Cheap: one comparison per message, no copies beyond the key the caller made.
    """

    __slots__ = ('limit', 'last', 'run', 'start', 'longest', 'longest_from', 'longest_to',
                 'last_t')

    def __init__(self, limit: Optional[int]) -> None:
        self.limit = limit
        self.last: Hashable = None
        self.run = 0
        self.start: Optional[float] = None
        self.last_t: Optional[float] = None
        self.longest = 0
        self.longest_from: Optional[float] = None
        self.longest_to: Optional[float] = None

    def add(self, key: Hashable, t: float) -> None:
        same = bool(self.run) and key == self.last
        if not same:
            self.last = key
        self.repeat(same, t)

    def repeat(self, same: bool, t: float) -> None:
        """`add` for a caller that compares the readings itself (images: same_bytes): `same`
        when this reading is identical to the previous one."""
        if same and self.run:
            self.run += 1
        else:
            self.run, self.start = 1, t
        self.last_t = t
        if self.run > self.longest:
            self.longest, self.longest_from, self.longest_to = self.run, self.start, t

    def to_end(self) -> bool:
        """True when the longest run lasts until the last reading."""
        return self.longest_to == self.last_t and self.run == self.longest

    def reached(self) -> bool:
        """True when the longest run is at least `limit` readings long."""
        return self.longest >= self.limit if self.limit else False

    def span(self) -> str:
        """Where the longest run lies: 'from t = A s to t = B s' or 'from t = A s to the end
        of the window'."""
        where = ('to the end of the window' if self.to_end()
                 else 'to t = %s s' % fmt(self.longest_to, 2))
        return 'from t = %s s %s' % (fmt(self.longest_from, 2), where)

    def finding(self, what: str, key_name: str) -> Optional[str]:
        """'N identical <what> in a row from t = A s to the end of the window (<key_name> L)'."""
        if not self.limit or self.longest < self.limit:
            return None
        return ('%d identical %s in a row %s (%s %d)'
                % (self.longest, what, self.span(), key_name, self.limit))


def same_bytes(last: Optional['np.ndarray'], data: 'np.ndarray') -> bool:
    """Whether `data` (an image's bytes as a uint8 array) is byte-for-byte `last` (the previous
    image's, or None): about 900 bytes spread over the image are compared first (a changing
    image differs there), and only when they match, every byte. The arrays' own comparison,
    so that checks without images do not import numpy."""
    if last is None or len(last) != len(data):
        return False
    stride = max(1, len(data) // 900)
    return bool((last[::stride] == data[::stride]).all()) and bool((last == data).all())


class TrailingRun:
    """A condition (black, silent, all zero) that holds from some time to the end of the
    window: `add(bad, t)` per reading; `since()` is the time the last unbroken run of bad
    readings began when it lasts to the end, with its length in readings and in seconds."""

    __slots__ = ('start', 'n', 'last_t')

    def __init__(self) -> None:
        self.start: Optional[float] = None
        self.n = 0
        self.last_t: Optional[float] = None

    def add(self, bad: bool, t: float) -> None:
        if bad:
            if not self.n:
                self.start = t
            self.n += 1
        else:
            self.start, self.n = None, 0
        self.last_t = t

    def since(self) -> Optional[Tuple[Optional[float], int, float]]:
        """(start t, readings, seconds) of a run lasting to the last reading, or None."""
        if not self.n:
            return None
        return self.start, self.n, (self.last_t or 0.0) - (self.start or 0.0)
