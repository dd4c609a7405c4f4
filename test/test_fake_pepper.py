"""Unit: the shared fake-Pepper builders (test/helpers/fake_pepper.py) say what the emulator's robot
profile says, and their faults are the ones the checks must catch."""
import math

import numpy as np

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


def test_the_profile_lists_are_naoqi_drivers():
    """The lists every test takes from here (JOINTS, WHEELS, BLIND) state naoqi_driver's facts:
    joint_state.cpp:79 (20 body joints, head first, wheels last, each arm joint with its twin),
    laser.cpp:178/:193 (blind slots 15-22 and 38-45)."""
    assert len(fake.JOINTS) == len(set(fake.JOINTS)) == 20
    assert fake.JOINTS[:2] == ['HeadYaw', 'HeadPitch'] and fake.JOINTS[-3:] == fake.WHEELS
    arms = [j for j in fake.JOINTS if j[0] in 'LR' and j[1].isupper()]
    assert len(arms) == 12 and {'R' + j[1:] for j in arms if j[0] == 'L'} == {j for j in arms if j[0] == 'R'}
    assert fake.BLIND == list(range(15, 23)) + list(range(38, 46))


def test_builders_take_the_variants_the_tests_need():
    assert fake.sonar(0, None, frame_id='SonarFront_frame', range=4.0).range == 4.0
    assert fake.sonar(0, platform='simulator').max_range == 5.0
    assert fake.laser(0).header.stamp.to_sec() == 0.0            # None leaves the stamp to the caller
    assert len(fake.laser(0, n=40).ranges) == 40
    assert all(r == -1.0 for r in fake.laser(0, blind=range(61)).ranges)
    sim = fake.sim_laser(0, returns=range(10, 12), beyond=(300,))
    assert len(sim.ranges) == 488 and sum(not math.isnan(r) for r in sim.ranges) == 3 and sim.ranges[300] == 9.0
    j = fake.joints(0, names=fake.JOINTS[1:], velocity=[])
    assert 'HeadYaw' not in j.name and list(j.velocity) == [] and len(j.effort) == 19
    assert fake.odometry(0, child_frame_id='').child_frame_id == ''
    i = fake.imu(0, covariance=fake.UNKNOWN_COVARIANCE)
    assert i.orientation_covariance[0] == i.angular_velocity_covariance[0] == -1.0
    img = fake.image(np.zeros((4, 6, 3), np.uint8), 'rgb8', step=17)
    assert (img.width, img.height, img.step, len(img.data)) == (6, 4, 17, 72)
    a = fake.stock_audio_buffer(0, cmap=(0, 2, 3, 5), dead='frontRight', samples=16)
    assert list(a.channelMap) == [0, 2, 3, 5] and len(a.data) == 64 and not any(a.data[1::4])
