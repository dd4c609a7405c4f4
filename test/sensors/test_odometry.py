"""Every pose takes part in the odometry's jump rule (and every angle in the joints'): a value
that leaps away for one message and comes straight back is a jump, while stamp jitter, a
swaying torso, a robot driving at Pepper's top speed and pose streams of 1-50 Hz still pass.

Real nav_msgs/Odometry and sensor_msgs/JointState messages, serialized as they come off the
wire, fed through SensorRun with explicit receive and header times.
"""
import math
import os
import random

import genpy
import pytest

from check_runs import judged, one_reason_with
from fake_pepper import JOINTS, joints, odometry, serialized
from pepper_interface_tests.plan import catalog, settings
from pepper_interface_tests.plan.settings import Options, SensorPlan
from pepper_interface_tests.results import FAIL, PASS
from pepper_interface_tests.sensors.base import RunContext
from pepper_interface_tests.sensors.jumps import JumpWatch
from pepper_interface_tests.sensors.window import SensorRun

ROBOT = settings.read_expectations(os.path.join(settings.package_dir(), 'config',
                                                'sensorExpectations.yaml'), 'robot')
T0, R0 = 5000.0, 1700000000.0


def judged_at(name, msgs, rate, expect=None, duration=None, stamp=None):
    """Messages at `rate` Hz from 0.05 s; header stamps = ROS time - 0.01 unless `stamp`
    (i, ros time) -> s says otherwise (0: a zero stamp)."""
    duration = duration or (len(msgs) / rate + 0.5)
    plan = SensorPlan(catalog.SENSORS[name], '/t', ROBOT[name].but(**(expect or {})))
    run = SensorRun(plan, RunContext('/nonexistent-not-written', 'robot', Options()), T0,
                    quick=False, wait=2.0, duration=duration)
    run.begin(T0)
    for i, m in enumerate(msgs):
        t = T0 + 0.05 + i / rate
        ros = R0 + t - T0
        s = stamp(i, ros) if stamp else ros - 0.01
        m.header.stamp = genpy.Time.from_sec(s) if s else genpy.Time(0, 0)
        run.feed_raw(run.sensor.msg_type, serialized(m), t, ros)
    return run.close(T0 + duration, 'window ended', None)


def odom(x, y=0.0, speed=0.0):
    from geometry_msgs.msg import Quaternion
    from nav_msgs.msg import Odometry
    m = Odometry(child_frame_id='base_link')
    m.header.frame_id = 'odom'
    m.pose.pose.position.x, m.pose.pose.position.y = x, y
    m.pose.pose.orientation = Quaternion(0, 0, 0, 1.0)
    m.twist.twist.linear.x = speed
    return m


def jump_reasons(r):
    return [x for x in r.reasons if x.startswith('pose jumps')]


# ------------------------------------------------------------------ the spike

def test_a_pose_leaping_25_m_for_one_message_in_eight_fails_with_count_largest_and_when():
    """15 Hz, one pose in eight 25 m away and straight back: every pair of anchors 0.5 s apart
    (the old rule) sees only healthy poses."""
    msgs = [odom(0.1 * i / 15 + (25.0 if i % 8 == 7 else 0.0), speed=0.1) for i in range(45)]
    r = judged_at('odometry', msgs, 15.0)
    assert r.verdict == FAIL
    text = jump_reasons(r)
    assert text, r.reasons
    assert '5 jumps, the largest 25.0' in text[0], text           # poses 7, 15, 23, 31, 39
    assert 'at t = 0.52 s' in text[0], text                       # the first spike: 7 / 15 + 0.05
    assert 'from the pose 0.067 s before' in text[0], text
    assert r.values.pose_jumps == 5 and abs(r.values.largest_pose_jump_m - 25.0) < 0.05


def test_a_relocalised_pose_that_stays_is_one_jump():
    msgs = [odom(0.0 if i < 20 else 3.0) for i in range(60)]
    r = judged_at('odometry', msgs, 15.0)
    assert r.values.pose_jumps == 1, r.reasons
    assert 'pose jumps' in r.reasons[0] and '1 jump, the largest 3 m' in r.reasons[0]


def test_a_jump_spread_over_three_fast_messages_is_seen():
    """50 Hz, 0.3 m per message away for three messages and back: each step is small."""
    xs = [0.0] * 20 + [0.3, 0.6, 0.9, 0.6, 0.3] + [0.0] * 30
    r = judged_at('odometry', [odom(x) for x in xs], 50.0, expect={'rate': (1.0, 60.0)})
    assert r.verdict == FAIL and jump_reasons(r), r.reasons


# ------------------------------------------------------------------ healthy motion passes

@pytest.mark.parametrize('rate', [1.0, 5.0, 15.0, 50.0])
def test_driving_at_0_55_m_s_with_a_swaying_torso_and_jittery_stamps_passes(rate):
    rng = random.Random(7)
    n = int(6 * rate) + 3
    sway = [0.03 * math.sin(2 * math.pi * 1.5 * i / rate) for i in range(n)]
    msgs = [odom(0.55 * i / rate + sway[i], 0.02 * math.cos(2 * math.pi * 1.5 * i / rate), 0.55)
            for i in range(n)]
    r = judged_at('odometry', msgs, rate, expect={'rate': (0.5, 60.0)},
               # jitter up to 40 % of the period (more would reorder the stamps: its own rule)
               stamp=lambda i, ros: ros - 0.05 + rng.uniform(-0.2, 0.2) / rate)
    assert not jump_reasons(r), r.reasons
    assert r.verdict == PASS, r.reasons


def test_standing_still_with_noisy_stamps_and_zero_stamps_passes():
    rng = random.Random(3)
    msgs = [odom(1.0 + rng.uniform(-0.005, 0.005)) for _ in range(60)]
    r = judged_at('odometry', msgs, 15.0, stamp=lambda i, ros: ros + rng.uniform(-0.025, 0.025))
    assert r.verdict == PASS, r.reasons
    # zero stamps (a stamp rule of their own): the poses are judged on the receive times
    r = judged_at('odometry', [odom(0.5 * i / 15, speed=0.5) for i in range(60)], 15.0,
               stamp=lambda i, ros: 0)
    assert not jump_reasons(r) and r.values.pose_jumps == 0, r.reasons
    assert r.values.pose_implied_speed_m_s.max < 0.6


def test_jump_watch_counts_runs_and_starts_afresh():
    w = JumpWatch(0.8, 0.5)
    for i in range(10):
        assert w.add(i * 0.1, (0.0, 0.0), i * 0.1)
    assert not w.add(1.0, (5.0, 0.0), 1.0) and w.jumps == 1
    assert w.add(1.1, (0.0, 0.0), 1.1)                 # back: judged against the poses before
    assert not w.add(1.2, (5.0, 0.0), 1.2) and w.jumps == 2


# ------------------------------------------------------------------ joints: the same aliasing

def test_a_joint_spike_between_anchors_fails():
    """50 Hz: HeadYaw leaps 1.5 rad for one message in ten and comes back; the old rule's
    anchors 0.1 s (five messages) apart step over it."""
    rest = {j: 0.0 for j in JOINTS}
    msgs = []
    for i in range(125):
        pos = dict(rest)
        pos['HeadYaw'] = 1.5 if i % 10 == 7 else 0.0
        msgs.append(joints(i, position=[pos[j] for j in JOINTS]))
    r = judged_at('jointState', msgs, 50.0)
    assert r.verdict == FAIL
    hits = [x for x in r.reasons if x.startswith('position of HeadYaw jumps')]
    assert hits and '12 jumps' in hits[0] and 'the largest 1.5 rad' in hits[0], r.reasons


def test_joints_moving_at_their_limit_pass():
    """HeadYaw at 5 rad/s (below its URDF 7.33 rad/s) with jittery stamps."""
    rng = random.Random(5)
    msgs = []
    for i in range(125):
        pos = {j: 0.0 for j in JOINTS}
        pos['HeadYaw'] = 1.5 * math.sin(5.0 / 1.5 * i / 50.0)
        msgs.append(joints(i, position=[pos[j] for j in JOINTS]))
    r = judged_at('jointState', msgs, 50.0, stamp=lambda i, ros: ros + rng.uniform(-0.008, 0.008))
    assert r.verdict == PASS, r.reasons


def test_stamps_that_stop_moving_keep_the_watch_bounded():
    w = JumpWatch(0.8, 0.5)
    for i in range(2000):
        w.add(7.0, (0.0, 0.0), i * 0.02)
    assert len(w.refs) <= 128 and w.jumps == 0


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
