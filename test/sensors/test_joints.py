"""The joint states check, with real sensor_msgs/JointState messages serialized as they come off
the wire and fed to the window at explicit times."""
from check_runs import NJ, judged, one_reason_with
from fake_pepper import JOINTS, joints
from pepper_interface_tests.results import FAIL, PASS
from pepper_interface_tests.sensors.joint_limits import LIMITS
from pepper_interface_tests.sensors.values import Spread


def test_joint_faults(tmp_path):
    cases = [
        ([joints(i, names=JOINTS[1:]) for i in range(NJ)], 'expected joints missing: HeadYaw'),
        ([joints(i, names=[JOINTS[0]] + JOINTS[:1] + JOINTS[2:]) for i in range(NJ)],
         'duplicate joint names HeadYaw'),
        ([joints(i, velocity=[0.0] * (len(JOINTS) - 1)) for i in range(NJ)],
         'velocity has 19 values for 20 joints in 125 of 125 messages'),
        ([joints(i, position=[0.0, 0.0, float('nan')] + [0.0] * (len(JOINTS) - 3)) for i in range(NJ)],
         'position of HipRoll is NaN'),
    ]
    for msgs, words in cases:
        r = judged('jointState', tmp_path, msgs)
        assert r.verdict == FAIL, words
        one_reason_with(r, words)


def test_joint_short_arrays_do_not_break_the_fields(tmp_path):
    """The original indexed velocity/effort without length checks."""
    r = judged('jointState', tmp_path, [joints(i, velocity=[0.0] * 3) for i in range(NJ)])
    lines = [v for k, v in r.fields if k == 'Joint']
    assert lines[0].startswith('HeadYaw: Position 0, Velocity 0, Effort 0.5')
    assert lines[-1] == 'WheelB: Position 0, Velocity n/a, Effort 0.5'


def test_joint_empty_velocity_and_effort_are_allowed(tmp_path):
    rest = [0.2 if LIMITS[j][0] is None else min(max(0.2, LIMITS[j][0]), LIMITS[j][1]) for j in JOINTS]
    msgs = [joints(position=rest, velocity=[], effort=[]) for _ in range(NJ)]
    r = judged('jointState', tmp_path, msgs)
    assert r.verdict == PASS, r.reasons     # a robot at rest: the same angles every time is no fault
    assert r.values.joint_count == len(JOINTS)
    assert r.values.joints['HeadYaw']['position'] == Spread(0.2, 0.2, 0.2)


def test_joint_positions_beyond_the_urdf_limits_fail(tmp_path):
    msgs = [joints(i) for i in range(NJ)]
    for m in msgs[60:]:
        m.position[JOINTS.index('HeadPitch')] = 1.2        # the URDF allows -0.71..0.64
    r = judged('jointState', tmp_path, msgs, rate=50.0)
    assert r.verdict == FAIL
    one_reason_with(r, "position of HeadPitch outside Pepper's joint limits [-0.7069, 0.637] rad "
                       "(pepper.urdf:41) by more than position_margin 0.05 in 65 of 125 messages "
                       "(e.g. 1.2 rad, first at t = 1.25 s)")


def test_joint_jumps_fail_and_reported_velocity_spikes_warn(tmp_path):
    msgs = [joints(i) for i in range(NJ)]
    for k, m in enumerate(msgs):
        m.position[JOINTS.index('HeadYaw')] = 2.0 if (k // 10) % 2 else -2.0    # 4 rad in 0.02 s
    r = judged('jointState', tmp_path, msgs, rate=50.0)
    assert r.verdict == FAIL
    one_reason_with(r, 'position of HeadYaw jumps: implied speed above 11.01 rad/s (URDF velocity '
                       'limit 7.34 x velocity_factor 1.5, pepper.urdf:15)')
    msgs = [joints(i, velocity=[0.01] * len(JOINTS)) for i in range(NJ)]
    msgs[30].velocity = [0.01] * (len(JOINTS) - 1) + [30.0]
    r = judged('jointState', tmp_path, msgs, rate=50.0)
    assert r.verdict == PASS, r.reasons
    assert any(w.startswith('reported velocity of %s beyond' % JOINTS[-1]) for w in r.warnings), r.warnings
