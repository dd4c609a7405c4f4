"""Unit: the shared fake-Pepper builders (test/fake_pepper.py) say what the emulator's robot
profile says, and their faults are the ones the checks must catch."""
import math

import fake_pepper as fake
from pepper_interface_tests.emulator import profiles


def test_good_messages_follow_the_robot_profile():
    s = fake.sonar(3, 12.5)
    assert (s.min_range, s.max_range) == (0.25, 2.55) and s.header.frame_id == 'SonarBack_frame'
    assert s.min_range <= s.range <= s.max_range and s.header.stamp.to_sec() == 12.5
    scan = fake.laser(0, 1.0)
    assert len(scan.ranges) == profiles.LASER_BEAMS == 61
    assert [r == -1.0 for r in scan.ranges] == profiles.laser_blind_mask()
    assert round((scan.angle_max - scan.angle_min) / scan.angle_increment) == 61  # laser.cpp:218
    j = fake.joints(0, 1.0)
    assert list(j.name) == list(profiles.JOINT_NAMES) and len(j.name) == 20
    assert len(j.position) == len(j.velocity) == len(j.effort) == 20
    o = fake.odometry(4, 1.0)
    assert (o.header.frame_id, o.child_frame_id) == ('odom', 'base_link')
    q = fake.imu(0, 1.0).orientation
    assert math.isclose(q.x ** 2 + q.y ** 2 + q.z ** 2 + q.w ** 2, 1.0)
    a = fake.audio_buffer(0)
    assert all(len(getattr(a, c)) == profiles.AUDIO_BUFFER for c in profiles.MIC_CHANNELS)


def test_faults_break_what_they_name():
    assert math.isnan(fake.sonar(0, 1.0, 'nan').range)
    assert fake.sonar(0, 1.0, 'out_of_range').range > 2.55
    assert len(fake.laser(0, 1.0, "wrong_ranges").ranges) == 40
    assert 'HeadYaw' not in fake.joints(0, 1.0, 'missing_joint').name
    dup = fake.joints(0, 1.0, 'dup_joint').name
    assert dup[0] == dup[1]
    assert len(fake.joints(0, 1.0, 'short_velocity').velocity) == 19
    assert fake.imu(0, 1.0, 'broken_quaternion').orientation.w == 0.5
    assert fake.odometry(0, 1.0, 'broken_quaternion').pose.pose.orientation.w == 2.0
    assert fake.sonar(0, 100.0, 'zero_stamp').header.stamp.to_sec() == 0.0
    assert fake.sonar(0, 100.0, 'old_stamp').header.stamp.to_sec() == 70.0
    assert fake.imu(0, 1.0, 'frame').header.frame_id == 'wrong_frame'
    assert set(fake.FAULTS) >= {'nan', 'missing_joint', 'old_stamp'}
