"""Test helper: the motion check's quick plan and the safety rule its interrupted runs must meet,
shared by the ROS 1 tests (test/sensors/test_motion.py) and the ROS 2 tier's (test/ros2/)."""
import os

import pytest

PKG = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
GOAL, TWIST, JOINTS = '/move_base_simple/goal', '/cmd_vel', '/joint_angles'


def expectations(tmp_path, **motion):
    """The shipped expectations file with the motion block's keys replaced (a quick plan)."""
    text = open(os.path.join(PKG, 'config', 'sensorExpectations.yaml')).read()
    keys = dict(dict(head_yaw=0.5, head_speed=0.1, base_turn=0.5, step_timeout=15.0), **motion)
    block = '  motion:\n' + ''.join('    %s: %s\n' % kv for kv in keys.items())
    start = text.index('  motion:\n')
    end = text.index('\nsimulator:')
    path = tmp_path / 'expect.yaml'
    path.write_text(text[:start] + block + text[end:])
    return str(path)


def assert_stopped_safely(received, head_yaw=0.5):
    """The last /cmd_vel is a zero twist, no goal after it, the head sent back to its start
    (the first head command was start + head_yaw)."""
    twists = [r for r in received if r['topic'] == TWIST]
    goals = [r for r in received if r['topic'] == GOAL]
    assert goals, 'no turn was ever commanded: %s' % received
    assert twists, 'the base was never stopped: %s' % received
    last = twists[-1]
    assert (last['vx'], last['vy'], last['vth']) == (0.0, 0.0, 0.0), last
    assert all(g['t'] <= last['t'] for g in goals), 'a goal after the stop: %s' % received
    assert received.index(last) > received.index(goals[-1])
    heads = [r for r in received if r['topic'] == JOINTS]
    if not head_yaw:
        assert not heads, heads
        return
    assert heads and heads[-1]['angles'] == [pytest.approx(heads[0]['angles'][0] - head_yaw, abs=1e-4)], heads
    assert heads[-1]['t'] >= last['t'] - 0.5     # sent back as the motion stopped
