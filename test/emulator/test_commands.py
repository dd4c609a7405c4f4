"""The emulator takes naoqi_driver's three motion commands and its world follows (emulator/
commands.py, body.py), against a real roscore: real rospy publishers of /joint_angles,
/move_base_simple/goal and /cmd_vel and real subscribers of the sensors (test/nodes/emu_move.py,
its own process), the emulator as a subprocess.

One script per run (emu_move.py SCHEDULE): HeadYaw to +0.3 rad at speed 0.2, a moveTo
turning +0.5 rad, a move() at 0.3 rad/s stopped by a zero twist. A healthy
robot: every stream agrees with the commands. Each fault: its stream is wrong in the way the
fault says, the others stay right. Tolerances are the physics' (a 10 Hz gyro integrated over a
1.7 s turn, a 61-slot scan of 0.069 rad per slot, a picture of 160 columns), never a measured
number's digits, so they hold on a loaded machine: times come from header stamps.
"""
import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from driver_views import shift_right
from rosmaster import NODES, kill_group, script, spawn

MOVE = [sys.executable, os.path.join(NODES, 'emu_move.py')]
HEAD, TURN, SPIN = 0.3, 0.5, 0.3
HEAD_YAW_MAX_VEL = 7.33998                   # pepper.urdf:15 (ros-naoqi/pepper_robot)
LASER_INCREMENT = 2 * 2.0944 / 61            # naoqi_driver laser.cpp:213-222
FRONT_PX_PER_RAD = 160 / 0.9826              # QQVGA front camera, hfov 0.9826 rad (profiles.py)
# |p| / r of each wheel (pepper.urdf:1401, 1427, 1453; radius 0.334 - 0.264): its spin per
# rad of the base's turn in place, negative (axes point outwards, right-hand rule)
WHEEL_RATIO = {'WheelFL': math.hypot(0.09, 0.155) / 0.07, 'WheelFR': math.hypot(0.09, 0.155) / 0.07,
               'WheelB': 0.17 / 0.07}


def run_motion(master, tmp_path, faults=''):
    log = open(str(tmp_path / 'emulator.log'), 'w')
    emu = spawn(script('pepperEmulator') + ['--audio', 'off', '--camera-resolution', 'QQVGA']
                + (['--faults', faults] if faults else []), master.env(), stdout=log,
                stderr=subprocess.STDOUT)
    try:
        out = subprocess.run(MOVE, env=master.env(), stdout=subprocess.PIPE, timeout=90)
    finally:
        kill_group(emu)
        log.close()
    data = json.loads(out.stdout)
    assert 'error' not in data, data
    data['log'] = (tmp_path / 'emulator.log').read_text()
    return data


# when each command went out (emu_move.py SCHEDULE), s after the start of the recording
HEAD_AT, GOAL_AT, SPIN_AT, STOP_AT, END = 0.8, 1.4, 3.8, 4.5, 5.3
BEFORE_HEAD, BEFORE_TURN, AFTER_TURN = HEAD_AT - 0.05, GOAL_AT - 0.05, SPIN_AT - 0.05


def rows(data, key, t0, t1):
    return [r for r in data[key] if t0 <= r[0] <= t1]


def last(data, key, t):
    return [r for r in data[key] if r[0] <= t][-1]


def odom_yaw_change(d):
    return last(d, 'odom', AFTER_TURN)[ODOM_YAW] - last(d, 'odom', BEFORE_TURN)[ODOM_YAW]


# columns of a record: odom t, stamp, x, y, yaw, vx, wz; imu t, stamp, gx, gy, gz, ax, ay, az, yaw
ODOM_YAW, ODOM_WZ, GX, GY, GZ, AX, AZ, IMU_YAW = 4, 6, 2, 3, 4, 5, 7, 8


def gyro_turn(d, axis=GZ):
    """The gyro's rate on column `axis` integrated over the moveTo, on header stamps."""
    r = rows(d, 'imu', BEFORE_TURN, AFTER_TURN + 0.05)
    stamps, rate = np.array([x[1] for x in r]), np.array([x[axis] for x in r])
    return float(np.sum((rate[1:] + rate[:-1]) / 2 * np.diff(stamps)))


def wheel_turn(d, col):
    """The wheel's turn over the base turn: its angle is published wrapped to [-pi, pi)
    (emulator/body.py), so a wheel that crossed pi reads 2 pi off (WheelFR -1.28 rad read as
    +5.00 in one run); each expected turn here is under pi."""
    return math.remainder(last(d, 'joints', AFTER_TURN)[col] - last(d, 'joints', BEFORE_TURN)[col], 2 * math.pi)


def laser_shift(d):
    """k such that the scan after the turn, at slot i, reads what the scan before read at
    slot i + k (a turn left moves the room to lower angles, lower slots: k > 0)."""
    before = np.array(last(d, 'laser', BEFORE_TURN)[2])
    after = np.array(last(d, 'laser', AFTER_TURN)[2])
    best = None
    for k in range(-15, 16):
        a = after[max(0, -k):len(after) - max(0, k)]
        b = before[max(0, k):len(before) - max(0, -k)]
        ok = (a > 0) & (b > 0)
        if ok.sum() < 15:
            continue
        err = float(np.median(np.abs(a[ok] - b[ok])))
        if best is None or err < best[0]:
            best = (err, k)
    return best[1]


def camera_shift(d):
    """Columns the front picture moved right between before and after the head's turn."""
    before = np.array(last(d, 'camera', BEFORE_HEAD)[2])
    after = np.array(last(d, 'camera', BEFORE_TURN)[2])
    return shift_right(before, after, reach=2)


def head_yaw(d, t):
    return last(d, 'joints', t)[2]


def head_speed(d):
    """HeadYaw's speed in the middle of its motion (20 % to 80 % of the way), on stamps."""
    start, end = head_yaw(d, BEFORE_HEAD), head_yaw(d, BEFORE_TURN)
    r = [x for x in rows(d, 'joints', BEFORE_HEAD, BEFORE_TURN)
         if 0.2 <= (x[2] - start) / (end - start) <= 0.8]
    return (r[-1][2] - r[0][2]) / (r[-1][1] - r[0][1])


def test_each_command_moves_the_robot_and_every_stream_agrees(master, tmp_path):
    d = run_motion(master, tmp_path)
    assert d['schedule'] == dict(head=HEAD_AT, goal=GOAL_AT, spin=SPIN_AT, stop=STOP_AT, end=END)
    log = d['log']
    assert 'the idle drive stops (a command publisher connected)' in log
    assert 'setAngles' in log and 'moveTo(0.000, 0.000, 0.500) in base_footprint' in log
    # the head reaches its target at 0.2 x HeadYaw's maximum velocity
    assert head_yaw(d, BEFORE_TURN) == pytest.approx(HEAD, abs=1e-3)
    assert head_speed(d) == pytest.approx(0.2 * HEAD_YAW_MAX_VEL, rel=0.2)
    # the base turns by the moveTo's yaw; odometry, gyro (z, positive) and wheels agree
    assert odom_yaw_change(d) == pytest.approx(TURN, abs=0.02)
    assert gyro_turn(d) == pytest.approx(TURN, rel=0.15)
    assert abs(gyro_turn(d, GX)) < 0.05 and abs(gyro_turn(d, GY)) < 0.05
    imu_yaw = last(d, 'imu', AFTER_TURN)[IMU_YAW] - last(d, 'imu', BEFORE_TURN)[IMU_YAW]
    assert imu_yaw == pytest.approx(TURN, abs=0.02)                 # the IMU's orientation too
    for col, name in ((3, 'WheelFL'), (4, 'WheelFR'), (5, 'WheelB')):
        assert wheel_turn(d, col) == pytest.approx(-TURN * WHEEL_RATIO[name], rel=0.1), name
    # the scan turns with the base, the picture pans with the head (right, for a turn left)
    assert abs(laser_shift(d) - TURN / LASER_INCREMENT) <= 2
    # (the head turned from where its sway had it: the encoder's change is the turn)
    turned = head_yaw(d, BEFORE_TURN) - head_yaw(d, BEFORE_HEAD)
    assert camera_shift(d) == pytest.approx(turned * FRONT_PX_PER_RAD, abs=6)
    # move() keeps turning at its speed until the zero twist, which stops it
    assert last(d, 'odom', STOP_AT - 0.05)[ODOM_WZ] == pytest.approx(SPIN, abs=0.01)
    assert last(d, 'odom', END - 0.05)[ODOM_WZ] == 0.0      # stopped within 0.3 / 0.75 s
    assert last(d, 'odom', END - 0.05)[ODOM_YAW] == last(d, 'odom', END - 0.3)[ODOM_YAW]
    assert d['stiffness'] == '1'


def test_sensor_faults_give_their_wrong_data_and_only_theirs(master, tmp_path):
    d = run_motion(master, tmp_path, 'imu:gyro_inverted,clock_offset=0.5;odometry:frozen_pose;'
                   'jointState:stuck_joint=HeadYaw;laser:reversed;frontCamera:not_following;'
                   'frontSonar:glass')
    assert gyro_turn(d) == pytest.approx(-TURN, rel=0.15)           # the opposite sign
    # odometry frozen while the wheels turn
    assert odom_yaw_change(d) == 0.0 and last(d, 'odom', 4.0)[ODOM_WZ] == 0.0
    assert wheel_turn(d, 3) == pytest.approx(-TURN * WHEEL_RATIO['WheelFL'], rel=0.1)
    # HeadYaw's encoder reads its first angle while the head turned (the stereo, depth and
    # bottom cameras would show it; the front camera here has its own fault)
    assert head_yaw(d, BEFORE_TURN) == head_yaw(d, BEFORE_HEAD)
    # a scan stored in reverse order turns the wrong way
    assert abs(laser_shift(d) + TURN / LASER_INCREMENT) <= 2
    assert abs(camera_shift(d)) <= 2                                # live, but not following
    assert len({tuple(r[2]) for r in rows(d, 'camera', 0.0, BEFORE_TURN)}) > 1
    # glass: the sonar sees a pane 0.8 m ahead, the laser's front beam the room behind it
    assert last(d, 'sonar', BEFORE_TURN)[2] == pytest.approx(0.8, abs=0.1)
    assert last(d, 'laser', BEFORE_TURN)[2][30] > 2.0
    # the IMU's stamps are 0.5 s ahead of the odometry's
    imu, odom = last(d, 'imu', SPIN_AT), last(d, 'odom', SPIN_AT)
    assert (imu[1] - imu[0]) - (odom[1] - odom[0]) == pytest.approx(0.5, abs=0.15)


def test_a_dead_gyro_and_an_obstacle(master, tmp_path):
    d = run_motion(master, tmp_path, 'imu:dead_gyro;robot:obstacle')
    assert odom_yaw_change(d) == pytest.approx(TURN, abs=0.02)      # the base did turn
    assert all(r[GX] == r[GY] == r[GZ] == 0.0 for r in d['imu'])        # the gyro read nothing
    # a bin 0.35 m ahead of the start pose: the front beams and the front sonar see it
    scan = np.array(last(d, 'laser', BEFORE_TURN)[2])
    assert 0.3 < scan[23:38].min() < 0.4 and 0.3 < last(d, 'sonar', BEFORE_TURN)[2] < 0.42


def test_a_blocked_base_and_swapped_imu_axes(master, tmp_path):
    d = run_motion(master, tmp_path, 'robot:base_blocked;imu:swapped_axes')
    assert 'moveTo(0.000, 0.000, 0.500) in base_footprint ignored: the base may not move' in d['log']
    assert odom_yaw_change(d) == 0.0 and wheel_turn(d, 3) == 0.0 and wheel_turn(d, 5) == 0.0
    assert head_yaw(d, BEFORE_TURN) == pytest.approx(HEAD, abs=1e-3)      # the head still obeys
    imu = last(d, 'imu', BEFORE_TURN)
    assert imu[AX] == pytest.approx(9.81, abs=0.2) and abs(imu[AZ]) < 0.2     # gravity on x


def test_a_resting_robot_ignores_every_command(master, tmp_path):
    d = run_motion(master, tmp_path, 'robot:resting')
    assert 'ignored: the robot is resting (stiffness 0)' in d['log']
    assert d['stiffness'] == '0'
    assert head_yaw(d, END - 0.05) == head_yaw(d, BEFORE_HEAD)
    assert last(d, 'odom', END - 0.05)[ODOM_YAW] == last(d, 'odom', BEFORE_HEAD)[ODOM_YAW]
