"""Unit: the motion check's rules (motion/rules.py) on recorded witnesses made up here: each
finding lands on the row of the sensor it concerns, the witnesses vote, and a motion that did
not happen fails no sensor."""
import math

import numpy as np
import pytest

from pepper_interface_tests.motion import rules
from pepper_interface_tests.motion.record import Recording, Scan
from pepper_interface_tests.motion.sequence import Sequence, Step
from pepper_interface_tests.plan.expectations import MotionExpect

E = MotionExpect()
INC = (2 * 2.0944) / 61          # naoqi_driver's angle_increment (laser.cpp:218)
ROOM = 1.0 + 0.8 * np.abs(np.sin(np.arange(61) * 0.37)) + 0.02 * np.arange(61)


def room_scan(turned):
    """The room's scan after the robot turned by `turned` rad (beams counter-clockwise)."""
    k = turned / INC
    x = np.arange(61) + k
    return np.interp(x, np.arange(61), ROOM, left=np.nan, right=np.nan)


def base_run(turn=0.5, odom=1.0, gyro=(0, 0, 1.0), laser=1.0, wheels=1.0, reversed_scan=False):
    """A base step of `turn` rad from t=1 to t=4 (ended), each witness seeing `factor` x the turn
    (gyro: per axis)."""
    rec = Recording()
    for i in range(61):
        t = i * 0.1
        f = min(max((t - 1.5) / 2.0, 0.0), 1.0)        # the turn happens between 1.5 and 3.5 s
        rate = turn / 2.0 if 1.5 <= t <= 3.5 else 0.0
        rec.odom_yaw.append((t, odom * turn * f))
        rec.gyro.append((t, gyro[0] * rate, gyro[1] * rate, gyro[2] * rate))
        rec.joints.append((t, {'HeadYaw': 0.0, 'WheelFL': wheels * 3 * f, 'WheelFR': wheels * 3 * f,
                               'WheelB': wheels * 3 * f}))
        if i % 2 == 0:
            r = room_scan(laser * turn * f)
            rec.scans.append(Scan(t, r[::-1] if reversed_scan else r, INC))
    seq = Sequence(E, rec, None, lambda: 0.0)
    seq.head_skip = 'not in this test'
    seq.steps = [Step('base', turn, turn, sent=1.0, ended=4.5, settled=True)]
    seq.index = 1
    return seq, rec


def judge(seq, rec):
    found = {}
    j = rules.Judge(seq, rec, E, lambda s, r, w: found.setdefault(s, (r, w)))
    fails, warns, skip = j.judge()
    return found, fails, warns, skip, j


def test_a_healthy_turn_puts_no_finding_on_any_sensor():
    found, fails, _, skip, j = judge(*base_run())
    assert not found and not fails
    assert j.base_state == 'moved'
    m = j.measured[0]
    assert m['odometry'] == pytest.approx(0.5, abs=0.01)
    assert m['gyro_z'] == pytest.approx(0.5, abs=0.03)
    assert m['laser'] == pytest.approx(0.5, abs=0.07)      # one beam is 0.069 rad


@pytest.mark.parametrize('kw, row, words', [
    (dict(gyro=(0, 0, -1.0)), 'imu', 'opposite sign'),
    (dict(gyro=(0, 0, 0)), 'imu', 'gyro reads about zero'),
    (dict(gyro=(1.0, 0, 0)), 'imu', "gyro's x axis"),
    (dict(odom=0.0), 'odometry', 'did not change'),
    (dict(odom=2.0), 'odometry', 'more than 35% off'),
    (dict(reversed_scan=True), 'laser', 'wrong way'),
    (dict(laser=0.0), 'laser', 'did not change'),
    (dict(wheels=0.0), 'jointState', 'wheel joints'),
])
def test_the_one_witness_that_disagrees_fails_on_its_own_row(kw, row, words):
    found, fails, _, _, j = judge(*base_run(**kw))
    assert set(found) == {row}, found
    assert any(words in r for r in found[row][0]), found[row]
    assert not fails and j.base_state == 'moved'


def test_a_base_that_did_not_move_fails_the_motion_row_and_no_sensor():
    found, fails, _, _, j = judge(*base_run(odom=0, gyro=(0, 0, 0), laser=0, wheels=0))
    assert not any(r for r, _ in found.values())
    assert j.base_state == 'did not move'
    assert any('the actuator, not a sensor' in f and 'charging flap' in f for f in fails)


def test_a_lone_witness_that_saw_a_turn_is_warned_not_failed():
    found, fails, _, _, j = judge(*base_run(odom=1.0, gyro=(0, 0, 0), laser=0, wheels=0))
    assert found['odometry'][0] == [] and 'alone saw a turn' in found['odometry'][1][0]
    assert j.base_state == 'did not move' and fails


def head_run(encoder=1.0, camera_px=None, cameras=('frontCamera',), contrast=40.0, ball=False):
    """Head steps +0.5 then -1.0 then +0.5 from HeadYaw 0; the encoder reads `encoder` x the
    truth; each camera's picture (a room of `contrast` grey levels) moves camera_px per rad of
    head yaw (default +60); ball: a bright ball crossing the picture on its own (2 px a frame)."""
    rec = Recording()
    px = 60.0 if camera_px is None else camera_px
    targets = [(0.0, 0.5), (3.0, -0.5), (6.0, 0.0)]

    def truth(t):
        h = 0.0
        for t0, target in targets:
            if t >= t0:
                start = h
                h = start + (target - start) * min((t - t0) / 1.0, 1.0)
        return h
    grid = np.linspace(0, 8 * math.pi, 400)
    texture = np.sin(grid) + 0.5 * np.sin(3.1 * grid + 1) + 0.3 * np.cos(7.3 * grid)
    for i in range(90):
        t = i * 0.1
        rec.joints.append((t, {'HeadYaw': encoder * truth(t)}))
        if i % 2 == 0:
            off = int(round(100 - px * truth(t)))
            frame = np.tile(128 + contrast * texture[off:off + 80], (20, 1)).astype(np.float32)
            if ball:
                x = 4 + 3 * (i % 22)        # 6 px a kept frame (one in two), as wide as the ball
                frame[8:14, x:x + 6] = 250.0
            for c in cameras:
                rec.frames.setdefault(c, []).append((t, frame))
    seq = Sequence(E, rec, None, lambda: 0.0)
    seq.base_skip = 'not in this test'
    seq.head_start = 0.0
    seq.steps = [Step('head', 0.5, 0.5, 0.0, 2.9, True), Step('head', -0.5, -1.0, 3.0, 5.9, True),
                 Step('head', 0.0, 0.5, 6.0, 8.5, True)]
    seq.index = 3
    return seq, rec


def test_a_head_that_follows_its_commands_passes():
    found, fails, _, skip, j = judge(*head_run())
    assert not found and not fails and j.head_state == 'moved'
    assert skip == 'base part skipped: not in this test'
    assert j.measured[1]['frontCamera'] < -20


def test_a_stuck_head_encoder_fails_jointstate_by_name_when_the_camera_saw_the_turn():
    found, fails, _, _, j = judge(*head_run(encoder=0.0))
    assert list(found) == ['jointState']
    assert 'HeadYaw did not move' in found['jointState'][0][0] and 'encoder is stuck' in found['jointState'][0][0]
    assert not fails


@pytest.mark.parametrize('px, words', [(0.0, 'not following'), (-60.0, 'wrong way')])
def test_a_camera_that_does_not_follow_the_head_fails(px, words):
    found, _, _, _, _ = judge(*head_run(camera_px=px))
    assert list(found) == ['frontCamera'] and words in found['frontCamera'][0][0]


def test_a_camera_on_a_plain_floor_with_a_ball_rolling_by_is_warned_not_failed():
    """A room with almost nothing to follow (0.5 grey levels): the ball, moving on its own,
    decides the shift. The camera cannot be judged, so it is warned; with the same ball in a
    textured room that does not follow the head, it fails."""
    found, fails, _, _, j = judge(*head_run(camera_px=0.0, contrast=0.5, ball=True))
    assert not fails and j.head_state == 'moved' and list(found) == ['frontCamera']
    reasons, warnings = found['frontCamera']
    assert not reasons and any('too little texture to follow' in w for w in warnings)
    found, _, _, _, _ = judge(*head_run(camera_px=0.0, ball=True))
    assert list(found) == ['frontCamera'] and 'not following' in found['frontCamera'][0][0]


def test_a_following_camera_on_a_plain_floor_still_passes():
    found, _, _, _, _ = judge(*head_run(contrast=0.5))
    assert not found


def test_a_head_that_did_not_move_fails_the_motion_row_not_the_sensors():
    found, fails, _, _, j = judge(*head_run(encoder=0.0, camera_px=0.0))
    assert not found and j.head_state == 'did not move'
    assert any('the head did not move' in f and 'Autonomous Life' in f for f in fails)


def test_a_part_skipped_before_moving_makes_the_row_skipped_with_the_reason():
    seq, rec = head_run()
    seq.base_skip = 'not enough free space (nothing may be within 0.50 m): the laser sees ...'
    _, fails, _, skip, _ = judge(seq, rec)
    assert not fails and skip.startswith('base part skipped: not enough free space')
