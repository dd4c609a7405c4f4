"""Laser (sensor_msgs/LaserScan): beam count matches the angles, sane limits, invalid beams.

Pepper's driver sets its blind beams to -1.0 (`blind_value` in the expectations); those are
counted apart from other invalid beams (NaN, inf, outside [range_min, range_max]).
"""
import math

from .base import Acc, Check, fmt


class LaserCheck(Check):
    family = 'laser'

    def __init__(self, plan, ctx):
        super().__init__(plan, ctx)
        self.valid = Acc()
        self.beams = 0
        self.blind = 0
        self.invalid = 0
        self.last_scan = None

    def fields(self, msg):
        return [('Frame id', msg.header.frame_id),
                ('Start angle of the scan', fmt(msg.angle_min)),
                ('End angle of the scan', fmt(msg.angle_max)),
                ('Angular distance between measurements', fmt(msg.angle_increment, 6)),
                ('Time between measurements', fmt(msg.time_increment, 6)),
                ('Time between scans', fmt(msg.scan_time)),
                ('Minimum range value', fmt(msg.range_min)),
                ('Maximum range value', fmt(msg.range_max)),
                ('Range data size', len(msg.ranges))]

    def on_message(self, msg, t):
        n = len(msg.ranges)
        if msg.angle_increment == 0 or not math.isfinite(msg.angle_increment):
            self.failures.add('inc', 'angle increment is zero or not finite', msg.angle_increment)
        else:
            span = (msg.angle_max - msg.angle_min) / msg.angle_increment
            if abs(span + 1 - n) > 1.01:
                self.failures.add('span', 'number of ranges does not match the angles '
                                  '((max - min) / increment + 1 = %s)' % fmt(span + 1, 1), n)
        expected = self.expect.get('ranges')
        if expected and n != expected:
            self.failures.add('count', '%d ranges where %d are expected' % (n, expected))
        if not (msg.range_min < msg.range_max):
            self.failures.add('limits', 'range_min %s is not below range_max %s'
                              % (fmt(msg.range_min), fmt(msg.range_max)))
        if msg.intensities and len(msg.intensities) != n:
            self.failures.add('intens', 'intensities (%d) not as long as ranges (%d)'
                              % (len(msg.intensities), n))
        blind = self.expect.get('blind_value')
        lo, hi = msg.range_min, msg.range_max
        for r in msg.ranges:
            if blind is not None and r == blind:
                self.blind += 1
            elif math.isfinite(r) and lo <= r <= hi:
                self.valid.add(r)
            else:
                self.invalid += 1
        self.beams += n
        self.last_scan = (msg.angle_min, msg.angle_increment, list(msg.ranges), lo, hi, blind)

    def finish(self):
        counted = max(1, self.beams - self.blind)
        share = self.invalid / counted if self.beams else 0.0
        self.values['beams'] = self.beams
        self.values['blind_beams'] = self.blind
        self.values['invalid_beams'] = self.invalid
        self.values['invalid_share'] = round(share, 4)
        self.values['range_m'] = self.valid.as_dict()
        if self.last_scan:
            a0, inc, ranges, lo, hi, blind = self.last_scan
            self.series['last_scan'] = {'angle_min': a0, 'angle_increment': inc,
                                        'ranges': [r if math.isfinite(r) else None for r in ranges],
                                        'range_min': lo, 'range_max': hi, 'blind_value': blind}
        if self.count:
            self.notes.append('Valid ranges: %s; invalid beams %.1f%% (%d of %d), blind beams %d'
                              % (self.valid.text('m'), 100 * share, self.invalid, counted, self.blind))
        limit = self.expect.get('max_invalid_share')
        if self.count and limit is not None and share > limit:
            self.fail('%.0f%% of the beams are invalid (NaN, inf or outside the range limits; '
                      'at most %.0f%% expected)' % (100 * share, 100 * limit))
