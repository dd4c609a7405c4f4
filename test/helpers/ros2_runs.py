"""Helpers of the ROS 2 tier's tests: the colcon-installed programs, a DDS domain per test, the
ROS 1 environment saved by tools/ros2/tests.sh, results files."""
import json
import os

import pytest

# DDS domains 20-219, 50 per pytest-xdist worker (gw0, gw1, ...), one per test
_worker = int(os.environ.get('PYTEST_XDIST_WORKER', 'gw0')[2:] or 0)
_domains = iter(range(20 + 50 * _worker, 70 + 50 * _worker))


def program(name):
    """`ros2 run pepper_interface_tests NAME` without ros2cli (not in the core): the installed
    program itself, lib/pepper_interface_tests/NAME of the workspace."""
    prefix = os.environ.get('PEPPER_ROS2_PREFIX')
    if not prefix:
        pytest.fail('PEPPER_ROS2_PREFIX is not set: run the ROS 2 tier with tools/ros2/tests.sh')
    return [os.path.join(prefix, 'lib', 'pepper_interface_tests', name)]


def domain_env(n=None, **extra):
    """The environment of a test of its own DDS domain (tests in the tier must not hear each
    other; ROS_LOCALHOST_ONLY keeps them off the network)."""
    return dict(os.environ, ROS_DOMAIN_ID=str(next(_domains) if n is None else n), ROS_VERSION='2', **extra)


def ros1_env():
    """The ROS 1 environment the tier saved before it sourced ROS 2 (tools/ros2/tests.sh)."""
    with open(os.environ['PEPPER_ROS1_ENV'], 'rb') as f:
        pairs = [e.split(b'=', 1) for e in f.read().split(b'\0') if b'=' in e]
    return dict((k.decode(), v.decode()) for k, v in pairs)


def results(out):
    with open(os.path.join(str(out), 'sensorTestResults.json')) as f:
        data = json.load(f)
    return data, {s['name']: s for s in data['sensors']}
