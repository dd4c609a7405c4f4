"""The IMU check, with real sensor_msgs/Imu messages serialized as they come off the wire and fed
to the window at explicit times."""
import pytest

from check_runs import N, judged, one_reason_with
from fake_pepper import UNKNOWN_COVARIANCE, imu
from pepper_interface_tests.results import FAIL, PASS


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
