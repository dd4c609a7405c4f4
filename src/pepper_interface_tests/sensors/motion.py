"""Motion (--move): Pepper turns its head and its base by small known amounts, and every motion
sensor must agree with the motion and with each other. Its home is motion/ (the plan's steps,
the commands, the witnesses, the safety, the rules: their docstrings state each rule with its
upstream source); this Check drives it from the runner's tick and hands its findings over:
on the other sensors' rows through RunContext.findings (it leads: Traits.leads, so every other
window opens after it), and on its own row, `motion`, the verdict of motion/rules.py.

Live only (a bag has nothing to command: plan/settings.py refuses --move with --bag). On a
terminal without --yes, the plan is said (on the terminal and through /speech) and the person
confirms with Enter (`s` skips). Closing the window at any moment (the end, Ctrl-C, SIGTERM, a
lost master) goes through motion/sequence.py `finish`: a motion under way is stopped (zero
/cmd_vel, no further goal, the head sent back) and nothing is sent afterwards.
"""
import select
import shutil
import sys
import textwrap
import time
from typing import TYPE_CHECKING, Any, List, Optional

from ..motion import rules
from ..motion.commands import Commands
from ..motion.record import Recording
from ..motion.sequence import Sequence
from ..motion.witnesses import Witnesses, heard_of
from . import motion_pc
from .base import Check
from .values.motion import MotionValues, StepValues

if TYPE_CHECKING:
    from ..plan.expectations import MotionExpect
    from ..plan.settings import SensorPlan
    from .base import RunContext

CONFIRM_WAIT = 120.0    # s a person has to press Enter before the motion is skipped
# s the checks before moving wait beyond witness_wait for naoqi_driver's first /diagnostics
# (the joints' Stiffness) when the run listens to it: it comes at 1 Hz (naoqi_driver
# share/boot_config.json "diag" "frequency": 1), so three periods, which leaves room for a
# subscription that connects late on a loaded machine. Deciding without it would send a
# resting robot commands it ignores, and call its base broken.
DIAGNOSTICS_WAIT = 3.0


def _asks(ctx: 'RunContext') -> bool:
    """Ask before moving: a terminal on both ends and no --yes."""
    if ctx.options.yes:
        return False
    try:
        return sys.stdin.isatty() and sys.stdout.isatty()
    except (AttributeError, ValueError):
        return False


class MotionCheck(Check):
    family = 'motion'
    expect: 'MotionExpect'
    found: Optional[MotionValues]

    def __init__(self, plan: 'SensorPlan', ctx: 'RunContext') -> None:
        super().__init__(plan, ctx)
        self.clock = time.monotonic
        self.rec = Recording()
        self.commands: Optional[Commands] = None
        self.witnesses: Optional[Witnesses] = None
        self.seq: Optional[Sequence] = None
        self.asked_at: Optional[float] = None
        self.operator_skip = False
        self.skip_text: Optional[str] = None
        self.pc: Optional[motion_pc.PcWatch] = None
        self._done = False

    def window(self, duration: float) -> float:
        e = self.expect
        return (e.witness_wait + DIAGNOSTICS_WAIT + 5 * e.step_timeout
                + (CONFIRM_WAIT if _asks(self.ctx) else 0.0))

    def start(self) -> None:
        self.commands = Commands(self.clock)
        self.witnesses = Witnesses(dict(self.ctx.topics), self.rec, self.clock)
        self.seq = Sequence(self.expect, self.rec, self.commands, self.clock)
        self.pc = motion_pc.PcWatch(self.clock)
        self.seq.begin()

    def done(self) -> bool:
        return self._done

    def poll(self, elapsed: float) -> None:
        seq = self.seq
        if seq is None or self._done:
            return
        try:
            self._poll(seq, elapsed)
        except Exception as e:   # any error during a motion stops it first
            seq.abort('error: %s: %s' % (type(e).__name__, e), self.clock())
            self._done = True
            raise

    def _awaits_diagnostics(self, elapsed: float) -> bool:
        """Still waiting for the joints' stiffness: the run listens to /diagnostics, none of its
        joint statuses has come yet, and DIAGNOSTICS_WAIT has not run out."""
        w = self.witnesses
        listens = w is not None and 'robotHealth' in w.topics
        return (listens and not self.rec.stiffness
                and elapsed < self.expect.witness_wait + DIAGNOSTICS_WAIT)

    def _poll(self, seq: Sequence, elapsed: float) -> None:
        now = self.clock()
        if self.pc is not None:
            self.pc.poll(now)
        if seq.state == 'listen':
            if elapsed < self.expect.witness_wait:
                return
            if self._awaits_diagnostics(elapsed):
                return
            seq.prepare(bool(heard_of(self.rec, 'laser')),
                        bool(heard_of(self.rec, 'frontSonar') or heard_of(self.rec, 'backSonar')),
                        bool(heard_of(self.rec, 'jointState')))
            if not self.rec.stiffness:
                self.notes.append('stiffness not checked before moving: no naoqi_driver joint status '
                                  '(Stiffness) arrived on /diagnostics within %.1f s'
                                  % elapsed)
            if not seq.steps:
                self._done = True
                seq.state = 'done'
                return
            assert self.commands is not None
            missing = self.commands.missing()
            if missing:
                self.notes.append('no subscriber yet on %s when the motion began (naoqi_driver '
                                  'subscribes to all three: naoqi_driver.cpp:937-938)' % ', '.join(missing))
            if _asks(self.ctx):
                self._ask(seq)
                seq.state = 'confirm'
                return
            seq.state = 'move'
        if seq.state == 'confirm':
            answer = self._answer()
            if answer is None:
                if self.asked_at is not None and now - self.asked_at > CONFIRM_WAIT:
                    self._skip(seq, 'nobody pressed Enter within %.0f s' % CONFIRM_WAIT)
                return
            self.waits_for_answer = False
            if answer.strip().lower().startswith('s'):
                self._skip(seq, 'skipped by the operator')
                return
            seq.state = 'move'
        if seq.state == 'move':
            seq.poll(now)
            assert self.commands is not None
            self.count = len(self.commands.sent)      # the progress line's "N sent"
        if seq.state in ('done', 'stopped'):
            self._done = True

    def _skip(self, seq: Sequence, why: str) -> None:
        self.waits_for_answer = False
        self.operator_skip = True
        seq.head_skip = seq.head_skip or why
        seq.base_skip = seq.base_skip or why
        seq.steps = []
        seq.state = 'done'
        self._done = True

    def _ask(self, seq: Sequence) -> None:
        text = seq.plan_text()
        skipped = [p for p, s in (('head', seq.head_skip), ('base', seq.base_skip)) if s]
        said = ['sensorTest --move: ' + text]
        for p in skipped:
            said.append('  (the %s stays still: %s)' % (p, seq.head_skip if p == 'head' else seq.base_skip))
        said.append('  Keep the space around the robot clear. Press Enter to start, s then Enter to skip.')
        # broken at spaces to the terminal's width ($COLUMNS first), as the guided check's prompts
        width = max(40, shutil.get_terminal_size((80, 24)).columns)
        lines = ['']
        for text_line in said:
            lines += textwrap.wrap(text_line, width, subsequent_indent='    ', break_on_hyphens=False)
        # the progress line on the cursor's row is cleared first, and none is drawn while the
        # question waits (self.waits_for_answer -> Progress.asking: outputs/terminal.py prints nothing)
        self.waits_for_answer = True
        sys.stdout.write('\r\033[K' + '\n'.join(lines) + '\n')
        sys.stdout.flush()
        self._say(text)
        self.asked_at = self.clock()

    def _say(self, text: str) -> None:
        topic = self.ctx.topics.get('speech')
        if not topic or not text:
            return
        try:
            from .. import rosapi
            pub = rosapi.publisher(topic, 'std_msgs/String', queue_size=1, latch=True)
            pub.publish(rosapi.msg('std_msgs/String')(data=text))
        except Exception:  # saying it is a courtesy; the terminal said it
            pass

    @staticmethod
    def _answer() -> Optional[str]:
        try:
            ready, _, _ = select.select([sys.stdin], [], [], 0)
        except (ValueError, OSError):
            return ''
        return sys.stdin.readline() if ready else None

    # ---------------------------------------------------------------- the end
    def finish(self) -> None:
        self.waits_for_answer = False
        seq = self.seq
        if seq is None:
            return
        if seq.state in ('listen', 'confirm') and not self._done:
            seq.head_skip = seq.head_skip or 'the run ended before the motion began'
            seq.base_skip = seq.base_skip or 'the run ended before the motion began'
            seq.steps = []
        try:
            # a motion under way is stopped, saying why; nothing is sent afterwards
            seq.finish(self.ctx.interrupted_by)
        finally:
            if self.witnesses is not None:
                self.witnesses.close()
        if self.commands is not None:
            self.count = len(self.commands.sent)
        judge = rules.Judge(seq, self.rec, self.expect, self.ctx.findings.add)
        fails, warns, skip = judge.judge()
        for r in fails:
            self.fail(r)
        for w in warns:
            self.warn(w)
        # a skip that a busy PC can cause says so, naming the load and the lag (sensors/motion_pc.py)
        pc = self.pc.busy(self.rec, self.expect.settle_time) if self.pc is not None else None
        self.skip_text = motion_pc.explain(skip, pc)
        self.notes += ['head: %s' % judge.head_state, 'base: %s' % judge.base_state]
        self.notes += ['%s %.2f s: %s' % (topic, t - seq.started, text)
                       for t, topic, text in (self.commands.sent if self.commands else [])]
        self.found = self._values(seq, judge)

    def skip_reason(self) -> Optional[str]:
        return self.skip_text

    def said_on_interrupt(self) -> List[str]:
        return [self.seq.stopped] if self.seq is not None and self.seq.stopped else []

    def _values(self, seq: Sequence, judge: Any) -> MotionValues:
        t0 = seq.started
        steps = []
        for i, s in enumerate(judge.completed()):
            steps.append(StepValues(s.part, round(s.commanded, 4), round((s.sent or t0) - t0, 3),
                                    round((s.ended or t0) - t0, 3), s.settled,
                                    {k: (None if v is None else round(v, 4))
                                     for k, v in judge.measured.get(i, {}).items()}))
        return MotionValues(head=judge.head_state, base=judge.base_state, stopped=seq.stopped,
                            steps=steps, **rules.plot_series(seq, self.rec))
