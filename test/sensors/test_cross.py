"""Unit: the cross-checks between sensors that need no motion (sensors/cross.py): the front
sonar against the laser's front sector, and each sensor's header clock against the others'."""
import math
import re

import pytest

from pepper_interface_tests.results import SensorResult
from pepper_interface_tests.sensors import cross
from pepper_interface_tests.sensors.values.laser import LaserValues, LastScan
from pepper_interface_tests.sensors.values.range import RangeValues
from pepper_interface_tests.stats import DelaySummary, StreamSummary

INC = (2 * 2.0944) / 61


def laser(front=2.0, ended=10.0):
    ranges = [3.0] * 61
    for i in range(61):
        if abs(-2.0944 + i * INC) <= 0.2:
            ranges[i] = front
    ranges[15:23] = [math.nan] * 8                       # blind slots
    scan = LastScan(-2.0944, INC, ranges, 0.1, 3.0, -1.0, [])
    return SensorResult(name='laser', title='LASER', topic='/l', msg_type='sensor_msgs/LaserScan',
                        verdict='PASS', values=LaserValues(last_scan=scan), ended_at=ended)


def sonar(r=2.1, ended=10.0):
    return SensorResult(name='frontSonar', title='FRONT SONAR', topic='/s', msg_type='sensor_msgs/Range',
                        verdict='PASS', values=RangeValues(range_series=[(0.0, 5.0), (9.9, r)]),
                        ended_at=ended)


def test_a_sonar_that_agrees_with_the_laser_is_not_warned():
    rows = [sonar(2.1), laser(2.0)]
    cross.apply(rows)
    assert rows[0].warnings == [] and rows[1].warnings == []


def test_glass_ahead_warns_both_rows_with_both_distances():
    rows = [sonar(0.8), laser(2.6)]
    cross.apply(rows)
    for r in rows:
        assert len(r.warnings) == 1 and '0.80 m' in r.warnings[0] and '2.60 m' in r.warnings[0]
        assert 'glass' in r.warnings[0]
    assert rows[0].verdict == 'PASS'


def test_windows_far_apart_are_not_compared():
    rows = [sonar(0.8, ended=10.0), laser(2.6, ended=20.0)]      # sequential mode: the robot may have moved
    cross.apply(rows)
    assert rows[0].warnings == []


def timed(name, delay):
    return SensorResult(name=name, title=name, topic='/' + name, msg_type='x/Y', verdict='PASS',
                        stats=StreamSummary(delay_s=DelaySummary(delay, delay, delay)))


def test_one_sensor_on_another_clock_is_warned_with_its_offset():
    rows = [timed('imu', 0.02), timed('odometry', 0.03), timed('jointState', 0.01), timed('microphone', -2.5)]
    cross.apply(rows)
    assert [bool(r.warnings) for r in rows] == [False, False, False, True]
    assert 'header stamps 2.52 s ahead of the other sensors' in rows[3].warnings[0]


def test_a_backlog_in_sensor_test_is_not_a_clock():
    """A topic whose messages waited in sensorTest (a busy PC; on ROS 2 rclpy's one thread for
    every topic) has a high mean delay, but its freshest message is as fresh as the others'."""
    rows = [timed('imu', 0.02), timed('odometry', 0.03), timed('laser', 0.02),
            SensorResult(name='jointState', title='jointState', topic='/joint_states', msg_type='x/Y', verdict='PASS',
                         stats=StreamSummary(delay_s=DelaySummary(0.01, 2.85, 6.3)))]
    cross.apply(rows)
    assert not any(r.warnings for r in rows), [r.warnings for r in rows]


def test_a_loaded_robots_camera_lag_is_not_a_clock():
    rows = [timed('imu', 0.02), timed('odometry', 0.03), timed('frontCamera', 0.7)]
    cross.apply(rows)
    assert not any(r.warnings for r in rows)


def test_the_emulators_glass_pane_and_an_offset_clock_are_warned(master, tmp_path):
    """Integration: the emulator with a glass pane ahead (the sonar sees it, the laser sees
    through) and the IMU stamped 2.5 s behind the others; both warned, nothing failed."""
    import json
    import os
    import subprocess

    from rosmaster import kill_group, script, spawn, wait_until
    log_path = tmp_path / 'emulator.log'
    with open(str(log_path), 'w') as log:
        emu = spawn(script('pepperEmulator') + ['__name:=emu_cross', '_audio:=off', '_condition:=still',
                                                '_faults:=frontSonar:glass;imu:clock_offset=-2.5'],
                    master.env(), stdout=log, stderr=subprocess.STDOUT)
    try:
        wait_until(lambda: 'publishers up' in log_path.read_text(), 30, log_path.read_text)
        out = tmp_path / 'out'
        done = subprocess.run(script('sensorTest') + [
            '--sensors', 'frontSonar,laser,imu,odometry,jointState', '--mode', 'parallel',
            '--duration', '2', '--wait', '8', '--output-dir', str(out), '--no-show', '--no-history',
            '--no-report', '--no-diagnostics', '--no-record'], env=master.env(), capture_output=True,
            text=True, timeout=60)
    finally:
        kill_group(emu)
    rows = {s['name']: s for s in json.loads((out / 'sensorTestResults.json').read_text())['sensors']}
    assert done.returncode == 0, done.stdout + done.stderr
    # the pane stands 0.8 m ahead; the sonar reads it with its own noise (0.79 and 0.81 m both
    # seen): the distance named is read, not spelled
    said = [float(m.group(1)) for w in rows['frontSonar']['warnings']
            for m in [re.search(r'front sonar reads ([0-9.]+) m', w)] if m]
    assert said and said[0] == pytest.approx(0.8, abs=0.05), rows['frontSonar']['warnings']
    offsets = [float(m.group(1)) for w in rows['imu']['warnings']
               for m in [re.search(r'header stamps ([0-9.]+) s behind', w)] if m]
    assert offsets and offsets[0] == pytest.approx(2.5, abs=0.3), rows['imu']['warnings']   # delivery adds a little
    assert not any(w for n in ('odometry', 'jointState') for w in rows[n]['warnings'])
    assert os.path.exists(str(out / 'sensorTestOutput.dat'))


def turning(odom_rate=0.2, gyro_rate=0.2, seconds=5.0):
    """Odometry and IMU rows of one window in which the robot turned (rad/s)."""
    from pepper_interface_tests.sensors.values.imu import ImuValues
    from pepper_interface_tests.sensors.values.odometry import OdometryValues
    ts = [i * 0.1 for i in range(int(seconds * 10) + 1)]
    yaw = [(t, math.atan2(math.sin(odom_rate * t + 3.0), math.cos(odom_rate * t + 3.0))) for t in ts]  # wraps at pi
    odom = SensorResult(name='odometry', title='ODOMETRY', topic='/o', msg_type='nav_msgs/Odometry', verdict='PASS',
                        values=OdometryValues(yaw_series=yaw), started_at=2.0)
    imu = SensorResult(name='imu', title='IMU', topic='/i', msg_type='sensor_msgs/Imu', verdict='PASS',
                       values=ImuValues(angular_velocity_z_rad_s=[(t, gyro_rate) for t in ts]), started_at=2.0)
    return [odom, imu]


def test_a_recorded_turn_seen_alike_by_odometry_and_gyro_is_not_warned():
    rows = turning()
    cross.apply(rows)
    assert not rows[0].warnings and not rows[1].warnings


def test_a_recorded_turn_with_the_gyro_of_the_opposite_sign_warns_both():
    rows = turning(gyro_rate=-0.2)
    cross.apply(rows)
    assert 'odometry\'s yaw changed +1.00 rad and the gyro\'s z integrates to -1.00 rad: opposite signs' \
        in rows[1].warnings[0]
    assert rows[0].warnings == rows[1].warnings


def test_a_robot_standing_still_is_not_compared():
    rows = turning(odom_rate=0.0, gyro_rate=0.01)
    cross.apply(rows)
    assert not rows[0].warnings
