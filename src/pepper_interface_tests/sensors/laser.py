"""Laser (sensor_msgs/LaserScan): beam count from the scan's own angles, the driver's blind
layout, real returns.

What the drivers publish:
  * naoqi_driver (ros-naoqi/naoqi_driver src/converters/laser.cpp): 61 slots
    (laser.cpp:221 `std::vector<float>(61, -1.0f)`), three segments of 15 measured slots with
    8 blind slots between them left at -1.0 (laser.cpp:178 and :193 `pos = pos+8`), i.e. blind
    slots 15-22 and 38-45; the measured slots are raw distances in base_footprint
    (laser.cpp:170-175), NOT clipped to range_max 3.0 (laser.cpp:236). angle_increment is
    span / 61 (laser.cpp:218), so (max - min) / increment is 61, not 60.
  * The simulator's /pepper/laser_2 (awesomebytes/pepper_virtual, branch simulation_that_works,
    pepper_gazebo_plugin/scripts/laser_publisher.py:428-429): 61 x 8 = 488 slots initialised to
    NaN, filled only where the point cloud has a point; range 0.1..7.0 (:392-393); increment
    span / 488. NaN there means "no return".

Rules (expectations, from the sensor's driver profile: config/sensorExpectations.yaml
`drivers:`): the beam count is (angle_max - angle_min) / angle_increment (naoqi_driver,
laser_publisher.py) or one more (REP 138's convention), with a beam of slack; `ranges` (the
driver's beam count, only where configured: the robot);
`blind_slots` ([[first, last], ...] inclusive: the driver's blind layout) holding `blind_value`;
without `blind_slots`, any `blind_value` counts as blind (older configurations).
`nan_is_no_return`: NaN is "nothing seen", not an invalid reading; `inf_is_no_return` (default
true, REP 117): +inf is "nothing in range".

Layout: a scan with another beam count than `ranges`, or a reading in a blind slot, is laid out
otherwise than the expected driver (`layout`): a WARNING naming both layouts and how to set the
expectation, not a failure - a filter chain, a patched driver or another publisher may fill or
drop those slots. Such a scan is judged by its readings: a blind slot's reading counts as any
other; a scan of another length is judged without the blind slots and boards.

Boards (`boards`: name -> [first, last] slots; naoqi_driver laser.cpp:166-176 right 0-14,
:181-191 front 23-37, :195-205 left 46-60): each board's segment is judged on its own, since
one dead board hides a third of the surroundings while the other two keep the whole scan
healthy. A board with no valid reading and no "nothing in range" mark in the whole window fails,
naming what it held: a board that stopped gives naoqi_driver's converter x = y = 0, i.e. the
board's mounting offset (0.056 m front, 0.092 m right and left, laser.cpp:170-171, :185-186,
:199-200), below range_min; yohatad/naoqi_driver2 publishes NaN in all 15 slots (kUnknownRange).
A board whose segment repeats slot for slot for `stuck_scans` scans in a row fails as stuck;
only a segment holding a reading within [range_min, range_max] counts (one beyond range_max
may be the board's fixed saturation value for "nothing seen", which repeats in open space).
A finite reading at or above range_min is valid, also beyond range_max ("beyond the advertised
range", information). Invalid: NaN (unless no-return), -inf is valid (REP 117, too close),
negative values (a blind value outside the blind layout too), readings below range_min.
A scan with no valid return at all fails; more than `max_invalid_share` invalid beams (blind
and no-return slots excluded) fails.

Stuck (`stuck_scans`): that many scans in a row identical slot for slot (every float to the
last bit) fail, naming when the run began; as for a board, only scans holding a reading within
[range_min, range_max] count. naoqi_driver reads the laser from ALMemory at the
converter's rate (laser.cpp:142-154, 10 Hz), faster than the boards sample: each board frames
at about 6.66 Hz, every 150 ms (yohatad/naoqi_driver2 src/converters/laser.hpp:49; Aldebaran's
laser documentation, cited by ros-naoqi pepper_robot pepper_sensors_py laser.py:39-40, gives 6
Hz), so a board's segment repeats in two reads in a row (three with the converter's timer
jitter) and so may the whole scan. `stuck_scans` (20, 2 s at 10 Hz) is far above that; a run of
seconds of identical raw distances, which carry measurement noise, is a frozen scan.

A frozen scan (the whole scan stuck) is said once, as the laser's, not once more per board
(line numbers: yohatad/naoqi_driver2 at 9506ea2, ros-naoqi/naoqi_driver at aed1b87):
Pepper's laser boards stop sampling while the robot rests (yohatad/naoqi_driver2
src/converters/laser.hpp:72-75; its converter then stops publishing, laser.cpp:226-243, "The
boards stop sampling while the robot is at rest"), and stock naoqi_driver goes on reading their
last values and stamping them with the current time (ros-naoqi/naoqi_driver
src/converters/laser.cpp:148 getListData, :154 `ros::Time::now()`): the usual cause of a frozen
scan is a resting robot, not three broken boards. The reason says so and how to wake the robot
(ALMotion.wakeUp, or press the chest button twice quickly: SoftBank's Pepper NAOqi 2.9 "Daily
use" guide, Rest mode), and, when the run has the driver's joint stiffness on /diagnostics
(sensors/stiffness.py), whether the robot is in fact resting (stiffness 0 on every joint) or
awake (then the laser or the driver stopped updating). It stays a FAIL: a frozen scan is
unusable. A board frozen while the others move keeps its own reason (above).
"""
import math
from array import array
from typing import TYPE_CHECKING, Any, List, Optional, Set, Tuple

import numpy as np

from .base import Acc, Check, StuckRun, fmt
from .values.laser import BeamKind, LaserValues, LastScan
from .wear import BeamNoise

if TYPE_CHECKING:
    import genpy

    from ..plan.expectations import LaserExpect
    from ..plan.settings import SensorPlan
    from .base import RunContext


# what one beam of a scan is, as the check judges it (the report's scan plot shows the same)
RETURN, BLIND, NO_RETURN, INVALID = BeamKind.RETURN, BeamKind.BLIND, BeamKind.NO_RETURN, BeamKind.INVALID


class Board:
    """One board's segment of the scan over the window: did it ever give a valid reading (or a
    "nothing in range" mark), what it held when it did not, and its run of identical segments."""

    def __init__(self, name: str, first: int, last: int, stuck_scans: Optional[int]) -> None:
        self.name, self.first, self.last = name, first, last
        self.alive = False
        self.scans = 0
        self.held: Optional[float] = None      # the one value every slot held so far (NaN too)
        self.uniform = True                     # every slot of every scan held `held`
        self.stuck = StuckRun(stuck_scans)
        self.stuck_seg: Any = ()
        self.slots = self.returns = 0           # non-blind slots seen, returns among them (drift)

    def add(self, ranges: Any, kinds: List[BeamKind], lo: float, hi: float, t: float) -> None:
        seg = ranges[self.first:self.last + 1]
        self.scans += 1
        own = kinds[self.first:self.last + 1]
        self.slots += sum(1 for k in own if k is not BLIND)
        self.returns += sum(1 for k in own if k is RETURN)
        if not self.alive and any(k in (RETURN, NO_RETURN) for k in kinds[self.first:self.last + 1]):
            self.alive = True
        if self.uniform:
            for r in seg:
                if self.held is None:
                    self.held = r
                if not (r == self.held or (math.isnan(r) and math.isnan(self.held))):
                    self.uniform = False
                    break
        if self.stuck.limit:
            measured = any(lo <= r <= hi for r in seg)
            self.stuck.add(array('f', seg).tobytes() if measured else t, t)
            if measured and self.stuck.run == self.stuck.longest:
                self.stuck_seg = seg        # what the longest identical run held

    def stuck_text(self) -> Optional[str]:
        found = self.stuck.finding('segments', 'stuck_scans')
        if not found:
            return None
        held = [r for r in self.stuck_seg if math.isfinite(r)]
        return '%s stuck: %s, holding %s-%s m' % (self.where(), found, fmt(min(held), 3),
                                                 fmt(max(held), 3))

    def where(self) -> str:
        return '%s board (slots %d-%d)' % (self.name, self.first, self.last)

    def dead(self, range_min: float) -> Optional[str]:
        if self.alive or not self.scans:
            return None
        if self.uniform and self.held is not None:
            held = self.held
            what = '%s in every slot of every scan' % (
                'NaN' if math.isnan(held) else fmt(held, 3) + ' m')
            if math.isfinite(held) and 0 <= held < range_min:
                what += ' (below range_min %s m: a board that stopped gives its mounting offset)' % fmt(range_min)
        else:
            what = 'only invalid readings (NaN, negative or below range_min %s m)' % fmt(range_min)
        return ('%s dead: no valid reading in %d scans, %s' % (self.where(), self.scans, what))


def blind_indices(slots: Optional[Tuple[Tuple[int, int], ...]]) -> Set[int]:
    out: Set[int] = set()
    for first, last in slots or ():
        out.update(range(int(first), int(last) + 1))
    return out


class LaserCheck(Check):
    family = 'laser'
    expect: 'LaserExpect'

    def __init__(self, plan: 'SensorPlan', ctx: 'RunContext') -> None:
        super().__init__(plan, ctx)
        self.valid = Acc()
        self.beams = 0
        self.blind = 0
        self.invalid = 0
        self.no_return = 0
        self.beyond = 0
        self.slots = self.expect.blind_slots
        self.blind_set = blind_indices(self.slots)
        self.nan_no_return = self.expect.nan_is_no_return
        self.inf_no_return = self.expect.inf_is_no_return
        # (angle_min, angle_increment, ranges, range_min, range_max, blind value) of the last scan
        self.last_kinds: List[BeamKind] = []      # the last scan's beams: RETURN, BLIND, NO_RETURN, INVALID
        self.last_scan: Optional[Tuple[float, float, List[float], float, float, Optional[float]]] = None
        self.stuck = StuckRun(self.expect.stuck_scans)
        self.boards = [Board(name, first, last, self.expect.stuck_scans)
                       for name, first, last in self.expect.boards or ()]
        # a scan laid out otherwise than the driver's: (scans, first example)
        self.layout_count = 0
        self.layout_example: Optional[str] = None
        self.found: Optional[LaserValues] = None      # what finish() measured
        self.range_noise = BeamNoise()

    def fields(self, msg: 'genpy.Message') -> List[Tuple[str, Any]]:
        return [('Frame id', msg.header.frame_id),
                ('Start angle of the scan', fmt(msg.angle_min)),
                ('End angle of the scan', fmt(msg.angle_max)),
                ('Angular distance between measurements', fmt(msg.angle_increment, 6)),
                ('Time between measurements', fmt(msg.time_increment, 6)),
                ('Time between scans', fmt(msg.scan_time)),
                ('Minimum range value', fmt(msg.range_min)),
                ('Maximum range value', fmt(msg.range_max)),
                ('Range data size', len(msg.ranges))]

    def on_message(self, msg: 'genpy.Message', t: float) -> None:
        n = len(msg.ranges)
        if msg.angle_increment == 0 or not math.isfinite(msg.angle_increment):
            self.failures.add('inc', 'angle increment is zero or not finite', msg.angle_increment)
        else:
            # beams = span / increment (naoqi_driver, laser_publisher.py) or span / increment + 1
            # (the REP 138 convention): either is right, one beam of slack covers both
            span = (msg.angle_max - msg.angle_min) / msg.angle_increment
            if not (span - 1.01 <= n <= span + 2.01):
                self.failures.add('span', 'number of ranges does not match the angles '
                                  '((max - min) / increment = %s)' % fmt(span, 1), n)
        expected = self.expect.ranges
        laid_out = not expected or n == expected     # the driver's slot indices apply
        if not laid_out:
            self._other_layout('%d slots instead of %s' % (n, fmt(expected)))
        if not (msg.range_min < msg.range_max):
            self.failures.add('limits', 'range_min %s is not below range_max %s'
                              % (fmt(msg.range_min), fmt(msg.range_max)))
        if msg.intensities and len(msg.intensities) != n:
            self.failures.add('intens', 'intensities (%d) not as long as ranges (%d)'
                              % (len(msg.intensities), n))
        lo, hi = msg.range_min, msg.range_max
        self._judge_beams(msg.ranges, lo, hi, laid_out)
        if self.stuck.limit:
            # a scan without a measured return is judged as such, not as stuck (nothing to
            # carry noise)
            measured = any(lo <= r <= hi for r in msg.ranges)
            self.stuck.add(array('f', msg.ranges).tobytes() if measured else t, t)
        if laid_out:
            for board in self.boards:
                if board.last < n:
                    board.add(msg.ranges, self.last_kinds, lo, hi, t)
        self.beams += n
        if len(self.last_kinds) == n:    # range noise per beam, returns only (sensors/wear.py)
            self.range_noise.add(np.where([k is RETURN for k in self.last_kinds],
                                          np.asarray(msg.ranges, dtype=float), np.nan))
        self.last_scan = (msg.angle_min, msg.angle_increment, list(msg.ranges), msg.range_min,
                          msg.range_max, self.expect.blind_value)

    def _other_layout(self, seen: str) -> None:
        self.layout_count += 1
        if self.layout_example is None:
            self.layout_example = seen

    def _judge_beams(self, ranges, lo, hi, laid_out):
        """Counts each beam by its kind (RETURN, BLIND, NO_RETURN, INVALID; the report's scan plot
        shows the last scan's kinds, so it agrees with the verdict) -> the number of returns."""
        blind = self.expect.blind_value
        slots = self.slots if laid_out else None
        kinds = []
        layout = None    # first slot of the blind layout that holds a reading
        filled = 0       # blind slots that hold a reading
        for k, r in enumerate(ranges):
            if slots is not None and k in self.blind_set:
                if blind is not None and r == blind:
                    self.blind += 1
                    kinds.append(BLIND)
                    continue
                filled += 1
                if layout is None:
                    layout = (k, r)
                # a reading where the driver leaves a blind slot: judged as the reading it is
            if slots is None and blind is not None and r == blind:
                self.blind += 1
                kinds.append(BLIND)
            elif (self.nan_no_return and math.isnan(r)) or (self.inf_no_return and r == math.inf):
                self.no_return += 1
                kinds.append(NO_RETURN)
            elif r == -math.inf or (math.isfinite(r) and r >= lo):
                kinds.append(RETURN)
                if math.isfinite(r):
                    self.valid.add(r)
                    if r > hi:
                        self.beyond += 1
            else:
                self.invalid += 1
                kinds.append(INVALID)
        self.last_kinds = kinds
        if layout is not None:
            self._other_layout('readings in %d of the %d blind slots %s (e.g. slot %d = %s, not '
                               'the blind value %s)' % (filled, len(self.blind_set), fmt(self.slots),
                                                        layout[0], fmt(layout[1], 3), fmt(blind)))
        returns = kinds.count(RETURN)
        if not returns:
            self.failures.add('empty', 'scan without a single valid return (every slot blind, '
                              'NaN or invalid)')
        return returns

    def finish(self) -> None:
        counted = max(1, self.beams - self.blind - self.no_return)
        share = self.invalid / counted if self.beams else 0.0
        if self.count:
            self.notes.append('Valid ranges: %s; invalid beams %.1f%% (%d of %d), blind beams %d, '
                              'no-return beams %d'
                              % (self.valid.text('m'), 100 * share, self.invalid, counted, self.blind,
                                 self.no_return))
        if self.beyond:
            self.notes.append('%d readings beyond the advertised range (raw distances, valid)'
                              % self.beyond)
        stuck = self.stuck.finding('scans', 'stuck_scans')
        if stuck:
            self.fail(self._frozen(stuck))
        dead = self._judge_boards(frozen=bool(stuck))
        if self.layout_count:
            self.warn(self._layout_warning())
        limit = self.expect.max_invalid_share
        if self.count and limit is not None and share > limit:
            self.fail('%.0f%% of the beams are invalid (NaN, negative or below range_min, blind '
                      'slots excluded; at most %.0f%% expected)' % (100 * share, 100 * limit))
        boards = bool(self.boards)
        self.found = LaserValues(
            beams=self.beams, blind_beams=self.blind, no_return_beams=self.no_return,
            invalid_beams=self.invalid, invalid_share=round(share, 4),
            beyond_advertised_max=self.beyond, range_m=self.valid.spread(),
            longest_identical_run=self.stuck.longest,
            other_layout_scans=self.layout_count or None,
            dead_boards=dead if boards else None,
            longest_identical_board_run={b.name: b.stuck.longest for b in self.boards} if boards else None,
            robot_resting=self._resting(),
            board_valid_share={b.name: round(b.returns / b.slots, 4) for b in self.boards if b.slots} or None,
            range_noise_m=self.range_noise.sd(),
            last_scan=self._last_scan())

    def _last_scan(self) -> Optional[LastScan]:
        """The last scan as the report plots it (NaN where a reading was not finite)."""
        if not self.last_scan:
            return None
        a0, inc, ranges, lo, hi, blind = self.last_scan
        return LastScan(a0, inc, [r if math.isfinite(r) else math.nan for r in ranges], lo, hi, blind,
                        list(self.last_kinds))

    def _resting(self) -> Optional[bool]:
        """Whether the driver's joint stiffness says the robot rests; None: no report."""
        witness = self.ctx.services.stiffness
        rest = witness.stiffness() if witness is not None else None
        return None if rest is None else rest[1] <= 0.0

    def _frozen(self, stuck: str) -> str:
        """The one reason of a frozen scan. With the robot's boards (naoqi_driver's layout): its
        likely cause, whether the robot rests and the fix first (the terminal shortens long
        reasons), then what was seen. Without (the simulator, another driver): what was seen."""
        if not self.boards:
            return 'laser stuck: ' + stuck
        seen = '%s, every board at once' % stuck
        witness = self.ctx.services.stiffness
        rest = witness.stiffness() if witness is not None else None
        wake = ('wake it up (ALMotion.wakeUp, or press the chest button twice quickly) and test '
                'again; at rest the laser boards stop sampling and naoqi_driver republishes their '
                'last values with fresh stamps')
        if rest is None:
            return ('laser stuck: probably a resting robot (no joint stiffness from the driver on '
                    '/diagnostics to tell): %s: %s' % (wake, seen))
        joints, highest = rest
        if highest <= 0.0:
            return ('laser stuck: the robot is resting (stiffness 0 on all %d joints in the '
                    'driver\'s /diagnostics): %s: %s' % (joints, wake, seen))
        return ('laser stuck: the robot is not resting (stiffness up to %s on %d joints in the '
                'driver\'s /diagnostics), so the laser boards or naoqi_driver stopped updating: '
                'restart naoqi_driver, then the robot: %s' % (fmt(highest, 2), joints, seen))

    def _judge_boards(self, frozen: bool = False) -> List[str]:
        """Fails each dead or stuck board (not as stuck when the whole scan is `frozen`: the
        laser's own reason says it once) -> the names of the dead boards."""
        lo = self.last_scan[3] if self.last_scan else 0.0
        found = [(board, board.dead(lo)) for board in self.boards]
        dead = [board.name for board, text in found if text]
        # every board dead in scans without a return: the scan's own rule says it, once
        said = len(dead) == len(self.boards) and 'empty' in self.failures.keys()
        for board, text in found:
            if text:
                if not said:
                    self.fail(text)
                continue
            stuck = None if frozen else board.stuck_text()
            if stuck:
                self.fail(stuck)
        return dead

    def _layout_warning(self) -> str:
        expect = self.expect
        wanted = expect.layout or ('%s slots, blind slots %s holding %s' % (
            fmt(expect.ranges), fmt(expect.blind_slots), fmt(expect.blind_value)))
        return ('laid out otherwise than expected in %d of %d scans: expected %s; seen %s; the '
                'readings are judged as they are. If another driver or a filter publishes this '
                'scan, set the laser\'s "driver:" to its profile (under "drivers:" in the '
                'expectations file, config/sensorExpectations.yaml or --expectations), or its '
                'own ranges, blind_slots and boards'
                % (self.layout_count, self.count, wanted, self.layout_example))
