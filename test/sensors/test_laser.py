"""The laser's three boards judged one by one, and a scan laid out otherwise than the expected
driver's: real sensor_msgs/LaserScan messages, serialized as they come off the wire, fed through
SensorRun with explicit times.

naoqi_driver's converter (ros-naoqi/naoqi_driver src/converters/laser.cpp) fills slots 0-14
from the right board (:166-176), 23-37 from the front (:181-191), 46-60 from the left
(:195-205), and leaves 15-22 and 38-45 at -1.0 (:178, :193, :221).
"""
import math
import os

import genpy
import pytest

from check_runs import judged, one_reason_with
from driver_feed import SIM, feed, run_of
from fake_pepper import BLIND, laser, serialized, sim_laser
from pepper_interface_tests.plan import catalog, settings
from pepper_interface_tests.plan.settings import Options, SensorPlan
from pepper_interface_tests.results import FAIL, PASS
from pepper_interface_tests.sensors.base import RunContext, fmt
from pepper_interface_tests.sensors.window import SensorRun

PKG = settings.package_dir()
EXPECT = os.path.join(PKG, 'config', 'sensorExpectations.yaml')
ROBOT = settings.read_expectations(EXPECT, 'robot')
T0, R0 = 5000.0, 1700000000.0
N = 25              # scans: 2.5 s at 10 Hz
RIGHT, FRONT, LEFT = range(0, 15), range(23, 38), range(46, 61)
# what naoqi_driver's converter computes from a board that stopped (x = y = 0 in ALMemory):
# the board's mounting offset, laser.cpp:170-171 (right), :185-186 (front), :199-200 (left)
DEAD_FRONT = 0.056
DEAD_SIDE = math.hypot(0.018, 0.090)


def judged_scans(msgs, expect=None, rate=10.0, services=None):
    plan = SensorPlan(catalog.SENSORS['laser'], '/laser', (expect or ROBOT['laser']))
    run = SensorRun(plan, RunContext('/nonexistent-not-written', 'robot', Options(), services), T0,
                    quick=False, wait=2.0, duration=3.0)
    run.begin(T0)
    for i, m in enumerate(msgs):
        t = T0 + 0.05 + i / rate
        m.header.stamp = genpy.Time.from_sec(R0 + t - T0 - 0.01)
        run.feed_raw(run.sensor.msg_type, serialized(m), t, R0 + t - T0)
    return run.close(T0 + 3.0, 'window ended', None)


def scan(i, board=None, value=None, others=None):
    """A healthy naoqi_driver scan (1.5 m +- 0.2 m, moving scan to scan); `board`'s slots hold
    `value` (a float, or a function of the scan index and slot)."""
    m = laser(i)
    r = list(m.ranges)
    for k in board or ():
        r[k] = value(i, k) if callable(value) else value
    for k, v in (others or {}).items():
        r[k] = v
    m.ranges = r
    return m


def reasons_with(result, words):
    hits = [r for r in result.reasons if words in r]
    assert hits, (words, result.reasons)
    return hits


# ------------------------------------------------------------------ a dead board

def test_a_front_board_stuck_at_its_mounting_offset_fails_by_name():
    r = judged_scans([scan(i, FRONT, DEAD_FRONT) for i in range(N)])
    assert r.verdict == FAIL
    text = reasons_with(r, 'front board (slots 23-37) dead')[0]
    assert 'no valid reading in 25 scans' in text and '0.056 m in every slot' in text, text
    assert 'below range_min 0.1 m' in text
    assert r.values.dead_boards == ['front']


def test_a_side_board_at_0_09_m_fails_as_the_issue_saw_it():
    r = judged_scans([scan(i, RIGHT, DEAD_SIDE) for i in range(N)])
    assert r.verdict == FAIL
    assert '0.092 m in every slot' in reasons_with(r, 'right board (slots 0-14) dead')[0]


def test_a_nan_board_fails_as_yohatad_naoqi_driver2_publishes_it():
    """yohatad/naoqi_driver2's laser.cpp: a board whose frame counter stopped is NaN in all its
    slots (kUnknownRange); +inf is "nothing in range"."""
    expect = settings.expectations.load(EXPECT, 'robot', driver='yohatad_naoqi_driver2')['laser']
    r = judged_scans([scan(i, LEFT, float('nan')) for i in range(N)], expect)
    assert r.verdict == FAIL
    assert 'NaN in every slot of every scan' in reasons_with(r, 'left board (slots 46-60) dead')[0]


def test_a_board_repeating_its_segment_fails_as_stuck_while_the_others_move():
    frozen = laser(0).ranges
    r = judged_scans([scan(i, RIGHT, lambda i, k: frozen[k]) for i in range(N)])
    assert r.verdict == FAIL
    text = reasons_with(r, 'right board (slots 0-14) stuck')[0]
    assert '25 identical segments in a row' in text and '(stuck_scans 20)' in text, text
    held = [frozen[k] for k in RIGHT]
    assert text.endswith('holding %s-%s m' % (fmt(min(held), 3), fmt(max(held), 3))), text
    # the whole scan changes: only the board's own rule sees it
    assert not [x for x in r.reasons if x.startswith('laser stuck')]


def test_a_board_dead_for_part_of_the_window_is_not_dead():
    """One valid reading in the window is a live board (the stuck rule judges repetition)."""
    r = judged_scans([scan(i, FRONT, DEAD_FRONT if i else 1.2) for i in range(N)])
    assert not [x for x in r.reasons if 'dead' in x], r.reasons


# ------------------------------------------------------------------ healthy scans stay PASS

def test_open_space_far_readings_that_vary_pass():
    r = judged_scans([scan(i, FRONT, lambda i, k: 5.3 + 0.01 * ((i + k) % 4)) for i in range(N)])
    assert r.verdict == PASS, r.reasons


def test_open_space_constant_saturation_beyond_range_max_is_not_stuck():
    """A board that sees nothing may report its fixed saturation distance (~5.4 m, yohatad's
    laser.cpp comment): beyond range_max, identical each scan, not a stuck board."""
    r = judged_scans([scan(i, FRONT, 5.4) for i in range(N)])
    assert r.verdict == PASS, r.reasons


def test_a_board_of_inf_is_nothing_in_range_under_yohatad_naoqi_driver2():
    expect = settings.expectations.load(EXPECT, 'robot', driver='yohatad_naoqi_driver2')['laser']
    r = judged_scans([scan(i, LEFT, float('inf')) for i in range(N)], expect)
    assert r.verdict == PASS, r.reasons
    assert r.values.dead_boards == []


def test_the_simulator_has_no_boards():
    sim = settings.read_expectations(EXPECT, 'simulator')['laser']
    assert sim.boards is None and sim.driver == 'pepper_virtual'


# ------------------------------------------------------------------ another layout: WARN

def test_blind_slots_holding_distances_warn_with_both_layouts_and_the_fix():
    r = judged_scans([laser(i, blind=()) for i in range(N)])
    assert r.verdict == PASS, r.reasons      # PASS with a warning: not a broken laser
    text = [w for w in r.warnings if 'laid out otherwise' in w][0]
    assert "expected naoqi_driver's 61 slots" in text, text
    assert 'readings in 16 of the 16 blind slots [[15, 22], [38, 45]]' in text, text
    assert 'not the blind value -1' in text, text
    assert '"driver:"' in text, text
    assert r.values.invalid_beams == 0       # the readings are judged as readings


def _cropped(i):
    """A filter that keeps the first 45 slots and says so in its angles."""
    m = laser(i, n=45)
    m.angle_max = m.angle_min + 45 * m.angle_increment
    return m


def test_a_shorter_scan_warns_and_is_judged_by_its_readings():
    r = judged_scans([_cropped(i) for i in range(N)])
    assert r.verdict == PASS, r.reasons
    assert [w for w in r.warnings if '45 slots instead of 61' in w], r.warnings


def test_a_broken_scan_in_another_layout_still_fails():
    r = judged_scans([laser(i, blind=(), ranges=[float('nan')] * 61) for i in range(N)])
    assert r.verdict == FAIL


def test_every_driver_profile_has_a_layout_and_a_source():
    data = settings.expectations.parse_yaml(EXPECT)
    with open(os.path.join(PKG, 'docs', 'drivers.md'), encoding='utf-8') as f:
        doc = f.read()
    for name, sensors in data['drivers'].items():
        assert sensors['laser'].get('layout'), name
        assert '`%s`' % name in doc, 'docs/drivers.md does not cite profile %s' % name


def test_a_scan_without_any_return_is_said_once_not_per_board():
    r = judged_scans([laser(i, ranges=[float('nan')] * 61) for i in range(N)])
    assert r.verdict == FAIL
    assert not [x for x in r.reasons if 'board' in x], r.reasons
    assert r.values.dead_boards == ['right', 'front', 'left']


@pytest.mark.parametrize('build, words', [
    (lambda i: laser(i, ranges=[float('nan')] * 61), 'scan without a single valid return'),
    (lambda i: laser(i, ranges=[-1.0] * 61), 'scan without a single valid return'),
    (lambda i: laser(i, ranges=[-1.0] * 61), '100% of the beams are invalid'),
    (lambda i: laser(i, n=40), 'number of ranges does not match the angles'),
    (lambda i: laser(i, angle_increment=0.0), 'angle increment is zero or not finite'),
    (lambda i: laser(i, range_min=3.0, range_max=1.0), 'range_min 3 is not below range_max 1'),
    (lambda i: laser(i, intensities=[1.0] * 10), 'intensities (10) not as long as ranges (61)'),
    (lambda i: _laser_frame(i), 'frame_id is "laser_frame", expected "base_footprint"'),
])
def test_laser_faults(tmp_path, build, words):
    r = judged('laser', tmp_path, [build(i) for i in range(N)])
    assert r.verdict == FAIL
    one_reason_with(r, words)


def _laser_frame(i):
    m = laser(i)
    m.header.frame_id = 'laser_frame'
    return m


def _scan_with_invalid(i, invalid):
    m = laser(i)
    # round robin over the three boards (0-14, 23-37, 46-60): no board is left without a
    # valid reading (a dead board fails on its own, the boards' tests above)
    counted = [k for trio in zip(range(0, 15), range(23, 38), range(46, 61)) for k in trio]
    r = list(m.ranges)
    for k in counted[:invalid]:
        r[k] = float('nan') if k % 2 else 0.05      # NaN, or below range_min
    m.ranges = r
    return m


def test_laser_invalid_share_limit(tmp_path):
    """16 blind beams (-1.0) are excluded; of the other 45, at most 50% may be invalid."""
    ok = judged('laser', tmp_path, [_scan_with_invalid(i, 22) for i in range(N)])   # 48.9%
    assert ok.verdict == PASS, ok.reasons
    assert ok.values.blind_beams == 16 * N and ok.values.invalid_beams == 22 * N
    bad = judged('laser', tmp_path, [_scan_with_invalid(i, 23) for i in range(N)])  # 51.1%
    assert bad.verdict == FAIL
    one_reason_with(bad, '51% of the beams are invalid')


def test_laser_raw_distances_beyond_range_max_are_valid(tmp_path):
    """naoqi_driver does not clip to range_max 3.0 (laser.cpp:170-175): 5 m in a wide room."""
    r = judged('laser', tmp_path, [laser(i, ranges=[-1.0 if k in BLIND else 5.0 + 0.001 * (i % 3)
                                                   for k in range(61)]) for i in range(N)])
    assert r.verdict == PASS, r.reasons
    assert r.values.beyond_advertised_max == 45 * N and r.values.invalid_beams == 0
    # the report's scan plot draws each beam as judged here: 5 m beams are returns, not invalid
    kinds = r.values.last_scan.kinds
    assert kinds.count('return') == 45 and kinds.count('blind') == 16, kinds


def test_laser_last_scan_kinds_follow_the_verdict(tmp_path):
    """Per beam of the last scan: a return, a blind slot, no return (+inf) or invalid (below
    range_min) - what the report's polar plot colours, so it never calls a return invalid."""
    ranges = [-1.0 if k in BLIND else 2.0 for k in range(61)]
    ranges[0], ranges[1], ranges[2] = float('inf'), 0.01, 4.5
    r = judged('laser', tmp_path, [laser(i, ranges=list(ranges)) for i in range(N)])
    kinds = r.values.last_scan.kinds
    assert kinds[:3] == ['no return', 'invalid', 'return'] and kinds[15] == 'blind', kinds


def test_laser_blind_value_outside_the_layout_is_invalid(tmp_path):
    """Only the driver's blind slots may hold -1.0; elsewhere it is an invalid reading."""
    r = judged('laser', tmp_path, [laser(i, blind=BLIND + list(range(0, 12))) for i in range(N)])
    assert r.values.blind_beams == 16 * N and r.values.invalid_beams == 12 * N
    assert r.verdict == PASS, r.reasons          # 12 of 45 = 27%: within max_invalid_share
    r = judged('laser', tmp_path, [laser(i, blind=BLIND + list(range(0, 15)) + list(range(23, 31)))
                                   for i in range(N)])
    assert r.verdict == FAIL
    one_reason_with(r, '51% of the beams are invalid')


def test_laser_blind_value_without_a_layout(tmp_path):
    """Without blind_slots any blind value is blind; without a blind value, -1.0 is invalid."""
    r = judged('laser', tmp_path, [laser(i, blind=range(0, 40)) for i in range(N)],
               expect={'blind_value': None, 'blind_slots': None})
    assert r.verdict == FAIL and r.values.blind_beams == 0
    r = judged('laser', tmp_path, [laser(i, blind=range(0, 40)) for i in range(N)],
               expect={'blind_slots': None, 'boards': None})
    assert r.verdict == PASS, r.reasons


def test_laser_stuck_scans_fail_and_say_from_when(tmp_path):
    """naoqi_driver reads ALMemory at its own rate: 2-3 identical scans in a row are normal,
    20 (2 s at 10 Hz) are a cached scan republished."""
    r = judged('laser', tmp_path, [laser(0) for _ in range(N)])
    assert r.verdict == FAIL
    one_reason_with(r, ': 25 identical scans in a row from t = 0.05 s to the end of '
                       'the window (stuck_scans 20)')
    r = judged('laser', tmp_path, [laser(i // 3) for i in range(N)])      # each scan three times
    assert r.verdict == PASS, r.reasons
    assert r.values.longest_identical_run == 3
    r = judged('laser', tmp_path, [laser(i) for i in range(5)] + [laser(99)] * 22)
    one_reason_with(r, '22 identical scans in a row from t = 0.55 s to the end of the window')


def sim_scan(returns=True, i=0):
    """The simulator's scan (fake_pepper.sim_laser) with 40 returns and one beyond range_max
    (real), or without a single return."""
    return sim_laser(i, returns=range(150, 190) if returns else (), beyond=(300,) if returns else ())


def test_simulator_laser_mostly_nan_with_returns_passes(tmp_path):
    r = feed(run_of('laser', tmp_path, SIM), [sim_scan(i=i) for i in range(18)], rate=6.25)
    assert r.verdict == PASS, r.reasons
    assert r.values.no_return_beams == 18 * (488 - 41) and r.values.invalid_beams == 0
    assert r.values.beyond_advertised_max == 18


def test_simulator_laser_without_returns_fails(tmp_path):
    r = feed(run_of('laser', tmp_path, SIM), [sim_scan(False) for _ in range(18)], rate=6.25)
    assert r.verdict == FAIL
    assert 'scan without a single valid return (every slot blind, NaN or invalid) in 18 of 18 messages' \
        in r.reasons


def test_robot_layout_is_not_applied_to_the_simulator(tmp_path):
    """The robot's expectations (61 slots, blind layout) would fail the simulator's scan."""
    r = feed(run_of('laser', tmp_path, ROBOT), [sim_scan(i=i) for i in range(18)], rate=6.25)
    assert r.verdict == FAIL        # NaN is invalid for naoqi_driver: most beams invalid
    assert any('488 slots instead of 61' in x for x in r.warnings)   # the layout: a warning


# ------------------------------------------------------------------ a frozen scan: a resting robot

def witness_of(stiffness):
    """The run's stiffness witness fed naoqi_driver's /diagnostics (emulator/events.py
    driver_array, diagnostics.cpp:159-222) as it comes off the wire, every joint at `stiffness`."""
    from pepper_interface_tests.emulator.events import driver_array
    from pepper_interface_tests.sensors.base import Services
    from pepper_interface_tests.sensors.stiffness import StiffnessWitness
    witness = StiffnessWitness('/diagnostics')
    array = driver_array({'HipPitch': 35.0, 'HeadYaw': 33.0, 'RHand': 30.0}, 85, False,
                         stiffness=stiffness)
    witness.feed_raw('diagnostic_msgs/DiagnosticArray', serialized(array), 1.0, 1.0)
    return Services(stiffness=witness)


def frozen_reasons(services=None):
    r = judged_scans([laser(0) for _ in range(N)], services=services)
    assert r.verdict == FAIL        # a frozen scan is unusable, whatever the cause
    rest = services.stiffness.stiffness() if services else None
    assert r.values.robot_resting == (None if rest is None else rest[1] == 0)
    assert len(r.reasons) == 1, r.reasons     # not once more per board (issue 24)
    assert not [x for x in r.reasons if 'board (slots' in x], r.reasons
    text = r.reasons[0]
    # the cause and the fix first (the terminal shortens a long reason), what was seen last
    assert text.startswith('laser stuck: '), text
    assert text.endswith(': 25 identical scans in a row from t = 0.05 s to the end of the window '
                         '(stuck_scans 20), every board at once'), text
    return text


WAKE = ('wake it up (ALMotion.wakeUp, or press the chest button twice quickly) and test again; '
        'at rest the laser boards stop sampling and naoqi_driver republishes their last values '
        'with fresh stamps: ')


def test_a_frozen_scan_is_one_reason_naming_a_resting_robot_and_the_fix():
    """Without /diagnostics: the usual cause (a resting robot) and how to wake it up."""
    text = frozen_reasons()
    assert text.startswith('laser stuck: probably a resting robot (no joint stiffness from the '
                           'driver on /diagnostics to tell): ' + WAKE), text


def test_a_frozen_scan_with_stiffness_0_says_the_robot_is_resting():
    text = frozen_reasons(witness_of(0.0))
    assert text.startswith('laser stuck: the robot is resting (stiffness 0 on all 3 joints in the '
                           'driver\'s /diagnostics): ' + WAKE), text


def test_a_frozen_scan_of_an_awake_robot_blames_the_laser_or_the_driver():
    text = frozen_reasons(witness_of(1.0))
    assert text.startswith('laser stuck: the robot is not resting (stiffness up to 1 on 3 joints in '
                           'the driver\'s /diagnostics), so the laser boards or naoqi_driver stopped '
                           'updating: restart naoqi_driver, then the robot: '), text
    assert 'wake it up' not in text, text


def test_a_frozen_simulator_scan_is_not_blamed_on_a_resting_robot():
    """Gazebo's laser has no boards and no rest: what was seen, nothing more."""
    r = feed(run_of('laser', '/nonexistent-not-written', SIM), [sim_scan() for _ in range(18)], rate=6.25)
    assert r.reasons == ['laser stuck: 18 identical scans in a row from t = 0.05 s to the end of the '
                         'window (stuck_scans 13)'], r.reasons


def test_boards_sampling_at_6_66_hz_read_at_10_hz_pass():
    """Each board frames every 150 ms (yohatad/naoqi_driver2 laser.hpp:49) with its own phase,
    the driver reads every 100 ms with +-20 ms of timer jitter: a board repeats its segment in
    two or three reads in a row, and so, now and then, does the whole scan. Healthy: PASS."""
    import random
    rnd = random.Random(7)
    phase = {RIGHT: 0.0, FRONT: 0.05, LEFT: 0.11}
    scans = []
    for i in range(N):
        t = i * 0.1 + rnd.uniform(-0.02, 0.02)
        m = laser(0)
        r = list(m.ranges)
        for board, p in phase.items():
            frame = int((t + p) / 0.15)         # the board's last frame at this read
            for k in board:
                r[k] = laser(frame).ranges[k] + 0.001 * ((frame * 7 + k) % 5)
        m.ranges = r
        scans.append(m)
    r = judged_scans(scans)
    assert r.verdict == PASS, r.reasons
    assert 2 <= max(r.values.longest_identical_board_run.values()) <= 3
    assert r.values.longest_identical_run <= 3


def test_the_stuck_threshold_stays_above_what_6_66_hz_boards_give():
    """The configuration's stuck_scans leaves room for the boards' own rate (the rule's reason)."""
    assert ROBOT['laser'].stuck_scans >= 3 * 10 / 6.66
