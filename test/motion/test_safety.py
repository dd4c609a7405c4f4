"""Unit: when the motion check may move and when it must stop (motion/safety.py)."""
from pepper_interface_tests.motion import safety
from pepper_interface_tests.motion.record import Recording


def rec(**kw):
    r = Recording()
    for k, v in kw.items():
        setattr(r, k, v)
    return r


def test_free_space_stiff_robot_may_move():
    r = rec(laser_nearest=(0.0, 1.2, 0.3), sonar={'frontSonar': (0.0, 1.5)},
            stiffness={'HeadYaw': 1.0, 'WheelFL': 1.0})
    assert safety.base_blocked(r, 0.5, 0.5, True, True) is None
    assert safety.stop_reason(r, 0.3) is None


def test_an_obstacle_is_said_with_where_it_is():
    r = rec(laser_nearest=(0.0, 0.42, 1.2), sonar={'frontSonar': (0.0, 0.45)})
    why = safety.base_blocked(r, 0.5, 0.5, True, True)
    assert 'not enough free space' in why and '0.42 m away to the left (+69 deg)' in why
    assert 'front sonar sees something 0.45 m away' in why
    assert safety.stop_reason(r, 0.3) is None
    r.laser_nearest = (0.0, 0.25, 0.0)
    assert 'closer than 0.30 m' in safety.stop_reason(r, 0.3) and 'ahead' in safety.stop_reason(r, 0.3)


def test_a_pressed_bumper_blocks_and_stops():
    r = rec(laser_nearest=(0.0, 2.0, 0.0), bumpers={2: True, 0: False})
    assert 'the back bumper is pressed' in safety.base_blocked(r, 0.5, 0.5, True, False)
    assert safety.stop_reason(r, 0.3) == 'the back bumper is pressed'


def test_a_resting_robot_is_asked_to_be_woken_up_and_keeps_its_head_still():
    r = rec(laser_nearest=(0.0, 2.0, 0.0), stiffness={'HeadYaw': 0.0, 'HeadPitch': 0.0, 'WheelB': 0.0})
    why = safety.base_blocked(r, 0.5, 0.5, True, True)
    assert 'resting' in why and 'wake it up' in why and 'HeadYaw 0.00' in why
    assert 'wake it up' in safety.head_blocked(r, 0.5)


def test_no_space_sensor_means_no_base_motion():
    assert 'cannot be checked' in safety.base_blocked(rec(), 0.5, 0.5, False, False)


def test_failing_health_blocks_the_base():
    r = rec(laser_nearest=(0.0, 2.0, 0.0), health_error='naoqi_driver_joints:Status: Too hot')
    assert 'robot health is failing' in safety.base_blocked(r, 0.5, 0.5, True, True)
