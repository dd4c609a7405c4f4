"""Sonars (sensor_msgs/Range): readings judged against the sensor's physical limits.

What the drivers publish:
  * naoqi_driver advertises min_range 0.25, max_range 2.55, field_of_view 0.5236
    (ros-naoqi/naoqi_driver src/converters/sonar.cpp:68-70) but publishes Pepper's raw
    ALMemory distance unclipped (sonar.cpp:114 `msgs_[i].range = float(values[i])`): several
    metres when nothing is in front.
  * The Gazebo sonar of the simulator advertises min 0, max 5, fov 1.05, with Gaussian noise.
So a reading outside the advertised [min_range, max_range] is a real distance, reported as
information ("beyond the advertised range"); only readings the sensor cannot physically give
fail: NaN, negative (REP 117's -inf, "too close", is valid, as is +inf, "nothing in range"), or
above the physical limit `physical_range` ([min, max] m, from the expectations: Pepper's sonar
measures 0..5 m, reference/pepper-sensors.md). Without `physical_range` the advertised limits
are the only limits known, and a reading outside them fails.
No stuck rule: a sonar with nothing in front reads its maximum again and again (sonar.cpp:114).
"""
import math
from typing import TYPE_CHECKING, Any, List, Optional, Tuple

from .base import Acc, Check, fmt
from .values import Point
from .values.range import RangeValues
from .wear import Noise

if TYPE_CHECKING:
    import genpy

    from ..plan.expectations import RangeExpect
    from ..plan.settings import SensorPlan
    from .base import RunContext


class RangeCheck(Check):
    family = 'range'
    expect: 'RangeExpect'

    def __init__(self, plan: 'SensorPlan', ctx: 'RunContext') -> None:
        super().__init__(plan, ctx)
        self.range = Acc()
        self.fov = Acc()
        self.beyond = 0        # readings above the advertised max_range (physically possible)
        self.below = 0         # readings below the advertised min_range (physically possible)
        self.beyond_example = None
        self.range_series: List[Point] = []
        self.noise = Noise()
        self.found: Optional[RangeValues] = None

    def fields(self, msg: 'genpy.Message') -> List[Tuple[str, Any]]:
        return [('Frame id', msg.header.frame_id),
                ('Field of view', fmt(msg.field_of_view)),
                ('Minimum range value', fmt(msg.min_range)),
                ('Maximum range value', fmt(msg.max_range)),
                ('Range value', fmt(msg.range))]

    def on_message(self, msg: 'genpy.Message', t: float) -> None:
        lo, hi, r = msg.min_range, msg.max_range, msg.range
        self.range.add(r)
        self.noise.add(r, msg.header.stamp.to_sec() or None)     # the sampling time
        self.fov.add(msg.field_of_view)
        if len(self.range_series) < 2000:
            self.range_series.append((round(t, 3), r if math.isfinite(r) else None))
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            self.failures.add('limits', 'min_range %s is not below max_range %s' % (fmt(lo), fmt(hi)))
        self._judge_range(r, lo, hi)
        fov_band = self.expect.field_of_view
        if not msg.field_of_view > 0:
            self.failures.add('fov', 'field of view is not positive', msg.field_of_view)
        elif fov_band and not (fov_band[0] <= msg.field_of_view <= fov_band[1]):
            self.failures.add('fov_band', 'field of view outside the expected [%s, %s] rad'
                              % (fmt(fov_band[0]), fmt(fov_band[1])), msg.field_of_view)

    def _judge_range(self, r, lo, hi):
        if math.isnan(r):
            self.failures.add('nan', 'range is NaN')
            return
        if math.isinf(r):
            return   # REP 117: +inf = nothing in range, -inf = too close; both are valid readings
        physical = self.expect.physical_range
        if physical is None:
            if not (lo <= r <= hi):
                self.failures.add('out', 'range outside [%s, %s] m' % (fmt(lo), fmt(hi)), r)
            return
        p_lo, p_hi = float(physical[0]), float(physical[1])
        if r < 0:
            self.failures.add('negative', 'range is negative', r)
        elif not (p_lo <= r <= p_hi):
            self.failures.add('physical', 'range outside the sensor\'s physical limits [%s, %s] m'
                              % (fmt(p_lo), fmt(p_hi)), r)
        elif r > hi:
            self.beyond += 1
            self.beyond_example = r if self.beyond_example is None else max(self.beyond_example, r)
        elif r < lo:
            self.below += 1

    def finish(self) -> None:
        self.found = RangeValues(self.range.spread(), self.range.nonfinite, self.fov.spread(), self.beyond,
                                 self.below, self.noise.sd(), list(self.range_series))
        if self.count:
            self.notes.append('Range value: ' + self.range.text('m'))
        if self.beyond:
            self.notes.append('%d of %d readings beyond the advertised range (up to %s m; a real '
                              'distance: naoqi_driver publishes the raw value unclipped)'
                              % (self.beyond, self.count, fmt(self.beyond_example)))
        if self.below:
            self.notes.append('%d of %d readings below the advertised min_range (a real distance)'
                              % (self.below, self.count))

