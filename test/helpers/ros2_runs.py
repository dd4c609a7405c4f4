"""Helpers of the ROS 2 tier's tests: the programs started as users start them (`ros2 run`,
`ros2 launch`), a DDS domain per test, the ROS 1 environment saved by tools/ros2/tests.sh,
results files."""
import json
import os
import signal

import pytest

# DDS domains 20-219, 50 per pytest-xdist worker (gw0, gw1, ...), one per test
_worker = int(os.environ.get('PYTEST_XDIST_WORKER', 'gw0')[2:] or 0)
_domains = iter(range(20 + 50 * _worker, 70 + 50 * _worker))


def program(name):
    """`ros2 run pepper_interface_tests NAME`, as a user starts it (ros2cli: the tools overlay of
    tools/platform/ros2.sh, or /opt/ros/humble). Humble's `ros2 run` does not forward a signal
    sent to it alone to the program (ros2run/api run_executable): signal the process group, as
    Ctrl-C in a terminal does (rosmaster.kill_group, signal_group)."""
    if not os.environ.get('PEPPER_ROS2_PREFIX'):
        pytest.fail('PEPPER_ROS2_PREFIX is not set: run the ROS 2 tier with tools/ros2/tests.sh')
    return ['ros2', 'run', 'pepper_interface_tests', name]


def signal_as_users_do(proc, sig):
    """SIGINT as Ctrl-C sends it (to the process group of `ros2 run` or `ros2 launch`); SIGTERM
    as `kill PID` of the program sends it (to the program `ros2 run` started: a SIGTERM to
    `ros2 run` itself ends it and leaves the program running, ros2run does not forward it)."""
    if sig == signal.SIGINT:
        os.killpg(proc.pid, sig)
        return
    with open('/proc/%d/task/%d/children' % (proc.pid, proc.pid)) as f:
        children = [int(c) for c in f.read().split()]
    assert len(children) == 1, 'ros2 run %d started %r' % (proc.pid, children)
    os.kill(children[0], sig)


def launch(name, *args):
    """`ros2 launch pepper_interface_tests NAME arg:=value ...`."""
    return ['ros2', 'launch', 'pepper_interface_tests', name] + list(args)


def domain_env(n=None, **extra):
    """The environment of a test of its own DDS domain (tests in the tier must not hear each
    other; ROS_LOCALHOST_ONLY keeps them off the network)."""
    return dict(os.environ, ROS_DOMAIN_ID=str(next(_domains) if n is None else n), **extra)


def ros1_env():
    """The ROS 1 environment the tier saved before it sourced ROS 2 (tools/ros2/tests.sh)."""
    with open(os.environ['PEPPER_ROS1_ENV'], 'rb') as f:
        pairs = [e.split(b'=', 1) for e in f.read().split(b'\0') if b'=' in e]
    return dict((k.decode(), v.decode()) for k, v in pairs)


def results(out):
    with open(os.path.join(str(out), 'sensorTestResults.json')) as f:
        data = json.load(f)
    return data, {s['name']: s for s in data['sensors']}
