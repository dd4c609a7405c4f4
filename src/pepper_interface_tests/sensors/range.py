"""Sonars (sensor_msgs/Range): range within limits (or +-inf as REP 117 allows), sane limits."""
import math

from .base import Acc, Check, fmt


class RangeCheck(Check):
    family = 'range'

    def __init__(self, plan, ctx):
        super().__init__(plan, ctx)
        self.range = Acc()
        self.fov = Acc()
        self.series['range_m'] = []

    def fields(self, msg):
        return [('Frame id', msg.header.frame_id),
                ('Field of view', fmt(msg.field_of_view)),
                ('Minimum range value', fmt(msg.min_range)),
                ('Maximum range value', fmt(msg.max_range)),
                ('Range value', fmt(msg.range))]

    def on_message(self, msg, t):
        lo, hi, r = msg.min_range, msg.max_range, msg.range
        self.range.add(r)
        self.fov.add(msg.field_of_view)
        if len(self.series['range_m']) < 2000:
            self.series['range_m'].append((round(t, 3), r if math.isfinite(r) else None))
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            self.failures.add('limits', 'min_range %s is not below max_range %s' % (fmt(lo), fmt(hi)))
        if math.isnan(r):
            self.failures.add('nan', 'range is NaN')
        elif math.isinf(r):
            pass   # REP 117: +inf = nothing in range, -inf = too close; both are valid readings
        elif not (lo <= r <= hi):
            self.failures.add('out', 'range outside [%s, %s] m' % (fmt(lo), fmt(hi)), r)
        fov_band = self.expect.get('field_of_view')
        if not msg.field_of_view > 0:
            self.failures.add('fov', 'field of view is not positive', msg.field_of_view)
        elif fov_band and not (fov_band[0] <= msg.field_of_view <= fov_band[1]):
            self.failures.add('fov_band', 'field of view outside the expected [%s, %s] rad'
                              % (fmt(fov_band[0]), fmt(fov_band[1])), msg.field_of_view)

    def finish(self):
        self.values['range_m'] = self.range.as_dict()
        self.values['infinite_ranges'] = self.range.nonfinite
        self.values['field_of_view_rad'] = self.fov.as_dict()
        if self.count:
            self.notes.append('Range value: ' + self.range.text('m'))
