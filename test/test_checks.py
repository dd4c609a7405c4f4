"""The checks, with real message objects serialized as they come off the wire.

Each message is built as a real sensor_msgs / nav_msgs object, serialized with msg.serialize()
and fed through SensorRun.feed_raw with a receive time and a ROS time, exactly as the live
subscription and the bag reader do. Times are explicit numbers, so nothing here depends on the
speed of the machine. Also: stream statistics (stats.py), the runner with a real bag file
(lanes, order, interrupt), and the three result writers.
"""
import io
import json
import os
import re
import xml.etree.ElementTree as ET

import genpy
import pytest
import rosbag
from std_msgs.msg import String

from fake_pepper import BLIND, JOINTS, UNKNOWN_COVARIANCE, imu, joints, laser, odometry, serialized, sonar
from pepper_interface_tests import codec, results
from pepper_interface_tests.observer import RunObserver
from pepper_interface_tests.outputs import files
from pepper_interface_tests.outputs.observers import ResultFiles
from pepper_interface_tests.outputs.terminal import Terminal
from pepper_interface_tests.plan import catalog, settings
from pepper_interface_tests.plan.settings import Options, SensorPlan
from pepper_interface_tests.results import FAIL, PASS, SKIPPED, RunResult, SensorResult
from pepper_interface_tests.runner import Runner, lanes_for
from pepper_interface_tests.sensors.base import Acc, RunContext, Tally, fmt
from pepper_interface_tests.sensors.joint_limits import LIMITS
from pepper_interface_tests.sensors.values import Spread
from pepper_interface_tests.sensors.window import SensorRun
from pepper_interface_tests.sources.bag import BagSource
from pepper_interface_tests.sources.messages import message_class
from pepper_interface_tests.stats import StreamStats

PKG = settings.package_dir()
ROBOT = settings.read_expectations(os.path.join(PKG, 'config', 'sensorExpectations.yaml'), 'robot')
T0 = 5000.0            # the runner's clock when listening begins (monotonic seconds)
R0 = 1700000000.0      # ROS time at T0


# ------------------------------------------------------------------ helpers

def make_run(name, tmp_path, expect=None, topic='/t', quick=False, wait=2.0, duration=3.0):
    plan = SensorPlan(catalog.SENSORS[name], topic, ROBOT[name].but(**(expect or {})))
    ctx = RunContext(str(tmp_path), 'robot', Options())
    run = SensorRun(plan, ctx, T0, quick=quick, wait=wait, duration=duration)
    run.begin(T0)
    return run


def feed(run, msgs, rate=10.0, start=0.05, delay=0.01, stamp=None):
    """Feed messages at `rate` from `start` s; header stamps = ROS time - delay unless `stamp`
    (i, ros_time) -> seconds says otherwise. Returns the last receive time."""
    t = T0
    for i, m in enumerate(msgs):
        t = T0 + start + i / rate
        ros = R0 + (t - T0)
        if hasattr(m, 'header'):
            s = stamp(i, ros) if stamp else ros - delay
            m.header.stamp = genpy.Time.from_sec(s) if s else genpy.Time(0, 0)
        run.feed_raw(run.sensor.msg_type, serialized(m), t, ros)
    return t


def close(run, at=3.0, reason='window ended', lookup=None):
    return run.close(T0 + at, reason, lookup)


def judged(name, tmp_path, msgs, expect=None, **kw):
    """Messages fed at the sensor's nominal rate (unless rate=...), judged after a 3 s window."""
    kw.setdefault('rate', float(ROBOT[name].nominal))
    run = make_run(name, tmp_path, expect)
    feed(run, msgs, **kw)
    return close(run, at=3.0)


def one_reason_with(result, words):
    hits = [r for r in result.reasons if words in r]
    assert hits, 'no reason with %r in %r' % (words, result.reasons)
    return hits[0]


N = 25      # messages per window at 10 Hz (2.5 s of a 3 s window)
NJ = 125    # joint states: 2.5 s at their nominal 50 Hz


# ------------------------------------------------------------------ good messages pass, family by family

@pytest.mark.parametrize('name, build, fields', [
    ('backSonar', sonar, ['Frame id', 'Field of view', 'Minimum range value', 'Maximum range value',
                          'Range value']),
    ('laser', laser, ['Frame id', 'Start angle of the scan', 'End angle of the scan',
                     'Angular distance between measurements', 'Time between measurements',
                     'Time between scans', 'Minimum range value', 'Maximum range value',
                     'Range data size']),
    ('jointState', joints, ['Header frame id', 'Number of joints'] + ['Joint'] * len(JOINTS)),
    ('odometry', odometry, ['Header', 'Child frame id', 'Pose', 'Twist']),
    ('imu', imu, ['Header', 'Orientation', 'Angular velocity', 'Linear acceleration']),
])
def test_good_messages_pass(tmp_path, name, build, fields):
    nominal = float(ROBOT[name].nominal)
    n = int(2.5 * nominal)
    r = judged(name, tmp_path, [build(i) for i in range(n)])
    assert r.verdict == PASS, r.reasons
    assert r.reasons == [] and r.messages == n
    assert r.rate_hz == pytest.approx(nominal) and r.stamp_rate_hz == pytest.approx(nominal)
    assert [k for k, _ in r.fields] == fields          # the spec's fields of the first message
    assert r.stats.delay_s.max == pytest.approx(0.01, abs=1e-3)
    assert r.received_type == catalog.SENSORS[name].msg_type
    assert r.notes, 'a summary of the values is expected'


def test_sonar_fields_hold_the_first_message(tmp_path):
    r = judged('backSonar', tmp_path, [sonar(i, range=1.25 if i == 0 else 2.0) for i in range(N)])
    assert dict(r.fields)['Range value'] == '1.25'
    assert dict(r.fields)['Frame id'] == 'SonarBack_frame'
    assert r.values.range_m.min == 1.25 and r.values.range_m.max == 2.0


# ------------------------------------------------------------------ sonar

@pytest.mark.parametrize('fault, words', [
    (dict(range=float('nan')), 'range is NaN in 25 of 25 messages'),
    (dict(range=5.5), "range outside the sensor's physical limits [0, 5] m in 25 of 25 messages (e.g. 5.5)"),
    (dict(range=-0.3), 'range is negative'),
    (dict(min_range=3.0, max_range=1.0), 'min_range 3 is not below max_range 1'),
    (dict(max_range=float('inf')), 'min_range 0.25 is not below max_range inf'),
    (dict(field_of_view=0.0), 'field of view is not positive'),
    (dict(field_of_view=2.0), 'field of view outside the expected [0.1, 1.2] rad'),
    (dict(frame_id='SonarFront_frame'), 'frame_id is "SonarFront_frame", expected "SonarBack_frame"'),
])
def test_sonar_faults(tmp_path, fault, words):
    r = judged('backSonar', tmp_path, [sonar(i, **fault) for i in range(N)])
    assert r.verdict == FAIL
    one_reason_with(r, words)


def test_sonar_beyond_the_advertised_range_is_a_real_distance(tmp_path):
    """naoqi_driver advertises max_range 2.55 but publishes the raw distance (sonar.cpp:114):
    4 m with nothing in front is a healthy reading, shown as information."""
    r = judged('backSonar', tmp_path, [sonar(i, range=4.0 + 0.01 * (i % 3)) for i in range(N)])
    assert r.verdict == PASS, r.reasons
    assert r.values.beyond_advertised_max == N
    assert any('25 of 25 readings beyond the advertised range (up to 4.02 m' in n for n in r.notes)
    r = judged('backSonar', tmp_path, [sonar(i, range=0.1) for i in range(N)])
    assert r.verdict == PASS, r.reasons
    assert r.values.below_advertised_min == N


def test_sonar_without_physical_limits_uses_the_advertised_ones(tmp_path):
    r = judged('backSonar', tmp_path, [sonar(i, range=4.0) for i in range(N)],
               expect={'physical_range': None})
    assert r.verdict == FAIL
    one_reason_with(r, 'range outside [0.25, 2.55] m in 25 of 25 messages (e.g. 4)')


def test_sonar_infinite_ranges_are_valid_readings(tmp_path):
    """REP 117: +inf = nothing in range, -inf = too close."""
    r = judged('backSonar', tmp_path, [sonar(i, range=float('inf') if i % 2 else float('-inf'))
                                       for i in range(N)])
    assert r.verdict == PASS, r.reasons
    assert r.values.infinite_ranges == N


def test_sonar_one_bad_message_is_counted(tmp_path):
    r = judged('backSonar', tmp_path, [sonar(i, range=9.5 if i == 7 else 1.0) for i in range(N)])
    assert r.verdict == FAIL
    assert one_reason_with(r, 'physical limits').endswith('in 1 of 25 messages (e.g. 9.5)')


# ------------------------------------------------------------------ laser

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
    # valid reading (a dead board fails on its own, test_laser_boards.py)
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


# ------------------------------------------------------------------ joint states

def test_joint_faults(tmp_path):
    cases = [
        ([joints(i, names=JOINTS[1:]) for i in range(NJ)], 'expected joints missing: HeadYaw'),
        ([joints(i, names=[JOINTS[0]] + JOINTS[:1] + JOINTS[2:]) for i in range(NJ)],
         'duplicate joint names HeadYaw'),
        ([joints(i, velocity=[0.0] * (len(JOINTS) - 1)) for i in range(NJ)],
         'velocity has 19 values for 20 joints in 125 of 125 messages'),
        ([joints(i, position=[0.0, 0.0, float('nan')] + [0.0] * (len(JOINTS) - 3)) for i in range(NJ)],
         'position of HipRoll is NaN'),
    ]
    for msgs, words in cases:
        r = judged('jointState', tmp_path, msgs)
        assert r.verdict == FAIL, words
        one_reason_with(r, words)


def test_joint_short_arrays_do_not_break_the_fields(tmp_path):
    """The original indexed velocity/effort without length checks."""
    r = judged('jointState', tmp_path, [joints(i, velocity=[0.0] * 3) for i in range(NJ)])
    lines = [v for k, v in r.fields if k == 'Joint']
    assert lines[0].startswith('HeadYaw: Position 0, Velocity 0, Effort 0.5')
    assert lines[-1] == 'WheelB: Position 0, Velocity n/a, Effort 0.5'


def test_joint_empty_velocity_and_effort_are_allowed(tmp_path):
    rest = [0.2 if LIMITS[j][0] is None else min(max(0.2, LIMITS[j][0]), LIMITS[j][1]) for j in JOINTS]
    msgs = [joints(position=rest, velocity=[], effort=[]) for _ in range(NJ)]
    r = judged('jointState', tmp_path, msgs)
    assert r.verdict == PASS, r.reasons     # a robot at rest: the same angles every time is no fault
    assert r.values.joint_count == len(JOINTS)
    assert r.values.joints['HeadYaw']['position'] == Spread(0.2, 0.2, 0.2)


# ------------------------------------------------------------------ odometry

@pytest.mark.parametrize('kw, words', [
    (dict(w=2.0), 'orientation is not a unit quaternion (norm 2)'),
    (dict(w=0.0), 'orientation is not a unit quaternion (norm 0)'),
    (dict(x=float('nan')), 'pose or twist holds NaN or inf'),
    (dict(pose_covariance=[float('nan')] + [0.0] * 35), 'a covariance holds NaN or inf'),
    (dict(child_frame_id=''), 'child_frame_id is empty'),
    (dict(child_frame_id='base_footprint'), 'child_frame_id is "base_footprint", expected "base_link"'),
    (dict(frame_id=''), 'header.frame_id is empty'),
    (dict(frame_id='map'), 'frame_id is "map", expected "odom"'),
])
def test_odometry_faults(tmp_path, kw, words):
    r = judged('odometry', tmp_path, [odometry(i, **kw) for i in range(37)])   # 2.5 s at 15 Hz
    assert r.verdict == FAIL
    one_reason_with(r, words)


# ------------------------------------------------------------------ data that cannot be real (issue 10)

def test_laser_stuck_scans_fail_and_say_from_when(tmp_path):
    """naoqi_driver reads ALMemory at its own rate: 2-3 identical scans in a row are normal,
    20 (2 s at 10 Hz) are a cached scan republished."""
    r = judged('laser', tmp_path, [laser(0) for _ in range(N)])
    assert r.verdict == FAIL
    one_reason_with(r, 'laser stuck: 25 identical scans in a row from t = 0.05 s to the end of '
                       'the window (stuck_scans 20)')
    r = judged('laser', tmp_path, [laser(i // 3) for i in range(N)])      # each scan three times
    assert r.verdict == PASS, r.reasons
    assert r.values.longest_identical_run == 3
    r = judged('laser', tmp_path, [laser(i) for i in range(5)] + [laser(99)] * 22)
    one_reason_with(r, '22 identical scans in a row from t = 0.55 s to the end of the window')


def test_imu_stuck_readings_fail(tmp_path):
    r = judged('imu', tmp_path, [imu(0) for _ in range(N)])
    assert r.verdict == FAIL
    one_reason_with(r, 'IMU stuck: 25 identical readings (angular velocity and linear acceleration) '
                       'in a row from t = 0.05 s')


@pytest.mark.parametrize('acc_z, words', [
    (0.0, 'median |linear acceleration| 0 m/s^2 outside acceleration_norm [6.8, 12.8] (an upright '
          'robot measures g = 9.81 m/s^2: a dead accelerometer reads 0)'),
    (1.0, 'values in g instead of m/s^2?'),
    (19.6, 'not the gravity an upright robot measures'),
])
def test_imu_acceleration_far_from_g_fails(tmp_path, acc_z, words):
    r = judged('imu', tmp_path, [imu(i, acc_z=acc_z) for i in range(N)])
    assert r.verdict == FAIL
    one_reason_with(r, words)


def test_imu_one_bump_is_a_warning_and_gyro_beyond_its_range_fails(tmp_path):
    msgs = [imu(i, acc_z=25.0 if i == 7 else 9.81) for i in range(N)]
    r = judged('imu', tmp_path, msgs)
    assert r.verdict == PASS, r.reasons
    assert any('outside acceleration_norm [6.8, 12.8] m/s^2' in w and 'at t = 0.75 s' in w
               for w in r.warnings), r.warnings
    msgs = [imu(i) for i in range(N)]
    msgs[10].angular_velocity.z = 12.0
    r = judged('imu', tmp_path, msgs)
    assert r.verdict == FAIL
    one_reason_with(r, "|angular velocity| beyond the gyrometer's range (max_angular_velocity 8.73 "
                       "rad/s, ~500 deg/s) in 1 of 25 messages (e.g. 12 rad/s, first at t = 1.05 s)")


def test_joint_positions_beyond_the_urdf_limits_fail(tmp_path):
    msgs = [joints(i) for i in range(NJ)]
    for m in msgs[60:]:
        m.position[JOINTS.index('HeadPitch')] = 1.2        # the URDF allows -0.71..0.64
    r = judged('jointState', tmp_path, msgs, rate=50.0)
    assert r.verdict == FAIL
    one_reason_with(r, "position of HeadPitch outside Pepper's joint limits [-0.7069, 0.637] rad "
                       "(pepper.urdf:41) by more than position_margin 0.05 in 65 of 125 messages "
                       "(e.g. 1.2 rad, first at t = 1.25 s)")


def test_joint_jumps_fail_and_reported_velocity_spikes_warn(tmp_path):
    msgs = [joints(i) for i in range(NJ)]
    for k, m in enumerate(msgs):
        m.position[JOINTS.index('HeadYaw')] = 2.0 if (k // 10) % 2 else -2.0    # 4 rad in 0.02 s
    r = judged('jointState', tmp_path, msgs, rate=50.0)
    assert r.verdict == FAIL
    one_reason_with(r, 'position of HeadYaw jumps: implied speed above 11.01 rad/s (URDF velocity '
                       'limit 7.34 x velocity_factor 1.5, pepper.urdf:15)')
    msgs = [joints(i, velocity=[0.01] * len(JOINTS)) for i in range(NJ)]
    msgs[30].velocity = [0.01] * (len(JOINTS) - 1) + [30.0]
    r = judged('jointState', tmp_path, msgs, rate=50.0)
    assert r.verdict == PASS, r.reasons
    assert any(w.startswith('reported velocity of %s beyond' % JOINTS[-1]) for w in r.warnings), r.warnings


def _odom_at(x, vx):
    m = odometry(0, x=x)
    m.twist.twist.linear.x = vx
    return m


def test_odometry_of_a_robot_standing_still_passes(tmp_path):
    r = judged('odometry', tmp_path, [_odom_at(1.0, 0.0) for _ in range(37)])
    assert r.verdict == PASS, r.reasons


def test_odometry_pose_jumps_and_twist_against_pose(tmp_path):
    msgs = [_odom_at(0.01 * i + (1.0 if i >= 20 else 0.0), 0.15) for i in range(37)]
    r = judged('odometry', tmp_path, msgs)
    assert r.verdict == FAIL
    one_reason_with(r, 'pose jumps: consecutive poses imply more than max_speed 0.8 m/s (Pepper '
                       'drives at most ~0.55 m/s)')
    # the twist says 0.4 m/s, the poses stand still
    r = judged('odometry', tmp_path, [_odom_at(0.0, 0.4) for _ in range(37)])
    assert r.verdict == FAIL
    one_reason_with(r, 'twist contradicts the pose: |twist| and the speed the poses imply differ by '
                       'more than twist_tolerance 0.25 m/s')


# ------------------------------------------------------------------ IMU

@pytest.mark.parametrize('kw, words', [
    (dict(orientation=(0, 0, 0, 0.5)), 'orientation is not a unit quaternion (norm 0.5)'),
    (dict(acc_z=float('nan')), 'angular velocity or linear acceleration holds NaN or inf'),
    (dict(acc_z=float('inf')), 'angular velocity or linear acceleration holds NaN or inf'),
    (dict(orientation_covariance=[float('nan')] * 9), 'orientation covariance holds NaN or inf'),
    (dict(acceleration_covariance=[0.0] * 8 + [float('inf')]), 'linear acceleration covariance holds NaN or inf'),
])
def test_imu_faults(tmp_path, kw, words):
    r = judged('imu', tmp_path, [imu(i, **kw) for i in range(N)])
    assert r.verdict == FAIL
    one_reason_with(r, words)


UNKNOWN = UNKNOWN_COVARIANCE


def test_imu_with_unknown_covariance_is_checked(tmp_path):
    """covariance[0] == -1 (as naoqi_driver sends) means the covariance is unknown, not that the
    data may be skipped: a good IMU passes, a NaN or zero attitude fails."""
    r = judged('imu', tmp_path, [imu(i, covariance=UNKNOWN) for i in range(N)])
    assert r.verdict == PASS, r.reasons
    assert r.values.acceleration_norm_m_s2.mean == pytest.approx(9.81)
    nan = (float('nan'),) * 4
    r = judged('imu', tmp_path, [imu(i, orientation=nan, orientation_covariance=UNKNOWN) for i in range(N)])
    assert r.verdict == FAIL
    one_reason_with(r, 'orientation holds NaN or inf (covariance -1 means unknown covariance')
    r = judged('imu', tmp_path, [imu(i, orientation=(0, 0, 0, 0), orientation_covariance=UNKNOWN) for i in range(N)])
    one_reason_with(r, 'orientation is not a unit quaternion (norm 0)')
    r = judged('imu', tmp_path, [imu(i, acc_z=float('nan'), acceleration_covariance=UNKNOWN) for i in range(N)])
    one_reason_with(r, 'angular velocity or linear acceleration holds NaN or inf')


# ------------------------------------------------------------------ the generic stream checks

def test_wrong_message_type_names_both_types(tmp_path):
    run = make_run('backSonar', tmp_path, topic='/naoqi_driver/sonar/back')
    for i in range(10):
        run.feed_raw('std_msgs/String', serialized(String(data='x')), T0 + 0.1 * i, R0 + 0.1 * i)
    r = close(run, lookup=lambda topic: ('std_msgs/String', ['/talker']))
    assert r.verdict == FAIL and r.messages == 0
    assert r.reasons[0] == ('topic /naoqi_driver/sonar/back carries std_msgs/String, '
                            'expected sensor_msgs/Range')
    assert r.received_type == 'std_msgs/String'


@pytest.mark.parametrize('lookup, words', [
    (lambda topic: (None, []), 'no publisher on /t (is the driver running'),
    (lambda topic: ('sensor_msgs/Image', []), 'topic /t is advertised as sensor_msgs/Image, expected '
                                              'sensor_msgs/Range'),
    (lambda topic: ('sensor_msgs/Range', ['/sonar_node']), 'no message on /t within 2.0 s although '
                                                           '/sonar_node publishes it'),
    (lambda topic: None, 'no message on /t within 2.0 s'),
    (None, 'no message on /t within 2.0 s'),
])
def test_no_messages_names_the_cause(tmp_path, lookup, words):
    run = make_run('backSonar', tmp_path)
    assert run.due(T0 + 1.0) == ''
    reason = run.due(T0 + 2.0)
    assert reason == 'no message within 2.0 s'
    r = close(run, at=2.0, reason=reason, lookup=lookup)
    assert r.verdict == FAIL and r.messages == 0
    assert len(r.reasons) == 1 and r.reasons[0].startswith(words), r.reasons
    assert r.stopped_because == reason and r.rate_hz is None


def test_corrupt_message_is_a_finding_not_a_crash(tmp_path):
    run = make_run('backSonar', tmp_path)
    feed(run, [sonar(i) for i in range(N)])
    run.feed_raw('sensor_msgs/Range', b'\x01\x02\x03', T0 + 2.9, R0 + 2.9)
    r = close(run)
    assert r.verdict == FAIL
    one_reason_with(r, 'message could not be decoded')


def test_too_few_messages(tmp_path):
    r = judged('backSonar', tmp_path, [sonar(i) for i in range(2)], start=2.5, rate=5.0)
    assert r.verdict == FAIL
    one_reason_with(r, 'only 2 messages in 3.0 s (at least 3 expected)')


@pytest.mark.parametrize('rate, words', [(2.0, 'rate 2.00 Hz outside the expected 4-16 Hz'),
                                         (40.0, 'rate 40.00 Hz outside the expected 4-16 Hz')])
def test_rate_outside_band(tmp_path, rate, words):
    n = int(2.8 * rate)
    r = judged('backSonar', tmp_path, [sonar(i) for i in range(n)], rate=rate)
    assert r.verdict == FAIL
    one_reason_with(r, words)
    one_reason_with(r, 'header stamp rate')


def test_header_stamp_rate_is_checked_apart_from_arrival_rate(tmp_path):
    """Messages arrive at 10 Hz, but their stamps advance as if the sensor ran at 30 Hz."""
    r = judged('backSonar', tmp_path, [sonar(i) for i in range(N)], stamp=lambda i, ros: R0 + i / 30.0)
    assert 9 < r.rate_hz < 11
    assert r.verdict == FAIL
    one_reason_with(r, 'header stamp rate 30.00 Hz outside')


def test_zero_stamps(tmp_path):
    r = judged('backSonar', tmp_path, [sonar(i) for i in range(N)], stamp=lambda i, ros: 0)
    assert r.verdict == FAIL
    one_reason_with(r, '25 messages with a zero header stamp')
    assert r.stats.zero_stamps == N and r.stamp_rate_hz is None


def test_backwards_stamps(tmp_path):
    r = judged('backSonar', tmp_path, [sonar(i) for i in range(N)],
               stamp=lambda i, ros: ros - (0.5 if i == 10 else 0.01))
    assert r.verdict == FAIL
    one_reason_with(r, 'header stamps went backwards 1 time')


def test_repeated_stamps_are_a_warning(tmp_path):
    r = judged('backSonar', tmp_path, [sonar(i) for i in range(N)],
               stamp=lambda i, ros: R0 + (i - (i == 10)) / 10.0)
    assert r.verdict == PASS, r.reasons
    assert '1 repeated header stamp' in r.warnings


@pytest.mark.parametrize('delay, words', [(30.0, 'clock offset: header stamps are a constant 30.0 s behind'),
                                          (-3.0, 'clock offset: header stamps are a constant 3.0 s ahead of')])
def test_stale_and_future_stamps(tmp_path, delay, words):
    r = judged('backSonar', tmp_path, [sonar(i) for i in range(N)], delay=delay)
    assert r.verdict == FAIL
    one_reason_with(r, words)


def test_publisher_that_stops_mid_window(tmp_path):
    run = make_run('backSonar', tmp_path)
    run.observe_connections(1, T0 + 0.1)
    feed(run, [sonar(i) for i in range(10)])          # 0.05 .. 0.95 s
    run.observe_connections(0, T0 + 1.2)
    r = close(run, at=2.95)
    assert r.verdict == FAIL
    reason = one_reason_with(r, 'messages stopped 0.9 s after the first one; nothing for the last 2.0 s')
    assert reason.endswith('(publisher left at 1.2 s)')


def test_pause_in_the_middle_is_a_warning(tmp_path):
    run = make_run('backSonar', tmp_path)
    t = feed(run, [sonar(i) for i in range(10)])
    feed(run, [sonar(i) for i in range(10)], start=t - T0 + 1.3)   # 1.3 s pause
    r = close(run)
    assert r.verdict == PASS, r.reasons
    assert any('1 pause longer than 1.00 s (longest 1.30 s' in w for w in r.warnings), r.warnings


def test_when_a_window_ends(tmp_path):
    run = make_run('backSonar', tmp_path, wait=2.0, duration=3.0)
    feed(run, [sonar(i) for i in range(5)])
    assert run.due(T0 + 2.5) == ''              # messages came: the wait does not apply
    assert run.due(T0 + 3.0) == 'window ended'


def test_late_first_message_extends_the_window(tmp_path):
    run = make_run('backSonar', tmp_path, wait=5.0, duration=2.0)
    assert run.due(T0 + 2.5) == ''
    feed(run, [sonar(i) for i in range(3)], start=3.0)
    assert run.due(T0 + 4.9) == ''
    assert run.due(T0 + 5.0) == 'window ended'  # first message + min(window, 2 s)


def test_quick_ends_once_settled(tmp_path):
    quick = make_run('backSonar', tmp_path, quick=True, duration=10.0)
    slow = make_run('backSonar', tmp_path, quick=False, duration=10.0)
    for run in (quick, slow):
        feed(run, [sonar(i) for i in range(9)])
        assert run.due(T0 + 1.0) == ''           # 9 < quick_messages (10)
        feed(run, [sonar(i) for i in range(1)], start=0.95)
    assert quick.due(T0 + 1.0) == 'verdict settled (--quick)'
    assert slow.due(T0 + 1.0) == ''


def test_interrupted_window_says_so(tmp_path):
    run = make_run('backSonar', tmp_path)
    feed(run, [sonar(i) for i in range(12)])
    r = close(run, at=1.2, reason='interrupted')
    assert r.stopped_because == 'interrupted'
    assert r.verdict == 'INTERRUPTED'     # not judged: never a FAIL blaming the robot
    assert r.reasons == ['interrupted after 1.2 s of the 3.0 s window (12 messages)']


def test_messages_outside_the_window_are_ignored(tmp_path):
    plan = SensorPlan(catalog.SENSORS['backSonar'], '/t', ROBOT['backSonar'])
    run = SensorRun(plan, RunContext(str(tmp_path), 'robot', Options()), T0)
    run.feed_raw('sensor_msgs/Range', serialized(sonar(0)), T0, R0)       # before begin()
    run.begin(T0)
    feed(run, [sonar(i) for i in range(N)])
    r = close(run)
    run.feed_raw('sensor_msgs/Range', serialized(sonar(0)), T0 + 3.1, R0 + 3.1)   # after close()
    assert r.messages == N and run.stats.count == N
    assert run.close(T0 + 4, 'again') is r                       # closing twice: same result


def test_audio_message_types_of_both_packages():
    assert message_class('naoqi_driver/AudioCustomMsg').__module__.startswith('pepper_interface_tests')
    mic = catalog.SENSORS['microphone']
    assert catalog.accepts_type(mic, 'naoqi_driver/AudioCustomMsg')
    assert catalog.accepts_type(mic, 'pepper_interface_tests/AudioCustomMsg')
    assert not catalog.accepts_type(mic, 'std_msgs/String')
    assert not catalog.accepts_type(catalog.SENSORS['laser'], 'sensor_msgs/Range')


# ------------------------------------------------------------------ stats.py

def test_stats_rates_and_intervals():
    s = StreamStats(start=10.0)
    for i in range(11):
        s.add(10.5 + 0.1 * i, 100.0 + 0.05 * i, 100.01 + 0.05 * i)
    assert s.count == 11
    assert s.rate == pytest.approx(10.0)
    assert s.stamp_rate == pytest.approx(20.0)
    assert s.first_latency == pytest.approx(0.5)
    assert s.jitter == pytest.approx(0.0, abs=1e-9)
    assert s.max_interval == pytest.approx(0.1)
    assert s.delay_summary()['mean'] == pytest.approx(0.01)
    assert s.gaps(0.2) == []


def test_stats_gaps_and_jitter():
    s = StreamStats(start=0.0)
    for t in (0.0, 0.1, 0.2, 1.7, 1.8, 3.0):
        s.add(t)
    gaps = s.gaps(1.0)
    assert [(round(a, 3), round(b, 3)) for a, b in gaps] == [(0.2, 1.5), (1.8, 1.2)]
    assert s.max_interval == pytest.approx(1.5)
    assert s.jitter > 0.5
    assert s.stamp_rate is None and s.delay_summary() is None   # no headers


def test_stats_zero_backwards_and_repeated_stamps():
    s = StreamStats(start=0.0)
    for i, stamp in enumerate([0.0, 5.0, 5.1, 5.1, 4.9, 0.0, 5.3]):
        s.add(0.1 * i, stamp, 6.0)
    assert s.zero_stamps == 2
    assert s.repeated == 1
    assert s.backwards == 1
    assert s.stamps == [5.0, 5.1, 5.1, 4.9, 5.3]
    assert s.stamp_rate is None              # not trusted once stamps went backwards
    assert s.count == 7                      # every message counts for the arrival rate


def test_stats_edge_cases():
    s = StreamStats()
    assert (s.count, s.rate, s.jitter, s.first_latency, s.max_interval) == (0, None, None, None, None)
    assert s.gaps(1.0) == [] and s.rate_series() == []
    s.add(3.0)
    assert s.rate is None                    # one message: no rate
    s.add(3.0)
    assert s.rate is None                    # no time between them: no rate, no division by zero


def test_stats_rate_series_and_summary():
    s = StreamStats(start=0.0)
    for i in range(30):
        s.add(0.05 + 0.1 * i if i < 20 else 2.05 + 0.2 * (i - 20), 1.0 + 0.1 * i, 1.02 + 0.1 * i)
    series = s.rate_series(end=4.0)
    assert [t for t, _ in series] == [0.5, 1.5, 2.5, 3.5]
    assert [hz for _, hz in series] == [10.0, 10.0, 5.0, 5.0]
    d = s.summary()
    assert d.messages == 30 and d.zero_stamps == 0 and d.delay_s.max == pytest.approx(0.02)
    json.dumps(codec.to_json(d))


def test_value_helpers():
    a = Acc()
    for v in (1.0, 2.0, float('nan'), 6.0, float('inf')):
        a.add(v)
    assert a.as_dict() == {'min': 1.0, 'mean': 3.0, 'max': 6.0} and a.nonfinite == 2
    assert a.text('m') == 'min 1, mean 3, max 6 m'
    assert Acc().text() == 'no finite values'
    assert fmt(0.5236) == '0.5236' and fmt(2.0) == '2' and fmt(float('nan')) == 'nan'
    assert fmt([1.0, 0.25]) == '[1, 0.25]' and fmt(0.0) == '0'
    t = Tally()
    t.add('k', 'range bad', 4.0)
    t.add('k', 'range bad', 9.0)
    assert t.reasons(10) == ['range bad in 2 of 10 messages (e.g. 4)']


# ------------------------------------------------------------------ lanes

def _plan(tmp_path, platform, mode, sensors):
    d = tmp_path / 'files'
    d.mkdir(exist_ok=True)
    (d / 'config.ini').write_text('platform %s\nmode %s\n' % (platform, mode))
    (d / 'topics.dat').write_text(''.join('%s /%s\n' % (n, n) for n in catalog.SENSORS))
    return settings.load_plan(Options(config=str(d / 'config.ini'), topics=str(d / 'topics.dat'),
                                      sensors=tuple(sensors), output_dir=str(tmp_path / 'out'),
                                      duration=2, wait=1))


def test_lanes_sequential_is_one_lane_in_order(tmp_path):
    order = ['odometry', 'frontCamera', 'laser', 'backSonar']
    lanes = lanes_for(_plan(tmp_path, 'robot', 'sequential', order))
    assert [[s.name for s in lane] for lane in lanes] == [order]


def test_lanes_parallel_on_the_robot_one_per_sensor(tmp_path):
    order = ['frontCamera', 'laser', 'bottomCamera', 'depthCamera']
    lanes = lanes_for(_plan(tmp_path, 'robot', 'parallel', order))
    assert [[s.name for s in lane] for lane in lanes] == [[n] for n in order]


def test_lanes_parallel_in_the_simulator_cameras_share_one_lane(tmp_path):
    order = ['laser', 'frontCamera', 'backSonar', 'depthCamera', 'stereoCamera', 'bottomCamera']
    plan = _plan(tmp_path, 'simulator', 'parallel', order)
    lanes = [[s.name for s in lane] for lane in lanes_for(plan)]
    assert lanes == [['laser'], ['frontCamera', 'depthCamera', 'bottomCamera'], ['backSonar'],
                     ['stereoCamera']]     # stereo is skipped in the simulator: its own lane


# ------------------------------------------------------------------ the runner, with a real bag

def write_bag(path, topics, seconds=8.0, rate=10.0, begin=R0):
    """topics: {topic: builder(i)}; messages recorded at `rate`, stamps 10 ms before recording."""
    with rosbag.Bag(str(path), 'w') as bag:
        for topic, build in topics.items():
            for i in range(int(seconds * rate)):
                t = begin + i / rate
                m = build(i)
                m.header.stamp = genpy.Time.from_sec(t - 0.01)
                bag.write(topic, m, genpy.Time.from_sec(t))
    return str(path)


class Interrupter(RunObserver):
    """An observer that presses Ctrl-C after `after` seconds of run time."""

    def __init__(self, after):
        self.after = after
        self.start = None

    def run_started(self, run, plan):
        self.start = None

    def tick(self, runs, now):
        self.start = now if self.start is None else self.start
        if now - self.start >= self.after:
            raise KeyboardInterrupt


class Broken(RunObserver):
    """An observer that fails: the run must go on."""

    def sensor_done(self, result):
        raise RuntimeError('observer failed')


def run_bag(tmp_path, mode, sensors, extra_observers=(), cameras=None):
    bag = write_bag(tmp_path / 'run.bag', {'/laser': laser, '/back': sonar})
    d = tmp_path / 'files'
    d.mkdir(exist_ok=True)
    (d / 'config.ini').write_text('platform robot\nmode %s\n' % mode)
    (d / 'topics.dat').write_text('Laser /laser\nBackSonar /back\nFrontSonar /front\n'
                                  'RealSenseCameraRGB /rs\n')
    out = tmp_path / 'out'
    out.mkdir(exist_ok=True)
    plan = settings.load_plan(Options(config=str(d / 'config.ini'), topics=str(d / 'topics.dat'),
                                      sensors=tuple(sensors), output_dir=str(out), duration=2,
                                      wait=1, cameras=cameras))
    source = BagSource(bag)
    ctx = RunContext(plan.output_dir, plan.platform, plan.options)
    term = io.StringIO()
    runner = Runner(plan, ctx, source, clock=source.clock,
                    observers=[Terminal(stream=term)] + list(extra_observers)
                    + [ResultFiles(str(out), out=io.StringIO())])
    run = runner.execute()
    return run, out, term.getvalue()


def test_runner_sequential_follows_the_given_order(tmp_path):
    run, out, term = run_bag(tmp_path, 'sequential', ['laser', 'realsenseRGBCamera', 'frontSonar', 'backSonar'],
                             cameras='pepper')
    r = {s.name: s for s in run.sensors}
    assert [s.name for s in run.sensors] == ['laser', 'realsenseRGBCamera', 'frontSonar', 'backSonar']
    assert (r['laser'].verdict, r['backSonar'].verdict) == (PASS, PASS), (r['laser'].reasons, r['backSonar'].reasons)
    assert r['realsenseRGBCamera'].verdict == SKIPPED
    assert r['frontSonar'].verdict == FAIL and r['frontSonar'].reasons == ['topic /front is not in the bag']
    # one after another, in this order, each a full window (bag time: exact)
    assert r['laser'].started_at == pytest.approx(0.0, abs=0.06)
    assert r['frontSonar'].started_at >= r['laser'].ended_at
    assert r['backSonar'].started_at >= r['frontSonar'].ended_at
    assert r['laser'].window_s == pytest.approx(2.0, abs=0.06)
    assert r['frontSonar'].window_s == pytest.approx(1.0, abs=0.06)      # --wait
    assert run.exit_code == results.EXIT_FAIL and not run.interrupted
    assert term.index('laser') < term.index('frontSonar') < term.rindex('backSonar')
    assert '2 passed, 1 failed, 1 skipped' in term


def test_runner_parallel_starts_everything_at_once(tmp_path):
    run, out, _ = run_bag(tmp_path, 'parallel', ['backSonar', 'laser'])
    assert [s.verdict for s in run.sensors] == [PASS, PASS]
    assert all(s.started_at == 0.0 for s in run.sensors)
    assert all(s.ended_at == pytest.approx(2.0, abs=0.06) for s in run.sensors)
    assert run.exit_code == results.EXIT_PASS


def test_runner_interrupt_finishes_the_files(tmp_path):
    run, out, term = run_bag(tmp_path, 'sequential', ['laser', 'backSonar'], [Interrupter(1.0)])
    assert run.interrupted and run.exit_code == results.EXIT_INTERRUPTED
    assert run.interrupt_reason == 'interrupted by Ctrl-C'
    laser, sonar_ = run.sensors
    assert laser.stopped_because == 'interrupted' and laser.messages >= 9
    assert sonar_.verdict == SKIPPED
    assert sonar_.reasons == ['not run: the run was interrupted before it started']
    dat = (out / results.OUTPUT_FILE).read_text()
    assert '[INTERRUPTED] interrupted by Ctrl-C' in dat
    assert re.search(r'\[END TIME\] \d{4}-\d\d-\d\d\.\d\d:\d\d:\d\d\n', dat)
    data = json.loads((out / results.JSON_FILE).read_text())
    assert data['interrupted'] is True and data['exit_code'] == 130
    assert [s['name'] for s in data['sensors']] == ['laser', 'backSonar']
    assert ET.parse(str(out / results.JUNIT_FILE)).getroot().get('tests') == '2'
    assert 'INTERRUPTED: interrupted by Ctrl-C' in term


def test_runner_simulator_cameras_one_at_a_time_in_parallel_mode(tmp_path):
    """Gazebo cannot render several cameras at once at full rate: in parallel mode the simulator's
    cameras share one lane, while the other sensors still run at the same time."""
    bag = write_bag(tmp_path / 'sim.bag', {'/laser': laser, '/back': sonar})
    d = tmp_path / 'files'
    d.mkdir()
    (d / 'config.ini').write_text('platform simulator\nmode parallel\n')
    (d / 'topics.dat').write_text('laserSensor /laser\nbackSonar /back\nfrontCamera /front_cam\n'
                                  'bottomCamera /bottom_cam\ndepthCamera /depth_cam\n')
    out = tmp_path / 'out'
    out.mkdir()
    plan = settings.load_plan(Options(config=str(d / 'config.ini'), topics=str(d / 'topics.dat'),
                                      sensors=('frontCamera', 'laser', 'bottomCamera', 'backSonar',
                                               'depthCamera', 'imu'),
                                      output_dir=str(out), duration=2, wait=1, record=False, show=False))
    source = BagSource(bag)
    source.live = True   # replayed as if live: the lanes of a live simulator run
    runner = Runner(plan, RunContext(plan.output_dir, plan.platform, plan.options), source,
                    clock=source.clock, observers=[ResultFiles(str(out), out=io.StringIO())])
    run = runner.execute()
    r = {s.name: s for s in run.sensors}
    assert [s.name for s in run.sensors] == [p.name for p in plan.sensors]
    cams = [r['frontCamera'], r['bottomCamera'], r['depthCamera']]
    for a, b in zip(cams, cams[1:]):
        assert b.started_at >= a.ended_at                 # one camera at a time
    assert r['laser'].started_at == 0.0 and r['backSonar'].started_at == 0.0
    assert r['laser'].ended_at > r['bottomCamera'].started_at       # overlapping the cameras
    assert (r['laser'].verdict, r['backSonar'].verdict) == (PASS, PASS)
    assert r['imu'].verdict == SKIPPED
    assert all(c.reasons == ['topic %s is not in the bag' % c.topic] for c in cams)
    # a real bag replay (sensorTest --bag) has no Gazebo behind it: all cameras at once
    out2 = tmp_path / 'out2'
    out2.mkdir()
    plan2 = settings.replace(plan, output_dir=str(out2))
    source = BagSource(bag)
    run = Runner(plan2, RunContext(plan2.output_dir, plan2.platform, plan2.options), source,
                 clock=source.clock, observers=[ResultFiles(str(out2), out=io.StringIO())]).execute()
    assert {s.name: s.started_at for s in run.sensors if s.name.endswith('Camera')} == \
        {'frontCamera': 0.0, 'bottomCamera': 0.0, 'depthCamera': 0.0}


def test_a_failing_observer_does_not_stop_the_run(tmp_path, capsys):
    run, out, _ = run_bag(tmp_path, 'parallel', ['backSonar', 'laser'], [Broken()])
    assert [s.verdict for s in run.sensors] == [PASS, PASS]
    data = json.loads((out / results.JSON_FILE).read_text())
    assert [s['verdict'] for s in data['sensors']] == [PASS, PASS]
    assert 'observer failed' in capsys.readouterr().err


# ------------------------------------------------------------------ result writers

def sample_run(tmp_path):
    """A run with a real PASS (from a SensorRun), a FAIL with XML-hostile text and a SKIPPED."""
    ok = judged('backSonar', tmp_path, [sonar(i) for i in range(N)])
    bad = SensorResult(name='laser', title='LASER', topic='/naoqi_driver/laser',
                       msg_type='sensor_msgs/LaserScan', verdict=FAIL,
                       reasons=['range <min> & "max" wrong', 'rate 2.00 Hz outside the expected 4-16 Hz'],
                       warnings=['1 pause'], messages=6, rate_hz=2.0, window_s=3.0,
                       fields=[['Frame id', 'base_footprint']], stopped_because='window ended',
                       rate_series=[(0.5, 2.0)])
    skipped = SensorResult(name='imu', title='IMU', topic=None, msg_type='sensor_msgs/Imu',
                           verdict=SKIPPED, reasons=['not available in the simulator'])
    run = RunResult(platform='robot', mode='sequential', start=1700000000.0, end=1700000012.5,
                    output_dir=str(tmp_path), sensors=[ok, bad, skipped])
    return run


def test_output_file_blocks(tmp_path):
    run = sample_run(tmp_path)
    path = str(tmp_path / results.OUTPUT_FILE)
    for _ in range(2):                     # appended, never truncated
        f = files.OutputFile(path)
        f.begin(run)
        for s in run.sensors:
            f.sensor(s)
        f.end(run)
        f.close()
    text = open(path).read()
    assert text.count('[TESTING] ############ SENSORS ############') == 2
    assert text.count('[END TIME] %s' % results.timestamp(run.end)) == 2
    first = text.split('[TESTING] ############ SENSORS ############')[1]
    assert re.search(r'\[START TIME\] \d{4}-\d\d-\d\d\.\d\d:\d\d:\d\d\n', first)
    sonar_block = first.split('[TESTING] ---- BACK SONAR ----\n')[1].split('\n\n')[0].splitlines()
    assert sonar_block[0] == '[TOPIC] /t (sensor_msgs/Range)'
    assert sonar_block[1] == '[MESSAGES] Printing back sonar data received.'
    assert [ln.split(':')[0] for ln in sonar_block[2:7]] == ['Frame id', 'Field of view', 'Minimum range value',
                                                         'Maximum range value', 'Range value']
    assert sonar_block[7] == '[END MESSAGES] Finished printing.'
    assert sonar_block[8].startswith('[SUMMARY] 25 messages in 3.0 s, rate 10.00 Hz')
    assert sonar_block[-1] == '[RESULT] PASS'
    assert '[RESULT] FAIL: range <min> & "max" wrong; rate 2.00 Hz outside the expected 4-16 Hz' in first
    assert '[WARNING] 1 pause' in first
    assert '[TESTING] ---- IMU ----\n[RESULT] SKIPPED: not available in the simulator\n' in first
    assert '[SUMMARY] 1 passed, 1 failed, 1 skipped\n[END TIME]' in first
    assert '[INTERRUPTED]' not in text


def test_output_file_interrupted(tmp_path):
    run = sample_run(tmp_path)
    run.interrupted, run.interrupt_reason = True, 'the ROS master at http://x:1 went away'
    f = files.OutputFile(str(tmp_path / 'o.dat'))
    f.begin(run)
    f.end(run)
    f.close()
    text = open(str(tmp_path / 'o.dat')).read()
    assert '[INTERRUPTED] the ROS master at http://x:1 went away\n' in text
    assert text.index('[INTERRUPTED]') < text.index('[END TIME]')


def test_json_fields(tmp_path):
    run = sample_run(tmp_path)
    path = str(tmp_path / results.JSON_FILE)
    files.write_json(run, path)
    data = files.load_json(path)
    assert data['schema_version'] == results.SCHEMA_VERSION
    assert (data['platform'], data['mode'], data['exit_code']) == ('robot', 'sequential', 1)
    assert data['summary'] == {PASS: 1, FAIL: 1, SKIPPED: 1, 'INTERRUPTED': 0}
    assert data['start'] == results.timestamp(run.start) and data['end_unix'] == 1700000012.5
    by = {s['name']: s for s in data['sensors']}
    assert by['laser']['reasons'][0] == 'range <min> & "max" wrong'
    assert by['backSonar']['messages'] == N and by['backSonar']['expected_rate_hz'] == [4.0, 16.0]
    assert by['backSonar']['fields'][0] == ['Frame id', 'SonarBack_frame']
    assert by['imu']['verdict'] == SKIPPED
    for s in data['sensors']:
        for key in ('verdict', 'reasons', 'warnings', 'messages', 'rate_hz', 'topic', 'stats',
                    'window_s', 'stopped_because', 'started_at', 'ended_at'):
            assert key in s
        assert 'series' not in s            # plots only on request
    assert 'series' in run.to_dict(with_series=True)['sensors'][0]
    assert not [f for f in os.listdir(str(tmp_path)) if f.startswith('.tmp-')]


def test_exit_codes():
    def run(*verdicts, interrupted=False):
        r = RunResult(platform='robot', mode='parallel', start=0.0, interrupted=interrupted)
        r.sensors = [SensorResult(name=str(i), title='', topic=None, msg_type='', verdict=v)
                     for i, v in enumerate(verdicts)]
        return r.exit_code
    assert run(PASS, SKIPPED, PASS) == 0          # SKIPPED counts as passed
    assert run(SKIPPED) == 0 and run() == 0
    assert run(PASS, FAIL, SKIPPED) == 1
    assert run(PASS, interrupted=True) == 130


def test_junit_xml(tmp_path):
    run = sample_run(tmp_path)
    path = str(tmp_path / results.JUNIT_FILE)
    files.write_junit(run, path)
    root = ET.parse(path).getroot()
    assert root.tag == 'testsuite'
    assert (root.get('tests'), root.get('failures'), root.get('skipped')) == ('3', '1', '1')
    assert float(root.get('time')) == pytest.approx(12.5)
    cases = root.findall('testcase')
    assert [c.get('name') for c in cases] == ['backSonar', 'laser', 'imu']
    passed, failed, skipped = cases
    assert passed.find('failure') is None and passed.find('skipped') is None
    assert 'topic: /t' in passed.find('system-out').text
    failure = failed.find('failure')
    assert failure.get('message') == ('range <min> & "max" wrong; '
                                      'rate 2.00 Hz outside the expected 4-16 Hz')
    assert 'topic: /naoqi_driver/laser' in failure.text
    assert skipped.find('skipped').get('message') == 'not available in the simulator'
    props = {p.get('name'): p.get('value') for p in root.find('properties')}
    assert props == {'platform': 'robot', 'mode': 'sequential', 'source': 'live', 'interrupted': 'false'}


def test_a_check_that_raises_fails_its_sensor_by_name(tmp_path):
    """A message a check cannot handle must not die silently in the subscriber thread."""
    run = make_run('backSonar', tmp_path)

    def broken(msg, t):
        raise ValueError('cannot handle this reading')
    run.check.on_message = broken
    feed(run, [sonar(i) for i in range(20)])
    r = close(run)
    assert r.verdict == FAIL and r.messages == 20
    assert any('could not be checked (ValueError: cannot handle this reading)' in x for x in r.reasons), r.reasons


def test_a_pass_with_warnings_shows_in_every_output(tmp_path, monkeypatch):
    """Issue 10, item 4: a suspicious but possible condition (here a pause in the stream) keeps
    the PASS, and every output says which PASS carries it: terminal PASS* with a legend, the
    .dat's [WARNING], the JSON's warnings, JUnit system-out, /diagnostics WARN."""
    from diagnostic_msgs.msg import DiagnosticStatus

    from pepper_interface_tests.outputs.diagnostics import result_status
    run = make_run('backSonar', tmp_path)
    msgs = [sonar(i) for i in range(N)]
    t = T0
    for i, m in enumerate(msgs):
        t = T0 + 0.05 + i / 10.0 + (1.5 if i >= 12 else 0.0)      # one 1.6 s pause
        m.header.stamp = genpy.Time.from_sec(R0 + (t - T0) - 0.01)
        run.feed_raw(run.sensor.msg_type, serialized(m), t, R0 + (t - T0))
    warned = close(run, at=4.5)
    assert warned.verdict == PASS and warned.warnings, (warned.reasons, warned.warnings)
    clean = judged('frontSonar', tmp_path, [sonar(i, frame_id='SonarFront_frame') for i in range(N)])
    assert clean.verdict == PASS and not clean.warnings, clean.warnings
    rr = RunResult(platform='robot', mode='parallel', start=1700000000.0, end=1700000005.0,
                   output_dir=str(tmp_path), sensors=[warned, clean])
    term = io.StringIO()
    monkeypatch.setenv('COLUMNS', '130')      # the summary as a table (narrower: one block per sensor)
    Terminal(stream=term).run_ended(rr)
    rows = {line.split()[0]: line for line in term.getvalue().splitlines() if line[:1].isalpha()}
    assert rows['backSonar'].split()[1] == 'PASS*' and 'warning: ' in rows['backSonar']
    assert rows['frontSonar'].split()[1] == 'PASS'
    assert 'PASS* = passed with 1 warning to read (not a failure)' in term.getvalue()
    f = files.OutputFile(str(tmp_path / results.OUTPUT_FILE))
    f.begin(rr)
    for s in rr.sensors:
        f.sensor(s)
    f.end(rr)
    f.close()
    files.write_json(rr, str(tmp_path / results.JSON_FILE))
    files.write_junit(rr, str(tmp_path / results.JUNIT_FILE))
    assert '[WARNING] ' + warned.warnings[0] in open(str(tmp_path / results.OUTPUT_FILE)).read()
    data = files.load_json(str(tmp_path / results.JSON_FILE))
    assert data['sensors'][0]['verdict'] == 'PASS' and data['sensors'][0]['warnings'] == warned.warnings
    case = ET.parse(str(tmp_path / results.JUNIT_FILE)).getroot().findall('testcase')[0]
    assert case.find('failure') is None and 'WARNING: ' + warned.warnings[0] in case.find('system-out').text
    status = result_status(warned)
    assert status.level == DiagnosticStatus.WARN and status.message.startswith('PASS with warnings: ')
    assert result_status(clean).level == DiagnosticStatus.OK


def test_suspicious_but_possible_conditions_are_warnings(tmp_path):
    """A constant 2 s clock offset (inside max_delay 5 s) and a rate near the band's edge
    keep the PASS and are named as warnings."""
    r = judged('backSonar', tmp_path, [sonar(i) for i in range(N)], delay=2.0)
    assert r.verdict == PASS, r.reasons
    assert any(w.startswith('clock offset: header stamps a constant 2.0 s behind') for w in r.warnings), r.warnings
    r = judged('backSonar', tmp_path, [sonar(i) for i in range(12)], rate=4.2)
    assert r.verdict == PASS, r.reasons
    assert any('near the edge of the expected 4-16 Hz' in w for w in r.warnings), r.warnings
