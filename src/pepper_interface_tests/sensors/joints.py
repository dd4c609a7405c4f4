"""Joint states (sensor_msgs/JointState): unique names, array lengths, finite positions,
the expected Pepper joints present, and physically possible values.

Impossible values (joint_limits.py: Pepper's URDF limits, cited there):
  * a position beyond the joint's [lower, upper] by more than `position_margin` rad fails
    (naoqi_driver publishes ALMotion getAngles("Body", true), the sensed angles,
    src/converters/joint_state.cpp:90, 102; the margin covers encoder resolution and the
    hands' 0..1 scale against the URDF's 0.02..0.98);
  * every position of a joint is judged against its positions of the last BASELINE s and the
    last one before (jumps.JumpWatch; header stamps, receive times when stamps are zero): a
    change beyond velocity x `velocity_factor` x max(dt, BASELINE) is a jump and fails, naming
    how many, the largest and when; a position that leaps away for one message and comes back
    is a jump. The wheels (continuous joints, positions wrap at +-pi) are left out;
  * a reported velocity above velocity x `velocity_factor` is a warning only: naoqi_driver
    reads it from ALMemory's Motion/Velocity/Sensor (joint_state.cpp:119-131), a value the
    DCM differentiates, which can spike.
A NaN position fails; a NaN velocity or effort is accepted as "unknown": naoqi_driver leaves
them NaN where ALMemory has no value (joint_state.cpp:130-137).
No stuck rule: a robot at rest publishes the same angles message after message.
"""
import math
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Tuple

from .base import Acc, Check, fmt
from .joint_limits import LIMITS
from .jumps import JumpWatch
from .values.joints import JointsValues
from .wear import Noise

if TYPE_CHECKING:
    import genpy

    from ..plan.expectations import JointsExpect
    from ..plan.settings import SensorPlan
    from .base import RunContext

BASELINE = 0.1     # s: positions closer in time may differ by velocity x factor x BASELINE


class JointsCheck(Check):
    family = 'joints'
    expect: 'JointsExpect'

    def __init__(self, plan: 'SensorPlan', ctx: 'RunContext') -> None:
        super().__init__(plan, ctx)
        self.joints: Dict[str, Dict[str, Acc]] = {}     # name -> {'position': Acc, 'velocity': Acc, 'effort': Acc}
        self.names_seen: List[str] = []
        self.found: Optional[JointsValues] = None
        self.margin = self.expect.position_margin
        self.factor = self.expect.velocity_factor
        self.jumps: Dict[str, JumpWatch] = {}      # name -> its positions' jumps
        self.noise: Dict[str, Noise] = {}          # name -> its positions' noise (drift from a baseline)

    def fields(self, msg: 'genpy.Message') -> List[Tuple[str, Any]]:
        out = [('Header frame id', msg.header.frame_id), ('Number of joints', len(msg.name))]
        for i, name in enumerate(msg.name):
            def at(seq, i=i):
                return fmt(seq[i]) if i < len(seq) else 'n/a'
            out.append(('Joint', '%s: Position %s, Velocity %s, Effort %s'
                        % (name, at(msg.position), at(msg.velocity), at(msg.effort))))
        return out

    def on_message(self, msg: 'genpy.Message', t: float) -> None:
        names = list(msg.name)
        n = len(names)
        if len(set(names)) != n:
            dup = sorted({x for x in names if names.count(x) > 1})
            self.failures.add('dup', 'duplicate joint names %s' % ', '.join(dup))
        for label, seq in (('position', msg.position), ('velocity', msg.velocity), ('effort', msg.effort)):
            if len(seq) not in (0, n):
                self.failures.add('len_' + label, '%s has %d values for %d joints' % (label, len(seq), n))
        for i, name in enumerate(names):
            acc = self.joints.get(name)
            if acc is None:
                acc = self.joints[name] = {'position': Acc(), 'velocity': Acc(), 'effort': Acc()}
                self.names_seen.append(name)
            for label, seq in (('position', msg.position), ('velocity', msg.velocity), ('effort', msg.effort)):
                if len(seq) == n:
                    acc[label].add(seq[i])
            if len(msg.position) == n and math.isnan(msg.position[i]):
                self.failures.add('nan_' + name, 'position of %s is NaN' % name)
            elif len(msg.position) == n:
                self._judge_limits(name, msg.position[i], t, msg.header.stamp.to_sec() or None)
            if len(msg.velocity) == n and self.factor is not None and name in LIMITS:
                v = msg.velocity[i]
                limit = LIMITS[name][2] * self.factor
                if math.isfinite(v) and abs(v) > limit:
                    self.warnings.add('vel_' + name, 'reported velocity of %s beyond %s rad/s '
                                      '(URDF limit %s x velocity_factor %s)'
                                      % (name, fmt(limit, 2), fmt(LIMITS[name][2]), fmt(self.factor)),
                                      '%s rad/s at t = %s s' % (fmt(v, 2), fmt(t, 2)))

    def _judge_limits(self, name, p, t, stamp):
        limits = LIMITS.get(name)
        if limits is None or not math.isfinite(p):
            return
        lower, upper, velocity, line = limits
        if lower is not None:        # not a wheel (its position wraps at +-pi)
            self.noise.setdefault(name, Noise()).add(p, stamp if stamp is not None else t)
        if self.margin is not None and lower is not None and upper is not None and \
                not (lower - self.margin <= p <= upper + self.margin):
            self.failures.add('limit_' + name, 'position of %s outside Pepper\'s joint limits '
                              '[%s, %s] rad (pepper.urdf:%d) by more than position_margin %s'
                              % (name, fmt(lower), fmt(upper), line, fmt(self.margin)),
                              '%s rad, first at t = %s s' % (fmt(p), fmt(t, 2)))
        if self.factor is None or lower is None:
            return
        when = stamp if stamp is not None else t
        watch = self.jumps.get(name)
        if watch is None:
            watch = self.jumps[name] = JumpWatch(velocity * self.factor, BASELINE)
        watch.add(when, (p,), t)

    def finish(self) -> None:
        jumped = {n: w for n, w in self.jumps.items() if w.jumps}
        self.found = JointsValues({name: {k: a.spread() for k, a in acc.items()} for name, acc in self.joints.items()},
                                  len(self.joints),
                                  {n: w.jumps for n, w in jumped.items()} if jumped else None,
                                  {n: round(w.largest, 3) for n, w in jumped.items()} if jumped else None,
                                  {n: sd for n, sd in ((n, w.sd(7)) for n, w in self.noise.items())
                                   if sd is not None} or None)
        for name, w in jumped.items():
            lower, upper, velocity, line = LIMITS[name]
            self.fail('position of %s jumps: implied speed above %s rad/s (URDF velocity limit %s '
                      'x velocity_factor %s, pepper.urdf:%d): %d %s, the largest %s rad from the '
                      'position %s s before at t = %s s (positions under %.1f s apart may differ '
                      'by %s rad)'
                      % (name, fmt(w.max_rate, 2), fmt(velocity), fmt(self.factor), line,
                         w.jumps, 'jump' if w.jumps == 1 else 'jumps',
                         fmt(w.largest, 3), fmt(w.largest_dt, 3), fmt(w.largest_t, 2), BASELINE,
                         fmt(w.max_rate * BASELINE, 3)))
        expected = self.expect.joints
        missing = [j for j in expected if j not in self.joints]
        if self.count and missing:
            self.fail('expected joints missing: ' + ', '.join(missing))
        if self.count:
            self.notes.append('%d joints: %s' % (len(self.names_seen), ', '.join(self.names_seen)))
            for name in self.names_seen:
                acc = self.joints[name]
                self.notes.append('%s position %s; velocity %s; effort %s'
                                  % (name, acc['position'].text('rad'), acc['velocity'].text('rad/s'),
                                     acc['effort'].text()))

