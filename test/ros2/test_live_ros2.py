"""sensorTest live on ROS 2 (rclpy, the Humble core of tools/platform/ros2.sh): the same data as
a ROS 1 bag, published by naoqi_driver2-shaped rclpy publishers (test/helpers/ros2_live.py),
gets the same verdicts. Run by the ROS 2 tier
(tools/ros2/tests.sh), in a ROS 2 environment (ROS_VERSION=2)."""
import os
import subprocess
import sys

import pytest

import ros2_recordings as rr
from ros2_runs import domain_env, program, results, ros1_env
from rosmaster import kill_group, script, spawn

HERE = os.path.dirname(os.path.abspath(__file__))
LIVE = [sys.executable, os.path.join(HERE, '..', 'helpers', 'ros2_live.py')]
# a topic missing from a bag is, live, a topic nobody publishes
LIVE_WORDS = {'backSonar': 'no publisher on /sonar/back'}
QUIET = ['--no-history', '--no-report', '--no-record', '--no-show']


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
    return results(tmp / 'bag')[1]


def live_run(tmp, faulty, extra=()):
    env = domain_env()
    log = open(str(tmp / 'publisher.log'), 'w')
    pub = spawn(LIVE + (['--faulty'] if faulty else []) + ['--seconds', '12'], env,
                stdout=log, stderr=subprocess.STDOUT)
    try:
        p = subprocess.run(program('sensorTest') + ['--sensors', rr.SENSORS, '--mode', 'parallel',
                           '--duration', '4', '--output-dir', str(tmp / 'live')] + QUIET + list(extra),
                           env=env, capture_output=True, text=True, timeout=120)
    finally:
        kill_group(pub)
        log.close()
    assert 'Traceback' not in p.stdout + p.stderr, p.stdout + p.stderr
    return p, results(tmp / 'live')[1]


@pytest.mark.parametrize('faulty', [False, True], ids=['healthy', 'faulty'])
def test_live_on_ros2_same_verdicts_as_the_same_data_in_a_ros1_bag(tmp_path, faulty):
    expected = bag_verdicts(tmp_path, faulty)
    p, got = live_run(tmp_path, faulty, ['--no-diagnostics'])
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
