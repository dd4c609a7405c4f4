"""The emulated body (emulator/body.py) as ALMotion moves Pepper: move() until told otherwise,
moveTo() relative and bounded, setAngles at a fraction of each joint's maximum velocity, the
omni wheels, the idle drive, and the robot conditions that refuse commands. Pure: no ROS.
The reference numbers are written out here from their sources, not read from body.py."""
import math

import pytest

from pepper_interface_tests.emulator import body as body_mod
from pepper_interface_tests.emulator import scene
from pepper_interface_tests.emulator.body import Body, CommandError, wheel_speeds
from pepper_interface_tests.emulator.commands import quaternion_yaw

# pepper.urdf (ros-naoqi/pepper_robot 60d4e08): wheel joints at :1401, :1427, :1453 (origin
# xyz, rpy yaw), radius = 0.334 - 0.264 (:143 against the wheels' z)
URDF_WHEELS = {'WheelFL': (0.09, 0.155, 1.07517), 'WheelB': (-0.17, 0.0, -3.14159),
               'WheelFR': (0.09, -0.155, -1.07517)}
RADIUS = 0.334 - 0.264
HEAD_YAW_MAX_VEL = 7.33998          # pepper.urdf:15
# ALMotion's default move config on Pepper (doc.aldebaran.com/2-5 control-walk.html)
MAX_VEL_THETA, MAX_VEL_XY, MAX_ACC_THETA = 1.0, 0.35, 0.75


def run(b, t0, t1, dt=0.02):
    """Snapshots from t0 to t1 every dt."""
    out, t = [], t0
    while t <= t1 + 1e-9:
        out.append(b.snapshot(t))
        t += dt
    return out


def test_wheels_for_a_turn_in_place_and_a_straight_drive():
    # every axis points outwards from the centre: turning left, each wheel's contact point
    # moves tangentially, the spin (right hand about the axis) is -w |p| / r for all three
    spin = wheel_speeds(0.0, 0.0, 0.5)
    for name, (x, y, _a) in URDF_WHEELS.items():
        assert spin[name] == pytest.approx(-0.5 * math.hypot(x, y) / RADIUS, rel=0.01), name
    # straight ahead: the back wheel's axis lies along x, it does not turn; the front two
    # spin the opposite ways (mirror images)
    ahead = wheel_speeds(0.2, 0.0, 0.0)
    assert abs(ahead['WheelB']) < 1e-3
    assert ahead['WheelFL'] == pytest.approx(-ahead['WheelFR']) and abs(ahead['WheelFL']) > 1.0


def test_move_to_is_relative_bounded_and_within_the_limits():
    b = Body(idle=False)
    b.move(0.0, 0.2, 0.0, 0.4)                      # drive somewhere first
    b.move(3.0, 0.0, 0.0, 0.0)
    s0 = b.snapshot(5.0)
    assert b.move_to(5.0, 0.2, 0.0, 0.5)
    snaps = run(b, 5.0, 10.0)
    end = snaps[-1]
    assert end.yaw == pytest.approx(s0.yaw + 0.5, abs=0.005)
    assert end.x == pytest.approx(s0.x + 0.2 * math.cos(s0.yaw), abs=0.005)
    assert end.y == pytest.approx(s0.y + 0.2 * math.sin(s0.yaw), abs=0.005)
    assert end.wz == 0.0 and end.vx == 0.0 and not b.moving()      # stopped by itself
    assert max(abs(s.wz) for s in snaps) <= MAX_VEL_THETA + 1e-9
    assert max(math.hypot(s.vx, s.vy) for s in snaps) <= MAX_VEL_XY + 1e-9
    accel = [abs(b2.wz - a.wz) / 0.02 for a, b2 in zip(snaps, snaps[1:])]
    assert max(accel) <= MAX_ACC_THETA * 1.01


def test_move_keeps_going_until_a_zero_twist_and_clamps():
    b = Body(idle=False)
    b.move(0.0, 0.0, 0.0, 5.0)                      # beyond MaxVelTheta
    s = b.snapshot(20.0)
    assert s.wz == pytest.approx(MAX_VEL_THETA)     # still turning 20 s later, clamped
    b.move(20.0, 1.0, 1.0, 0.0)
    assert math.hypot(b.snapshot(25.0).vx, b.snapshot(25.0).vy) == pytest.approx(MAX_VEL_XY)
    b.move(25.0, 0.0, 0.0, 0.0)
    assert b.snapshot(28.0).vx == 0.0 and not b.moving()


def test_a_move_to_replaces_a_running_move_and_the_other_way_round():
    b = Body(idle=False)
    b.move(0.0, 0.0, 0.0, 0.3)
    b.snapshot(2.0)
    b.move_to(2.0, 0.0, 0.0, -0.2)
    yaw0 = b.snapshot(2.0).yaw
    assert b.snapshot(8.0).yaw == pytest.approx(yaw0 - 0.2, abs=0.01) and not b.moving()
    b.move_to(8.0, 0.0, 0.0, 3.0)
    b.move(8.5, 0.0, 0.0, 0.0)                      # a zero move() ends the moveTo
    assert b.snapshot(12.0).wz == 0.0 and not b.moving()


def test_move_to_in_the_odom_frame_goes_to_that_pose():
    b = Body(idle=False)
    b.move_to(0.0, 0.1, 0.05, 0.3, frame='odom')
    end = b.snapshot(6.0)
    assert (end.x, end.y, end.yaw) == pytest.approx((0.1, 0.05, 0.3), abs=0.005)


def test_set_angles_at_the_fraction_of_the_maximum_velocity():
    b = Body(idle=False)
    start = b.snapshot(1.0).joints['HeadYaw']
    assert b.set_angles(1.0, ['HeadYaw'], [0.5], 0.1)
    duration = abs(0.5 - start) / (0.1 * HEAD_YAW_MAX_VEL)
    half = b.snapshot(1.0 + duration / 2)
    assert half.joints['HeadYaw'] == pytest.approx((start + 0.5) / 2, abs=0.02)
    assert half.joint_velocities['HeadYaw'] == pytest.approx(
        math.copysign(0.1 * HEAD_YAW_MAX_VEL, 0.5 - start), rel=0.01)
    done = b.snapshot(1.0 + duration + 0.1)
    assert done.joints['HeadYaw'] == 0.5 and done.joint_velocities['HeadYaw'] == 0.0
    assert b.snapshot(30.0).joints['HeadYaw'] == 0.5          # held: no more sway
    # changeAngles: relative to the current angle; targets clipped to the URDF's limits
    b.set_angles(30.0, ['HeadYaw'], [-0.2], 1.0, relative=True)
    assert b.snapshot(31.0).joints['HeadYaw'] == pytest.approx(0.3)
    b.set_angles(31.0, ['Head'], [3.0, 0.0], 1.0)
    assert b.snapshot(33.0).joints['HeadYaw'] == pytest.approx(2.08567)


@pytest.mark.parametrize('names, angles', [(['HeadRoll'], [0.1]), (['HeadYaw'], [0.1, 0.2]),
                                           (['WheelFL'], [1.0]), (['HeadYaw'], [float('nan')])])
def test_commands_almotion_would_reject(names, angles):
    b = Body(idle=False)
    with pytest.raises(CommandError):
        b.set_angles(0.0, names, angles, 0.5)


def test_a_resting_robot_ignores_everything():
    b = Body(idle=True, resting=True)
    s = b.snapshot(0.5)
    assert s.stiffness == 0.0 and s.joints['HeadPitch'] == body_mod.REST_HEAD_PITCH
    assert not b.move(1.0, 0.0, 0.0, 0.5) and not b.move_to(1.0, 0.0, 0.0, 0.5)
    assert not b.set_angles(1.0, ['HeadYaw'], [0.5], 0.2)
    end = b.snapshot(5.0)
    assert (end.x, end.yaw, end.joints['HeadYaw']) == (0.0, 0.0, s.joints['HeadYaw'])
    assert all(w == 0.0 for w in end.wheels.values())


def test_a_blocked_base_refuses_while_the_head_obeys():
    b = Body(idle=True, base_blocked=True)
    assert not b.move_to(0.0, 0.0, 0.0, 0.5) and not b.move(0.0, 0.0, 0.0, 0.5)
    assert b.set_angles(0.0, ['HeadYaw'], [0.4], 0.5)
    end = b.snapshot(3.0)
    assert end.yaw == 0.0 and end.stiffness == 1.0 and end.joints['HeadYaw'] == 0.4


def test_the_idle_drive_is_the_circle_and_stops_when_commands_are_expected():
    b = Body(idle=True)
    s = b.snapshot(20.0)
    assert (s.x, s.y, s.yaw) == pytest.approx(scene.robot_pose(20.0), abs=1e-4)
    # specific force of the circle: v w towards the centre (+y in the base frame)
    assert s.ay == pytest.approx(scene.LINEAR_SPEED * scene.ANGULAR_SPEED, abs=1e-6)
    coming = []
    b.expected = lambda: bool(coming)
    b.snapshot(21.0)
    coming.append(True)
    b.snapshot(21.5)
    assert b.snapshot(23.0).wz == 0.0 and b.snapshot(23.0).vx == 0.0


def test_the_obstacle_is_near_the_start_heading_and_the_robot_stands_before_it():
    b = Body(obstacle=True)
    x, y, r = b.circles()[0]
    assert x - r == pytest.approx(0.35) and y == 0.0
    assert b.snapshot(10.0).x == 0.0 and b.snapshot(10.0).yaw == 0.0      # no idle drive
    assert Body().circles() == ()


@pytest.mark.parametrize('q, yaw', [((0, 0, math.sin(0.25), math.cos(0.25)), 0.5),
                                    ((0, 0, 2 * math.sin(-0.4), 2 * math.cos(-0.4)), -0.8)])
def test_goal_yaw_as_the_driver_reads_it(q, yaw):
    class Q:
        x, y, z, w = q
    assert quaternion_yaw(Q) == pytest.approx(yaw)


def test_a_zero_quaternion_gives_nan_as_in_the_driver():
    class Q:
        x = y = z = w = 0.0
    assert math.isnan(quaternion_yaw(Q))
