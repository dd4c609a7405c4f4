"""Touch sensors and bumpers (headTouch, handTouch, bumper): naoqi_driver's touch events.

What the driver publishes (ros-naoqi/naoqi_driver; the CSSR4Africa fork is the same):
- one message per change of an ALMemory touch event, pressed or released, and nothing at all
  while nobody touches the robot (src/event/touch.cpp:172-204: state = value > 0.5); the
  topics are not latched, so a zone pressed before the run began sends nothing;
- the index is the position of the event in the driver's own list, not the constant of the
  message file: HeadTouch.button 0 front, 1 middle, 2 rear (src/naoqi_driver.cpp:882-884)
  although HeadTouch.msg declares buttonFront=1 ... buttonRear=3; Bumper.bumper 0 right,
  1 left, 2 back (back only on Pepper, :842-846); HandTouch.hand 0-5 right back/left/right,
  left back/left/right (:862-867; Pepper's hands have the back sensors only);
- the state is Bumper/HandTouch/HeadTouch stateReleased 0 or statePressed 1
  (src/event/touch.cpp:214, 227, 240).

The rules, in every mode:
- an index outside the driver's list, or a state other than 0 / 1, fails naming the value;
- a zone pressed and not released within `max_press` s fails as stuck (a jammed bumper);
- a zone pressed again with no release in between is a warning (a lost release event).
Guided (a person is there: ctx.services.operator, sensors/guide.py): each zone the robot has
is asked for in turn and passes when its press and its release arrive; zones not pressed
within the per-zone time (--touch-wait) fail, named in one reason, and the person is told when
each is given up ("[headTouch/front] not pressed within 15 s, next zone", sensors/guide.py); a
zone pressed only after its wait is still a FAIL (the wait is the rule: the robot had moved on),
but its reason says what was seen ("pressed 4.2 s after the 15 s wait: touch sooner, or raise
--touch-wait"), since a working sensor and a slow person are not a dead sensor; a zone the
person skips from the keyboard is reported as skipped by the operator (a warning, SKIPPED when
every zone is).
A bumper jammed before the run is found here: its press never comes.
Unattended (no person: CI, a launch file, a bag): the events that arrive are judged; a sensor
with no event at all is SKIPPED ("not touched"), never failed for the lack of a person.
"""
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Tuple

from .base import Check, fmt
from .values.touch import TouchValues, ZoneRow

if TYPE_CHECKING:
    import genpy

    from ..plan.expectations import TouchExpect
    from ..plan.settings import SensorPlan
    from .base import Operator, RunContext

RELEASED, PRESSED = 0, 1     # stateReleased, statePressed of the three message files
LATE = 'too late: '          # the outcome of a zone pressed only after its wait
TOUCH_WAIT = 15.0            # s per zone in guided mode (--touch-wait): hear or read the prompt,
                             # walk round the robot to the back bumper, press


@dataclass(frozen=True)
class Zone:
    id: str          # the zone's word in ids and prompts: headTouch/front
    words: str       # "the front of the head"
    prompt: str      # "Touch the front of my head"
    asked: bool      # Pepper has it: asked for in guided mode


def _head(i: str, where: str) -> Zone:
    return Zone(i, 'the %s of the head' % where, 'Touch the %s of my head' % where, True)


def _hand(i: str, side: str, part: str, pepper: bool) -> Zone:
    return Zone(i, 'the %s of the %s hand' % (part, side), 'Touch the %s of my %s hand' % (part, side),
                pepper)


def _bumper(i: str, where: str) -> Zone:
    return Zone(i, 'the %s bumper' % where, 'Press my %s bumper' % where, True)


# message type -> (index field, the driver's list of zones in index order)
DRIVER_ZONES: Dict[str, Tuple[str, Tuple[Zone, ...]]] = {
    'HeadTouch': ('button', (_head('front', 'front'), _head('middle', 'middle'),
                             Zone('rear', 'the rear of the head', 'Touch the back of my head', True))),
    'HandTouch': ('hand', (_hand('rightBack', 'right', 'back', True),
                           _hand('rightLeft', 'right', 'left side', False),
                           _hand('rightRight', 'right', 'right side', False),
                           _hand('leftBack', 'left', 'back', True),
                           _hand('leftLeft', 'left', 'left side', False),
                           _hand('leftRight', 'left', 'right side', False))),
    'Bumper': ('bumper', (_bumper('right', 'front right'), _bumper('left', 'front left'),
                          _bumper('back', 'back'))),
}


def zones_of(msg_type: str) -> Tuple[str, Tuple[Zone, ...]]:
    """(index field, zones in the driver's order) of a touch message type (any package)."""
    return DRIVER_ZONES[msg_type.split('/')[-1]]


def asked_zones(msg_type: str) -> Tuple[Zone, ...]:
    """The zones guided mode asks for on Pepper."""
    return tuple(z for z in zones_of(msg_type)[1] if z.asked)


class _ZoneState:
    __slots__ = ('presses', 'pressed_at', 'released_at', 'first_press', 'first_release', 'last_press',
                 'outcome', 'stuck', 'wait_end', 'late_press')

    def __init__(self) -> None:
        self.presses = 0
        self.pressed_at: Optional[float] = None     # current press (None: released)
        self.released_at: Optional[float] = None    # last release
        self.first_press: Optional[float] = None
        self.first_release: Optional[float] = None
        self.last_press: Optional[float] = None      # the latest press
        self.outcome = ''
        self.stuck = False
        self.wait_end: Optional[float] = None       # its wait ended unpressed at (given up)
        self.late_press: Optional[float] = None     # the first press after that


class TouchCheck(Check):
    family = 'touch'
    expect: 'TouchExpect'
    queue_size = 50

    def __init__(self, plan: 'SensorPlan', ctx: 'RunContext') -> None:
        super().__init__(plan, ctx)
        self.found: Optional[TouchValues] = None
        self.field, self.zones = zones_of(plan.sensor.msg_type)
        self.state = [_ZoneState() for _ in self.zones]
        self.operator: Optional[Operator] = ctx.services.operator
        self.wait = ctx.options.touch_wait or TOUCH_WAIT
        self.now = 0.0
        self.order = [i for i, z in enumerate(self.zones) if z.asked]   # zones still to ask
        self.asking: Optional[int] = None
        self.asked_any = False
        self.topic = plan.topic or ''
        self.asked_at = 0.0
        self._done = False

    @property
    def guided(self) -> bool:
        return self.operator is not None

    def window(self, duration: float) -> float:
        return self.operator.budget if self.operator is not None else duration

    def _name(self, i: int) -> str:
        return '%s (%s %d)' % (self.zones[i].words, self.field, i)

    def fields(self, msg: 'genpy.Message') -> List[Tuple[str, Any]]:
        i, state = getattr(msg, self.field), msg.state
        zone = self.zones[i].words if 0 <= i < len(self.zones) else 'outside the driver\'s list'
        return [('Zone', '%s (%s %d)' % (zone, self.field, i)),
                ('State', {RELEASED: 'released', PRESSED: 'pressed'}.get(state, str(state)))]

    def on_message(self, msg: 'genpy.Message', t: float) -> None:
        i, state = int(getattr(msg, self.field)), int(msg.state)
        if not 0 <= i < len(self.zones):
            self.failures.add('index', '%s %d is outside the driver\'s list (0-%d: %s)' % (
                self.field, i, len(self.zones) - 1, ', '.join(z.id for z in self.zones)), i)
            return
        if state not in (RELEASED, PRESSED):
            self.failures.add('state', 'state %d of %s is neither released (0) nor pressed (1)'
                              % (state, self._name(i)), state)
            return
        z = self.state[i]
        if state == PRESSED:
            if z.pressed_at is not None:
                self.warnings.add('again', '%s pressed again with no release in between (a lost '
                                  'release event?)' % self._name(i))
                return
            z.presses += 1
            z.pressed_at = z.last_press = t
            if z.wait_end is not None and z.late_press is None:
                z.late_press = t
            if z.first_press is None:
                z.first_press = t
        else:
            if z.pressed_at is not None:
                held = t - z.pressed_at
                if held > self.expect.max_press and not z.stuck:
                    z.stuck = True
                    self.fail('%s stuck: pressed at t = %s s and released only %s s later (more than '
                              '%g s)' % (self._name(i), fmt(z.pressed_at, 2), fmt(held, 2),
                                         self.expect.max_press))
                if z.first_release is None:
                    z.first_release = t
            z.pressed_at, z.released_at = None, t

    # ------------------------------------------------------------ guided mode
    def poll(self, elapsed: float) -> None:
        self.now = elapsed
        for i, z in enumerate(self.state):
            if z.pressed_at is not None and not z.stuck and elapsed - z.pressed_at > self.expect.max_press:
                z.stuck = True
                self.fail('%s stuck: pressed at t = %s s and not released within %g s (jammed?)'
                          % (self._name(i), fmt(z.pressed_at, 2), self.expect.max_press))
                if self.asking == i:
                    self._next('stuck: pressed, not released within %g s' % self.expect.max_press,
                               said=True)
        op = self.operator
        if op is None or self._done:
            return
        if self.asking is None:
            if not self.order:
                self._done = True
                op.finished(self.plan.sensor.name)
                return
            if not op.turn(self.plan.sensor.name):
                return
            if not self.asked_any and op.publishing(self.topic) is False:
                # nothing publishes the topic (the driver's converter disabled, the driver not
                # running): nobody is asked to touch for nothing; the stream rules say why
                for i in self.order:
                    self.state[i].outcome = 'not asked: no publisher on the topic'
                self.order = []
                return
            self.asked_any = True
            self.asking = self.order.pop(0)
            self.asked_at = elapsed
            zone = self.zones[self.asking]
            op.ask('%s/%s' % (self.plan.sensor.name, zone.id), zone.prompt)
            return
        z = self.state[self.asking]
        pressed_since = z.last_press is not None and z.last_press >= self.asked_at
        if z.released_at is not None and z.released_at >= self.asked_at and z.pressed_at is None \
                and not z.stuck:
            self._next('passed')      # its press (a hasty operator's, just before the prompt) and release
        elif op.skipped():
            self._next('skipped by the operator')
        elif not pressed_since and z.pressed_at is None and elapsed - self.asked_at >= self.wait:
            z.wait_end = self.asked_at + self.wait
            self._next(self._not_pressed, said=True)     # one reason for all such zones: finish()
        elif z.pressed_at is not None and z.stuck:
            self._next('stuck: held down since before it was asked', said=True)

    @property
    def _not_pressed(self) -> str:
        return 'not pressed within %g s' % self.wait

    def _next(self, outcome: str, said: bool = False) -> None:
        """The zone being asked is over; `said`: given up without its touch, which the person is
        told before the next zone is asked."""
        if self.asking is None:
            return
        z = self.state[self.asking]
        if not z.outcome:
            z.outcome = outcome
            if said and self.operator is not None:
                self.operator.moved_on('%s/%s' % (self.plan.sensor.name, self.zones[self.asking].id),
                                       outcome, bool(self.order))
        self.asking = None

    def done(self) -> bool:
        return self._done

    # ------------------------------------------------------------ the end
    def finish(self) -> None:
        if self.asking is not None:     # the window ended while asking (interrupted)
            self._next('not answered before the end of the window')
        rows = []
        late: List[Tuple[str, str]] = []     # (zone, seconds after its wait) pressed too late
        for i, (zone, z) in enumerate(zip(self.zones, self.state)):
            if z.pressed_at is not None and not z.stuck:
                if self.now - z.pressed_at > self.expect.max_press:
                    z.stuck = True
                    self.fail('%s stuck: pressed at t = %s s and not released within %g s (jammed?)'
                              % (self._name(i), fmt(z.pressed_at, 2), self.expect.max_press))
                else:
                    self.warn('%s still pressed at the end of the window (pressed at t = %s s)'
                              % (self._name(i), fmt(z.pressed_at, 2)))
            outcome = z.outcome or self._unasked_outcome(z, zone)
            if outcome == self._not_pressed and z.late_press is not None and z.wait_end is not None:
                after = fmt(max(0.0, z.late_press - z.wait_end), 1)
                late.append((self._name(i), after))
                outcome = '%spressed %s s after the %g s wait' % (LATE, after, self.wait)
            if z.stuck and not outcome.startswith('stuck'):
                outcome = 'stuck'
            held: Optional[float] = None   # the first press's, or until the end when never released
            if z.first_press is not None:
                end = z.first_release if z.first_release is not None and z.first_release >= z.first_press \
                    else self.now
                held = max(0.0, end - z.first_press)
            rows.append(ZoneRow(zone.words, '%s/%s' % (self.plan.sensor.name, zone.id), i, z.presses,
                                _r(z.first_press), _r(z.first_release), _r(held), outcome))
        self.found = TouchValues('guided' if self.guided else 'unattended', rows)
        unpressed = [self._name(r.index) for r in rows if r.outcome == self._not_pressed]
        if unpressed:
            already = 'a zone already held down before the run: the driver sends only changes'
            self.fail('%s was not pressed within %g s of asking (a dead sensor, or %s)'
                      % (unpressed[0], self.wait, already) if len(unpressed) == 1 else
                      'not pressed within %g s of asking: %s (each a dead sensor, or %s)'
                      % (self.wait, ', '.join(unpressed), already))
        if late:
            self.fail('%s was pressed %s s after the %g s wait: touch sooner, or raise --touch-wait'
                      % (late[0][0], late[0][1], self.wait) if len(late) == 1 else
                      'pressed after the %g s wait: %s; touch sooner, or raise --touch-wait'
                      % (self.wait, ', '.join('%s %s s after' % z for z in late)))
        skipped = [r.zone for r in rows if r.outcome == 'skipped by the operator']
        if skipped:
            self.warn('skipped by the operator (not tested): %s' % ', '.join(skipped))
        if self.guided:
            self.notes.append('guided: %s' % '; '.join(
                '%s %s' % (r.zone, r.outcome) for r in rows if self.zones[r.index].asked))
        touched = [r.zone for r in rows if r.presses]
        if touched:
            self.notes.append('touched: %s' % '; '.join(
                '%s (%d press%s%s)' % (r.zone, r.presses, '' if r.presses == 1 else 'es',
                                       ', held %s s' % fmt(r.held_s, 2) if r.held_s is not None else '')
                for r in rows if r.presses))
        untouched = [r.zone for r in rows if not r.presses and self.zones[r.index].asked]
        if untouched and not self.guided:
            self.notes.append('not touched: %s' % ', '.join(untouched))

    def _unasked_outcome(self, z: _ZoneState, zone: Zone) -> str:
        if z.stuck:
            return 'stuck'
        if z.presses and z.first_release is not None:
            return 'touched'
        if z.presses:
            return 'pressed, not released'
        return 'not touched' if zone.asked or not self.guided else 'not asked (Pepper has none)'

    def skip_reason(self) -> Optional[str]:
        if self.guided:
            asked = [s for z, s in zip(self.zones, self.state) if z.asked]
            if asked and all(s.outcome == 'skipped by the operator' for s in asked):
                return 'every zone skipped by the operator'
            return None
        if self.count == 0:
            return ('not touched: nobody was asked to (unattended: no terminal and no --guided); '
                    'run with --guided and touch each zone when asked to test it')
        return None


def _r(v: Optional[float]) -> Optional[float]:
    return round(v, 3) if v is not None else None
