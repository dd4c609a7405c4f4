"""Unit: outputs/drift.py compares a sensor's values with the baseline's, family by family: a
value beyond its margin is a Drift and a warning naming then and now; within it, nothing; the
microphones are compared with each other, so a louder room warns about none. Pure: no ROS."""
import pytest

from pepper_interface_tests.outputs import drift
from pepper_interface_tests.results import FAIL, PASS, SKIPPED, SensorResult
from pepper_interface_tests.sensors.values import Spread
from pepper_interface_tests.sensors.values.audio import AudioValues, ChannelLevel
from pepper_interface_tests.sensors.values.camera import CameraValues
from pepper_interface_tests.sensors.values.depth import DepthValues, MedianSpread
from pepper_interface_tests.sensors.values.health import HealthValues, JointRow
from pepper_interface_tests.sensors.values.imu import ImuValues
from pepper_interface_tests.sensors.values.joints import JointsValues
from pepper_interface_tests.sensors.values.laser import LaserValues
from pepper_interface_tests.sensors.values.motion import MotionValues, StepValues
from pepper_interface_tests.sensors.values.range import RangeValues

REF = drift.Ref('20261120-101500', '2026-11-20')


def result(family, values, rate=10.0, verdict=PASS, messages=100, name='s'):
    return SensorResult(name=name, title=name, topic='/t', msg_type='x', verdict=verdict, family=family,
                        values=values, rate_hz=rate, messages=messages)


def mics(rl, rr, fl, fr):
    return AudioValues(channels={c: ChannelLevel(rms_dbfs=v) for c, v in
                                 zip(('rearLeft', 'rearRight', 'frontLeft', 'frontRight'), (rl, rr, fl, fr))})


def camera(brightness=120.0, contrast=50.0, sharpness=900.0, noise=2.0):
    return CameraValues(brightness_mean=Spread(brightness - 1, brightness, brightness + 1),
                        brightness_spread=Spread(contrast, contrast, contrast), sharpness=sharpness, noise=noise)


def found(then, now, family):
    return drift.drift(result(family, then), result(family, now), REF)


def test_the_same_values_give_no_drift_in_any_family():
    for family, v in [('camera', camera()), ('audio', mics(-30, -31, -29, -30)),
                      ('imu', ImuValues(acceleration_norm_median_m_s2=9.8,
                                        angular_velocity_norm_rad_s=Spread(0, 0.002, 0.01),
                                        angular_velocity_noise_rad_s=0.001)),
                      ('range', RangeValues(infinite_ranges=3, range_noise_m=0.01)),
                      ('laser', LaserValues(board_valid_share={'front': 0.9}, range_noise_m=0.01)),
                      ('depth', DepthValues(valid_share=Spread(0.8, 0.9, 1), depth_m=MedianSpread(1, 2, 3))),
                      ('joints', JointsValues(position_noise_rad={'HeadYaw': 0.001})),
                      ('health', HealthValues(hottest=[JointRow('HipPitch', 40.0)]))]:
        assert found(v, v, family) == [], family


def test_a_quiet_microphone_is_named_with_then_and_now_and_the_others_level():
    d = found(mics(-29, -30, -29, -30), mics(-41, -30, -29, -31), 'audio')
    assert [x.measure for x in d] == ['level:rearLeft']
    text = d[0].text
    assert text.startswith('rearLeft level -41 dBFS, was -29 dBFS on 2026-11-20 (run 20261120-101500): '
                           '12 dB quieter, the others within 1 dB')
    assert 'grille' in text and d[0].then == -29 and d[0].now == -41


def test_a_louder_room_moves_all_four_microphones_and_warns_about_none():
    assert found(mics(-40, -41, -40, -39), mics(-25, -26, -25, -24), 'audio') == []


def test_a_quieter_channel_in_a_louder_room_is_still_named():
    d = found(mics(-40, -40, -40, -40), mics(-37, -30, -30, -30), 'audio')
    assert [x.measure for x in d] == ['level:rearLeft'] and 'than the others' in d[0].change


@pytest.mark.parametrize('now, measure', [
    (camera(sharpness=300.0), 'sharpness'),            # a knocked lens: a third of the detail
    (camera(brightness=70.0), 'brightness'),           # dim=0.6
    (camera(contrast=25.0), 'contrast'),               # haze on the lens
    (camera(noise=4.0), 'noise'),                      # a hot sensor
])
def test_each_camera_value_beyond_its_margin(now, measure):
    d = found(camera(), now, 'camera')
    assert [x.measure for x in d] == [measure]


def test_camera_values_within_their_margins_give_nothing():
    assert found(camera(), camera(brightness=100, contrast=42, sharpness=600, noise=2.6), 'camera') == []


def test_half_the_rate_is_a_drift_and_a_loaded_wobble_is_not():
    v = camera()
    half = drift.drift(result('camera', v, rate=10.0), result('camera', v, rate=5.0), REF)
    assert [x.measure for x in half] == ['rate'] and '50 % slower' in half[0].text
    assert drift.drift(result('camera', v, rate=10.0), result('camera', v, rate=8.5), REF) == []


def test_touch_events_and_a_rate_from_few_messages_have_no_rate_to_drift():
    assert drift.drift(result('touch', None, rate=10.0), result('touch', None, rate=1.0), REF) == []
    few = drift.drift(result('camera', camera(), rate=1.0, messages=3), result('camera', camera(), rate=0.5,
                                                                                messages=2), REF)
    assert few == []


def test_imu_bias_noise_and_gravity():
    base = ImuValues(acceleration_norm_median_m_s2=9.81, angular_velocity_norm_rad_s=Spread(0, 0.003, 0.01),
                     angular_velocity_noise_rad_s=0.002)
    biased = ImuValues(acceleration_norm_median_m_s2=9.81, angular_velocity_norm_rad_s=Spread(0, 0.023, 0.04),
                       angular_velocity_noise_rad_s=0.002)
    assert [x.measure for x in found(base, biased, 'imu')] == ['gyro_bias']
    noisy = ImuValues(acceleration_norm_median_m_s2=9.81, angular_velocity_norm_rad_s=Spread(0, 0.005, 0.01),
                      angular_velocity_noise_rad_s=0.006)
    assert [x.measure for x in found(base, noisy, 'imu')] == ['gyro_noise']
    heavy = ImuValues(acceleration_norm_median_m_s2=10.4, angular_velocity_norm_rad_s=Spread(0, 0.003, 0.01),
                      angular_velocity_noise_rad_s=0.002)
    assert [x.measure for x in found(base, heavy, 'imu')] == ['gravity']


def test_a_scratched_laser_board_loses_valid_readings_and_names_the_board():
    then = LaserValues(board_valid_share={'right': 0.95, 'front': 0.96, 'left': 0.94}, range_noise_m=0.01)
    now = LaserValues(board_valid_share={'right': 0.95, 'front': 0.70, 'left': 0.93}, range_noise_m=0.011)
    d = found(then, now, 'laser')
    assert [x.measure for x in d] == ['valid_share:front'] and d[0].label == 'front valid share'
    assert 'fewer valid readings' in d[0].text


def test_a_noisy_sonar_and_one_that_loses_its_readings():
    then = RangeValues(infinite_ranges=0, range_noise_m=0.005)
    assert [x.measure for x in found(then, RangeValues(infinite_ranges=0, range_noise_m=0.02), 'range')] \
        == ['range_noise']
    assert [x.measure for x in found(then, RangeValues(infinite_ranges=30, range_noise_m=0.005), 'range')] \
        == ['valid_share']


def test_depth_valid_share_and_distance():
    then = DepthValues(valid_share=Spread(0.8, 0.9, 1), depth_m=MedianSpread(1, 2.0, 3))
    now = DepthValues(valid_share=Spread(0.6, 0.7, 0.8), depth_m=MedianSpread(1, 2.1, 3))
    assert [x.measure for x in found(then, now, 'depth')] == ['valid_share']


def test_a_noisier_joint_and_a_hotter_one():
    then = JointsValues(position_noise_rad={'HeadYaw': 0.0005, 'HipPitch': 0.0005})
    now = JointsValues(position_noise_rad={'HeadYaw': 0.0005, 'HipPitch': 0.002})
    d = found(then, now, 'joints')
    assert [x.label for x in d] == ['HipPitch position noise']
    hot = found(HealthValues(hottest=[JointRow('KneePitch', 38.0)]),
                HealthValues(hottest=[JointRow('KneePitch', 50.0)]), 'health')
    assert [x.measure for x in hot] == ['temperature:KneePitch'] and '12 degC hotter' in hot[0].text


def test_a_baseline_sensor_that_did_not_pass_and_a_skipped_one_give_nothing():
    assert drift.drift(result('camera', camera(), verdict=SKIPPED),
                       result('camera', camera(sharpness=1.0)), REF) == []
    assert drift.drift(result('camera', camera()), result('camera', camera(sharpness=1.0), verdict=SKIPPED),
                       REF) == []
    # a sensor that fails now still says what drifted (the failure is the absolute rules')
    assert drift.drift(result('camera', camera()), result('camera', camera(sharpness=1.0), verdict=FAIL), REF)


def test_apply_puts_each_drift_on_the_result_as_a_warning_never_a_failure():
    now = result('camera', camera(sharpness=100.0))
    drift.apply(now, result('camera', camera()), REF)
    assert now.verdict == PASS and len(now.drift) == 1 and now.warnings == [now.drift[0].text]


def test_every_rule_has_a_margin_a_reason_and_advice():
    for key, rule in drift.RULES.items():
        assert rule.margin > 0 and len(rule.reason) > 40 and rule.advice, key


def test_every_joint_noisier_is_one_warning_naming_them_and_one_noisier_joint_its_own():
    names = ['HeadYaw', 'HeadPitch', 'HipRoll', 'HipPitch', 'KneePitch']
    then = JointsValues(position_noise_rad={n: 0.00005 for n in names})
    d = found(then, JointsValues(position_noise_rad={n: 0.002 for n in names}), 'joints')
    assert len(d) == 1 and d[0].measure == 'joint_noise:*'
    assert d[0].text.startswith('position noise of all 5: median 0.00200 rad, was 0.0000500 rad on 2026-11-20')
    assert "40 times the baseline's" in d[0].text and 'stood still' in d[0].text
    six = JointsValues(position_noise_rad=dict(then.position_noise_rad, RHand=0.00005))
    d = found(six, JointsValues(position_noise_rad=dict(six.position_noise_rad, **{n: 0.002 for n in names})),
              'joints')
    assert [x.label for x in d] == ['position noise of 5 of 6 (HeadYaw, HeadPitch, HipRoll, HipPitch, KneePitch)']
    three = dict(then.position_noise_rad, HeadYaw=0.002, HipRoll=0.002, KneePitch=0.002)
    assert [x.label for x in found(then, JointsValues(position_noise_rad=three), 'joints')] == \
        ['HeadYaw position noise', 'HipRoll position noise', 'KneePitch position noise']


def test_docs_list_every_rule_with_its_margin_and_reason():
    import os

    from pepper_interface_tests.plan.settings import package_dir
    with open(os.path.join(package_dir(), 'docs', 'drift.md'), encoding='utf-8') as f:
        text = f.read()
    for key, rule in drift.RULES.items():
        row = [line for line in text.splitlines() if line.startswith('| `%s` |' % key)]
        assert row and rule.margin_text() in row[0] and rule.reason in row[0], key


def moved(odometry, laser, head=0.5, settled=True):
    """A --move run's steps: the head +0.5 rad, the base +0.5 rad, what the witnesses measured."""
    return MotionValues(head='moved', base='moved', steps=[
        StepValues('head', 0.5, 1.0, 2.0, True, {'HeadYaw': head, 'frontCamera': 40.0}),
        StepValues('base', 0.5, 2.0, 4.0, settled, {'odometry': odometry, 'gyro_z': 0.5, 'laser': laser,
                                                    'wheels': 3.8})])


def test_a_motion_followed_worse_than_on_the_baseline_is_a_drift_of_that_witness():
    """follow_error: the mean |measured - commanded| per witness over the settled steps; only
    a rise beyond 0.05 rad counts (the laser's scan matching wobbles by about 0.01 rad)."""
    assert found(moved(0.5, 0.474), moved(0.5, 0.462), 'motion') == []      # within its spread
    d = found(moved(0.5, 0.474), moved(0.41, 0.474, head=0.42), 'motion')
    assert sorted(x.measure for x in d) == ['follow_error:HeadYaw', 'follow_error:odometry']
    odo = [x for x in d if x.measure == 'follow_error:odometry'][0]
    assert 'odometry follow error' in odo.text and '0.0900 rad' in odo.text and 'was 0' in odo.text
    assert found(moved(0.41, 0.474), moved(0.5, 0.474), 'motion') == []     # better is no wear
    # a step that did not settle (stopped, timed out) says nothing about how the base follows
    assert found(moved(0.5, 0.474), moved(0.2, 0.2, settled=False), 'motion') == []
