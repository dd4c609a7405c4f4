"""sensorTest live on ROS 2 (rclpy, the Humble core of tools/platform/ros2.sh): the same data as
a ROS 1 bag, published by naoqi_driver2-shaped rclpy publishers (test/helpers/ros2_live.py),
gets the same verdicts; this node's /diagnostics go out over rclpy. Run by the ROS 2 tier
(tools/ros2/tests.sh), in a ROS 2 environment (ROS_VERSION=2)."""
import json
import os
import subprocess
import sys

import pytest

import ros2_recordings as rr
from rosmaster import kill_group, script, spawn

HERE = os.path.dirname(os.path.abspath(__file__))
LIVE = [sys.executable, os.path.join(HERE, '..', 'helpers', 'ros2_live.py')]
# a topic missing from a bag is, live, a topic nobody publishes
LIVE_WORDS = {'backSonar': 'no publisher on /sonar/back'}
QUIET = ['--no-history', '--no-report', '--no-record', '--no-show']


def domain_env(n):
    """A DDS domain of the test's own: the tier's tests must not hear each other."""
    return dict(os.environ, ROS_DOMAIN_ID=str(n), ROS_VERSION='2')


def results(out):
    with open(os.path.join(str(out), 'sensorTestResults.json')) as f:
        return {s['name']: s for s in json.load(f)['sensors']}


def ros1_env():
    """The ROS 1 environment the tier saved before it sourced ROS 2 (tools/ros2/tests.sh)."""
    with open(os.environ['PEPPER_ROS1_ENV'], 'rb') as f:
        pairs = [e.split(b'=', 1) for e in f.read().split(b'\0') if b'=' in e]
    return dict((k.decode(), v.decode()) for k, v in pairs)


def bag_verdicts(tmp, faulty):
    """sensorTest --bag on ROS 1 (rospy cannot import next to ROS 2's messages: its own process)."""
    env = dict(ros1_env(), ROS_MASTER_URI='http://127.0.0.1:1')
    bag = str(tmp / 'pepper.bag')
    subprocess.run([sys.executable, '-c', 'import sys; sys.path.insert(0, %r); import ros2_recordings as rr; '
                    'rr.write_ros1(%r, rr.records(faulty=%r))' % (os.path.join(HERE, '..', 'helpers'), bag, faulty)],
                   env=env, check=True, timeout=120)
    p = subprocess.run(script('sensorTest') + ['--bag', bag, '--sensors', rr.SENSORS, '--output-dir',
                       str(tmp / 'bag')] + QUIET + ['--no-diagnostics'], env=env, capture_output=True,
                       text=True, timeout=120)
    assert p.returncode == (1 if faulty else 0), p.stdout + p.stderr
    return results(tmp / 'bag')


def live_run(tmp, domain, faulty, extra=()):
    env = domain_env(domain)
    log = open(str(tmp / 'publisher.log'), 'w')
    pub = spawn(LIVE + (['--faulty'] if faulty else []) + ['--seconds', '12'], env,
                stdout=log, stderr=subprocess.STDOUT)
    try:
        p = subprocess.run(script('sensorTest') + ['--sensors', rr.SENSORS, '--mode', 'parallel',
                           '--duration', '4', '--output-dir', str(tmp / 'live')] + QUIET + list(extra),
                           env=env, capture_output=True, text=True, timeout=120)
    finally:
        kill_group(pub)
        log.close()
    assert 'Traceback' not in p.stdout + p.stderr, p.stdout + p.stderr
    return p, results(tmp / 'live')


@pytest.mark.parametrize('faulty', [False, True], ids=['healthy', 'faulty'])
def test_live_on_ros2_same_verdicts_as_the_same_data_in_a_ros1_bag(tmp_path, faulty):
    expected = bag_verdicts(tmp_path, faulty)
    p, got = live_run(tmp_path, 11 + faulty, faulty, ['--no-diagnostics'])
    assert p.returncode == (1 if faulty else 0), p.stdout + p.stderr
    assert 'ROS 2: topics of naoqi_driver2' in p.stdout, p.stdout
    assert {n: s['verdict'] for n, s in got.items()} == {n: s['verdict'] for n, s in expected.items()}, \
        p.stdout
    for name, s in got.items():
        if faulty and name in rr.FAULTS:     # each fault fails by its name, as in the bag
            words = LIVE_WORDS.get(name, rr.FAULTS[name])
            assert any(words in r for r in s['reasons']), s
        else:
            assert s['verdict'] == 'PASS' and s['messages'] > 0, s
