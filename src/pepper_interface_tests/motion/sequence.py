"""The motion check's run sequence: listen, check, (ask), move step by step, stop.

1. listen `witness_wait` s to the witnesses (their first messages);
2. the checks before moving (safety.py): the base part is SKIPPED with a reason when the base
   may not move, the head part when the head is not stiff;
3. on a terminal without --yes, the person is told what will happen and confirms with Enter
   (`s` skips the motion check): `confirm` is given by the check (sensors/motion.py);
4. the steps, each sent once and waited for until it settles (the witnesses unchanged for
   `settle_time` s) or `step_timeout` s: HeadYaw to start + head_yaw, start - head_yaw, start;
   the base turns by +base_turn, then -base_turn (it ends where it started); a base that did
   not take the first turn (no witness moved) is not sent the turn back;
5. `abort(why)` at any moment (Ctrl-C, SIGTERM, a lost master, a bumper, an obstacle, an
   error): a zero /cmd_vel at once, no further goal, the head sent back to its start; then the
   commands are closed and nothing is ever sent again.
"""
from dataclasses import dataclass, field
from typing import Callable, List, Optional

from ..plan.expectations import MotionExpect
from . import estimate, safety
from .commands import Commands
from .record import WHEELS, Recording

MIN_STEP = 1.5      # s before a step may count as settled (ALMotion takes a moment to start)
HEAD_LATENCY = 0.3  # s before ALMotion's setAngles is under way (a joint state or two later)
# HeadYaw's maximum speed (rad/s): pepper_description pepper.urdf line 15 (sensors/joint_limits.py)
HEAD_YAW_SPEED = 7.33998
# rad/s a turn in place is expected at, at least: ALMotion turns the base at up to ~1 rad/s by
# default (its move config); 0.3 leaves room for its acceleration and a slow start
BASE_SPEED = 0.3
# rad: a witness changing less than this over settle_time has settled (encoder noise and a
# head's last creep stay below it; a 0.5 rad step at 0.1 speed moves ~0.7 rad/s)
STILL = 0.03


@dataclass
class Step:
    part: str               # 'head' or 'base'
    target: float           # head: absolute HeadYaw; base: the relative turn
    commanded: float        # the change of yaw commanded (rad)
    sent: Optional[float] = None
    ended: Optional[float] = None
    settled: bool = False

    def label(self) -> str:
        if self.part == 'head':
            return 'head yaw to %+.2f rad' % self.target
        return 'base turn %+.2f rad' % self.target


@dataclass
class Sequence:
    expect: MotionExpect
    rec: Recording
    commands: Commands
    clock: Callable[[], float]
    started: float = 0.0
    state: str = 'listen'   # listen, confirm, move, done, stopped
    steps: List[Step] = field(default_factory=list)
    index: int = 0
    head_skip: Optional[str] = None
    base_skip: Optional[str] = None
    stopped: Optional[str] = None    # where and why a motion was stopped
    head_start: Optional[float] = None
    head_moved = False

    def begin(self) -> None:
        self.started = self.clock()

    # ---------------------------------------------------------------- before moving
    def prepare(self, heard_laser: bool, heard_sonar: bool, heard_joints: bool) -> None:
        """Decide the steps from what the witnesses said during witness_wait."""
        e = self.expect
        self.head_start = self.rec.latest_joint('HeadYaw')
        if e.head_yaw <= 0:
            self.head_skip = 'head_yaw is 0 in the expectations file'
        elif not heard_joints or self.head_start is None:
            self.head_skip = ('no HeadYaw in the joint states: the head\'s start is unknown, so it '
                              'is not moved')
        else:
            self.head_skip = safety.head_blocked(self.rec, e.min_stiffness)
        if e.base_turn <= 0:
            self.base_skip = 'base_turn is 0 in the expectations file'
        else:
            self.base_skip = safety.base_blocked(self.rec, e.clearance, e.min_stiffness,
                                                 heard_laser, heard_sonar)
        if self.head_skip is None and self.head_start is not None:
            h0, a = self.head_start, e.head_yaw
            for target, prev in ((h0 + a, h0), (h0 - a, h0 + a), (h0, h0 - a)):
                self.steps.append(Step('head', target, target - prev))
        if self.base_skip is None:
            t = e.base_turn
            self.steps += [Step('base', t, t), Step('base', -t, -t)]

    def plan_text(self) -> str:
        """What will happen, in words (said on the terminal and through /speech)."""
        e = self.expect
        parts = []
        if self.head_skip is None:
            parts.append('turn my head %.0f degrees to the left, then to the right, and back'
                         % (e.head_yaw * 57.2958))
        if self.base_skip is None:
            parts.append('turn in place %.0f degrees to the left and back' % (e.base_turn * 57.2958))
        return 'I will %s, slowly.' % '; then '.join(parts) if parts else ''

    # ---------------------------------------------------------------- moving
    def _send(self, step: Step) -> None:
        e = self.expect
        step.sent = self.clock()
        if step.part == 'head':
            self.head_moved = True
            self.commands.head(step.target, e.head_speed)
        else:
            self.commands.turn(step.target)

    def expected(self, step: Step) -> float:
        """Seconds the step should take: HeadYaw at head_speed x its maximum speed, the base at
        BASE_SPEED (ALMotion's turns are slower than its maximum)."""
        if step.part == 'head':
            return abs(step.commanded) / (self.expect.head_speed * HEAD_YAW_SPEED)
        return abs(step.commanded) / BASE_SPEED

    def _settled(self, step: Step, now: float) -> bool:
        """The head reached its target; or the witnesses are quiet for settle_time after having
        moved; or they never moved within the step's expected time (+ MIN_STEP + settle_time),
        which is how a part that does not move ends its step before step_timeout."""
        e = self.expect
        assert step.sent is not None
        took = now - step.sent
        # at its target, and no sooner than the head can be there (a stuck encoder reading the
        # start angle would otherwise end the step back to the start at once)
        if step.part == 'head' and took >= self.expected(step) + HEAD_LATENCY:
            h = self.rec.latest_joint('HeadYaw')
            if h is not None and abs(h - step.target) <= e.joint_tolerance / 2:
                return True
        if took < MIN_STEP:
            return False
        if took >= self.expected(step) + MIN_STEP + e.settle_time and not self._moved(step, now):
            return True
        since = now - e.settle_time
        if since < step.sent:
            return False
        for series in self._recent(step, since):
            if len(series) >= 2 and max(series) - min(series) > STILL:
                return False
        return self._moved(step, now)

    def _moved(self, step: Step, now: float) -> bool:
        """A witness changed by still_share of the command since the step was sent."""
        assert step.sent is not None
        least = self.expect.still_share * abs(step.commanded)
        return any(series and abs(series[-1] - series[0]) >= least
                   for series in self._recent(step, step.sent - 0.3))

    def _recent(self, step: Step, since: float) -> List[List[float]]:
        if step.part == 'head':
            return [[v for _, v in self.rec.joint_series('HeadYaw', since)]]
        with self.rec.lock:
            odom = [v for t, v in self.rec.odom_yaw if t >= since]
            gyro = estimate.gyro_series(self.rec.gyro, since)
        out = [odom, [v for _, v in gyro]]
        for w in WHEELS:
            out.append([v for _, v in self.rec.joint_series(w, since)])
        return out

    def poll(self, now: float) -> None:
        """Advance: send the next step once the current one has settled; stop the base when it
        must stop (safety.stop_reason)."""
        if self.state != 'move':
            return
        if self.index >= len(self.steps):
            self.state = 'done'
            return
        step = self.steps[self.index]
        if step.sent is None:
            self._send(step)
            return
        if step.part == 'base':
            why = safety.stop_reason(self.rec, self.expect.stop_distance)
            if why:
                self.abort(why, now)
                return
        if self._settled(step, now) or now - step.sent >= self.expect.step_timeout:
            step.ended = now
            step.settled = now - step.sent < self.expect.step_timeout
            self.index += 1
            if step.part == 'base' and not self._moved(step, now):
                # a base that did not take the turn is not sent the turn back: were the block
                # to lift (a hatch closed, an obstacle gone), the robot would end away from
                # where it started
                self.steps = self.steps[:self.index]
            if self.index >= len(self.steps):
                self.state = 'done'
            else:
                self._send(self.steps[self.index])

    def current(self) -> Optional[Step]:
        if self.state == 'move' and self.index < len(self.steps) and self.steps[self.index].sent is not None:
            return self.steps[self.index]
        return None

    def abort(self, why: str, now: float) -> None:
        """Stop at once: a zero twist, no further goal, the head back to its start."""
        step = self.current()
        self.commands.stop()
        done = 'the base was stopped (zero /cmd_vel)'
        if self.head_moved and self.head_start is not None:
            self.commands.head(self.head_start, self.expect.head_speed)
            done += ' and the head sent back to its start'
        if step is not None:
            step.ended = now
            took = now - step.sent if step.sent is not None else 0.0
            self.stopped = ('stopped during "%s" (%.1f s into the step): %s; %s'
                            % (step.label(), took, why, done))
        elif self.state in ('listen', 'confirm'):
            self.stopped = 'stopped before moving: %s' % why
        else:
            self.stopped = 'stopped: %s' % why
        self.state = 'stopped'

    def finish(self, interrupted_by: Optional[str] = None) -> None:
        """The end of the check's window: a motion still under way is stopped (saying why: the
        run's interrupt, or the window's end); then nothing is ever sent again."""
        if self.state == 'move':
            self.abort(interrupted_by or 'the check\'s window ended', self.clock())
        self.commands.close()
