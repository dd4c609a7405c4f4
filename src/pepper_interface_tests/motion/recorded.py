"""The motion rules on a recording (a ROS 1 bag or a ROS 2 recording, issue 25 point 4): where
the robot turned its base or yawed its head, the very rules of a --move run (rules.Judge) judge
each witness, with the witnesses' vote in place of the command.

A recording has no command, so the motion is found in the recording itself:
- base turns: the stretches where any base witness moves (odometry's yaw, the gyro on any axis,
  the laser's scan turning, the wheel joints) faster than MOVING_RATE, merged across gaps
  shorter than MERGE_GAP and widened by PAD on each side (the scan before the turn, the
  settling after it). Each stretch is a step whose "command" is the vote of the signed
  witnesses (odometry's yaw change, the integrated gyro z, the laser's turn): the sign most of
  them saw, and the median size of those with that sign. Then rules.Judge.base_step votes and
  judges exactly as live: a witness that disagrees with the majority is the broken one.
  Judged only with at least MIN_WITNESSES witnesses (two cannot tell which one is wrong:
  sensors/cross.py's two-witness warning stays for those) and when the signed witnesses do not
  split evenly on the sign; a stretch whose largest turn is below cross.RECORDED_TURN is a
  wobble, not a turn.
- head yaw moves: the stretches where HeadYaw (joint_states) moves faster than HEAD_RATE,
  at least HEAD_MIN_MOVE in all; the encoder is the reference (nothing else measures the
  head's yaw), so the rule judged is the cameras' (rules.Judge.head_step: the picture must
  follow the head, the right way). A head move during a base turn is left out (the pictures
  then move for both reasons). The head's speed for the frame-gap rule is its mean speed over
  the stretch (the move over the time HeadYaw moved).
Rates are taken over RATE_SPAN s at least.

The times are the recording's (record times); the rules' margins are MotionExpect's defaults.
"""
import collections
import dataclasses
import statistics
from typing import Any, Deque, Dict, List, Mapping, Optional, Sequence, Tuple

from ..plan.expectations import MotionExpect
from ..sources.handling import Handling
from ..sources.witness import TopicWitness
from . import estimate
from .record import WHEELS, Recording
from .rules import Judge
from .sequence import HEAD_YAW_SPEED, Step
from .witnesses import FRAME_PERIOD, HEAD_CAMERAS, Recorder

MOVING_RATE = 0.1     # rad/s: ALMotion turns at up to 1 rad/s; a still robot's gyro reads ~0.01
# rad/s of HeadYaw: a commanded yaw at the slowest useful speed (0.05 of 7.34 rad/s) moves 0.37;
# the head's idle sway (Autonomous Life's "breathing", the fake NAOqi's too) about 0.1
HEAD_RATE = 0.3
RATE_SPAN = 0.2       # s: a rate is measured over at least this
MERGE_GAP = 1.0       # s: a pause shorter than this is one motion
PAD = 0.5             # s either side of a stretch
MIN_WITNESSES = 3     # base witnesses needed to vote
RECORDED_TURN = 0.3   # rad: a turn, not a wobble (as sensors/cross.py RECORDED_TURN)
HEAD_MIN_MOVE = 0.2   # rad of HeadYaw: a move the cameras see (a 0.2 rad yaw slides ~16 of 80 px)
WHEEL_RATE = 0.5      # rad/s of the three wheels' summed spin (a 0.1 rad/s base turn spins ~0.7)
BASE_ROWS = ('jointState', 'odometry', 'imu', 'laser')
HEAD_ROWS = ('jointState',) + HEAD_CAMERAS
ROLES = BASE_ROWS + HEAD_CAMERAS
# s either side of HeadYaw moving: the head cameras' frames converted (a head step starts PAD
# before the first rate over RATE_SPAN that passes HEAD_RATE, and is judged from the frame before
# it: 0.7 s plus a frame's gap; 2 s leaves room for a loaded robot's 1.3 fps)
KEEP_AROUND = 2.0
# m the base may travel during a turn for the laser to be judged on it: scan_turn matches a
# turn in place (a --move turn); a robot driving while it turns changes its distances too
# (0.1 m: a tenth of the beams' typical 1-3 m, the size of the rule's own tolerance)
MAX_TRAVEL = 0.1

Span = Tuple[float, float]


class RecordedWitness(TopicWitness):
    """One witness topic of a recording, fed by the source (a sources.Listener) into `recorder`;
    a head camera's messages go undecoded to LeanRecorder.raw_frame."""

    buff_size = 1 << 22

    def __init__(self, role: str, topic: str, recorder: 'LeanRecorder') -> None:
        super().__init__(topic, recorder.handlers[role][0]._type)
        self.role, self.recorder = role, recorder

    def feed_raw(self, type_name: str, buff: bytes, t_recv: float, ros_now: float,
                 conn: Optional[Dict[str, Any]] = None, own: Optional[Handling] = None) -> None:
        if self.role not in HEAD_CAMERAS:
            super().feed_raw(type_name, buff, t_recv, ros_now, conn, own)
        elif type_name == self.type_name:
            self.recorder.raw_frame(self.role, buff, t_recv)

    def take(self, msg: Any, t_recv: float) -> None:
        self.recorder.handle(self.role, msg, t_recv)


class LeanRecorder(Recorder):
    """The witnesses' handlers, bounded for a recording of any length, and no dearer than the
    motion in it: of /joint_states only HeadYaw and the wheels are kept, and a head camera's
    frame is decoded and made small only when HeadYaw moves faster than HEAD_RATE within
    KEEP_AROUND s of it. The cheap witness decides: a frame waits undecoded (the bytes the
    source read, no copy) until HeadYaw moves, which converts the waiting frames within
    KEEP_AROUND s, or until it is KEEP_AROUND s old, when it is dropped unread. A recording
    whose head never moves converts no frame (ten minutes of four cameras would otherwise cost
    a conversion per frame and ~400 MB of small frames)."""

    def __init__(self, recording: Recording) -> None:
        super().__init__(recording)
        self.keeps: List[List[float]] = []     # [from, to]: frames converted for a head move
        self.waiting: Dict[str, Deque[Tuple[float, bytes]]] = {}   # camera -> undecoded frames
        self.taken: Dict[str, float] = {}      # camera -> time of the last frame taken
        self.head: Deque[Tuple[float, float]] = collections.deque(maxlen=30)   # the last HeadYaws

    def _joints(self, role: str, msg: Any, t: float) -> None:
        kept = {n: p for n, p in zip(msg.name, msg.position) if n == 'HeadYaw' or n in WHEELS}
        self.rec.joints.append((t, kept))
        if 'HeadYaw' not in kept:
            return
        self.head.append((t, kept['HeadYaw']))
        if _moving(self.head, HEAD_RATE, angle=False):
            if self.keeps and self.keeps[-1][1] >= t - KEEP_AROUND:
                self.keeps[-1][1] = t + KEEP_AROUND
            else:
                self.keeps.append([t - KEEP_AROUND, t + KEEP_AROUND])
            self._convert_waiting()

    def raw_frame(self, role: str, buff: bytes, t: float) -> None:
        """A head camera's serialized sensor_msgs/Image at time t: at most one every
        FRAME_PERIOD s is taken; converted now when HeadYaw moved within KEEP_AROUND s, else
        left waiting."""
        with self.rec.lock:
            self.rec.count(role)
            if role in self.taken and t - self.taken[role] < FRAME_PERIOD:
                return
            self.taken[role] = t
            waiting = self.waiting.setdefault(role, collections.deque())
            while waiting and waiting[0][0] < t - KEEP_AROUND:
                waiting.popleft()        # HeadYaw did not move within KEEP_AROUND s of it
            if self.keeps and self.keeps[-1][1] >= t:
                self._convert(role, buff, t)
            else:
                waiting.append((t, buff))

    def _convert_waiting(self) -> None:
        """HeadYaw moves: the waiting frames from the start of its keep on are converted, the
        older ones can be in no later keep (each starts KEEP_AROUND s before its motion)."""
        start = self.keeps[-1][0]
        for role, waiting in self.waiting.items():
            while waiting:
                t, buff = waiting.popleft()
                if t >= start:
                    self._convert(role, buff, t)

    def _convert(self, role: str, buff: bytes, t: float) -> None:
        try:
            msg = self.handlers[role][0]().deserialize(bytes(buff))   # a Ros2Image too
        except Exception:   # a broken message: that camera's own row says so
            return
        self._frame(role, msg, t)


def listeners(topics: Mapping[str, str], rec: Recording,
              selected: Optional[Sequence[str]] = None) -> List[RecordedWitness]:
    """A listener per witness role the run's topics name, all feeding `rec`. With `selected`
    (the run's sensors): none unless a motion witness's row is selected; then every base
    witness (they vote for each other's rows) and the head cameras that are selected (a camera
    is judged on its own row only: a run without one reads no images for this)."""
    roles = list(ROLES)
    if selected is not None:
        if not set(selected) & set(ROLES):
            return []
        roles = [r for r in ROLES if r in BASE_ROWS or r in selected]
    recorder = LeanRecorder(rec)
    return [RecordedWitness(role, topics[role], recorder) for role in roles if topics.get(role)]


def _moving(series: Sequence[Tuple[float, float]], rate: float, angle: bool = True) -> List[Span]:
    """The stretches where the series changes faster than `rate`, each rate taken over at least
    RATE_SPAN s (record times come in bunches: two messages a millisecond apart say nothing)."""
    out = []
    i = 0
    for tb, b in series:
        while i + 1 < len(series) and series[i + 1][0] <= tb - RATE_SPAN:
            i += 1
        ta, a = series[i]
        if tb - ta < RATE_SPAN:
            continue
        d = estimate.wrap(b - a) if angle else b - a
        if abs(d) / (tb - ta) > rate:
            out.append((ta, tb))
    return out


def _merge(spans: List[Span], gap: float, pad: float) -> List[Span]:
    out: List[List[float]] = []
    for a, b in sorted(spans):
        if out and a - out[-1][1] <= gap:
            out[-1][1] = max(out[-1][1], b)
        else:
            out.append([a, b])
    return [(a - pad, b + pad) for a, b in out]


def _cumulative(steps: Sequence[Tuple[float, float]], t0: float) -> List[Tuple[float, float]]:
    out, total = [(t0, 0.0)], 0.0
    for t, d in steps:
        total += d
        out.append((t, total))
    return out


def base_spans(rec: Recording) -> List[Span]:
    """Where the base moved, by any witness (each rate over RATE_SPAN s at least)."""
    spans = _moving(rec.odom_yaw, MOVING_RATE)
    for k in range(1, 4) if len(rec.gyro) > 1 else ():    # any axis: a swapped one too
        turned = [(b[0], 0.5 * (a[k] + b[k]) * (b[0] - a[0])) for a, b in zip(rec.gyro, rec.gyro[1:])]
        spans += _moving(_cumulative(turned, rec.gyro[0][0]), MOVING_RATE, angle=False)
    if len(rec.scans) > 1:
        turns = [(b.t, estimate.scan_turn(a.ranges, b.ranges, a.increment) or 0.0)
                 for a, b in zip(rec.scans, rec.scans[1:])]
        spans += _moving(_cumulative(turns, rec.scans[0].t), MOVING_RATE, angle=False)
    wheels = [(t, p) for t, p in rec.joints if all(w in p for w in WHEELS)]
    if len(wheels) > 1:
        travel = [(tb, sum(abs(estimate.wrap(pb[w] - pa[w])) for w in WHEELS))
                  for (ta, pa), (tb, pb) in zip(wheels, wheels[1:])]
        spans += _moving(_cumulative(travel, wheels[0][0]), WHEEL_RATE, angle=False)
    return _merge(spans, MERGE_GAP, PAD)


def head_spans(rec: Recording) -> List[Span]:
    return _merge(_moving(rec.joint_series('HeadYaw'), HEAD_RATE, angle=False), MERGE_GAP / 2, PAD)


class _Run:
    """What rules.Judge reads of a --move run, for a recording (no command, no motion row)."""

    def __init__(self, steps: List[Step]) -> None:
        self.steps, self.index = steps, len(steps)
        self.head_skip = self.base_skip = self.stopped = None


def _vote_turn(j: Judge, i: int, span: Span) -> Optional[float]:
    """The turn the signed witnesses vote for over `span` (None: too few, or a tie on the sign)."""
    probe = Step('base', 1.0, 1.0, span[0], span[1])
    j.base_step(i, probe)          # only to measure: its findings are dropped
    m = j.measured.get(i, {})
    j.found.clear()
    j.warned.clear()
    present = [k for k in ('odometry', 'gyro_z', 'laser', 'wheels') if m.get(k) is not None]
    if len(present) < MIN_WITNESSES:
        return None
    signed = [v for v in (m.get('odometry'), m.get('gyro_z'), m.get('laser')) if v is not None]
    if max((abs(v) for v in signed), default=0.0) < RECORDED_TURN:
        return None
    big = max(abs(v) for v in signed)
    seen = [v for v in signed if abs(v) >= 0.2 * big]
    up, down = [v for v in seen if v > 0], [v for v in seen if v < 0]
    if len(up) == len(down):
        return None
    return statistics.median(up if len(up) > len(down) else down)


def judge(rec: Recording, expect: Optional[MotionExpect] = None
          ) -> Tuple[Dict[str, List[str]], Dict[str, List[str]], Dict[str, List[str]]]:
    """(fail reasons, warnings, notes: the motion found), each by sensor, of a recording."""
    e = expect or MotionExpect()
    j = Judge(_Run([]), rec, e, lambda *a: None)   # type: ignore[arg-type]
    notes: Dict[str, List[str]] = {}
    bases = base_spans(rec)
    found: Dict[str, List[str]] = {}
    warned: Dict[str, List[str]] = {}
    for i, span in enumerate(bases):
        travel = _travel(rec, span)
        if travel > MAX_TRAVEL and rec.scans:     # not a turn in place: the laser cannot tell
            j.rec = dataclasses.replace(rec, scans=[])
        turn = _vote_turn(j, i, span)
        if turn is not None:
            j.base_step(i, Step('base', turn, turn, span[0], span[1]))
        j.rec = rec
        if turn is None:
            continue
        if travel > MAX_TRAVEL and rec.scans:
            _note(notes, ('laser',), 'the recorded base turn of %+.2f rad was not a turn in place '
                  '(odometry: %.2f m travelled): the laser is not judged on it' % (turn, travel))
        _note(notes, BASE_ROWS, 'recorded base turn of %+.2f rad (the witnesses\' vote) from %.1f '
              'to %.1f s into the recording' % (turn, _since(rec, span[0]), _since(rec, span[1])))
        _collect(j, found, warned, 'the recorded base turn of %+.2f rad: ' % turn)
    for i, span in enumerate(head_spans(rec), start=len(bases)):
        if any(a < span[1] and span[0] < b for a, b in bases):
            continue
        series = rec.joint_series('HeadYaw')
        moved = estimate.change(series, span[0], span[1], angle=False)
        if moved is None or abs(moved) < HEAD_MIN_MOVE:
            continue
        target = estimate.value_at(series, span[1]) or 0.0
        busy = _merge([m for m in _moving(series, HEAD_RATE, angle=False)
                       if span[0] <= m[0] and m[1] <= span[1]], 0.0, 0.0)
        speed = abs(moved) / max(sum(b - a for a, b in busy), RATE_SPAN) / HEAD_YAW_SPEED
        j.e = dataclasses.replace(e, head_speed=min(max(speed, 1e-3), 1.0))
        j.head_step(i, Step('head', target, moved, span[0], span[1]))
        j.e = e
        _note(notes, HEAD_ROWS, 'recorded head yaw of %+.2f rad (HeadYaw) from %.1f to %.1f s into '
              'the recording' % (moved, _since(rec, span[0]), _since(rec, span[1])))
        _collect(j, found, warned, 'the recorded head yaw of %+.2f rad: ' % moved)
    return found, warned, notes


def _travel(rec: Recording, span: Span) -> float:
    """How far odometry says the base went over the span (m; 0 without positions)."""
    pts = [(x, y) for t, x, y in rec.odom_xy if span[0] <= t <= span[1]]
    return sum(((b[0] - a[0]) ** 2 + (b[1] - a[1]) ** 2) ** 0.5 for a, b in zip(pts, pts[1:]))


def _note(notes: Dict[str, List[str]], rows: Sequence[str], text: str) -> None:
    for r in rows:
        notes.setdefault(r, []).append(text)


def _since(rec: Recording, t: float) -> float:
    """Seconds from the first witness message to t (the padding before it left out)."""
    starts = [s[0][0] for s in (rec.odom_yaw, rec.gyro, rec.joints) if s]
    return max(0.0, t - min(starts)) if starts else 0.0


def _collect(j: Judge, found: Dict[str, List[str]], warned: Dict[str, List[str]], prefix: str) -> None:
    for sensor, texts in j.found.items():
        found.setdefault(sensor, []).extend(prefix + t for t in texts)
    for sensor, texts in j.warned.items():
        warned.setdefault(sensor, []).extend(prefix + t for t in texts)
    j.found.clear()
    j.warned.clear()
