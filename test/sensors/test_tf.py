"""The robot's transform tree, end to end: the real emulator publishes /tf as naoqi_driver does
(emulator/tf_publisher.py), the real sensorTest listens and looks every sensor's frame up with
tf2 (sensors/frames.py) and judges the tree on the tf row (sensors/tf.py).

* healthy robot and simulator: every frame placed, the tf row passes, no frame reason anywhere;
* each tree fault of the emulator is caught on its row(s) and nowhere else.
"""
import json
import os
import subprocess
import time

import pytest

from emulator_runs import run
from rosmaster import kill_group, script, spawn, wait_until

ROBOT = ['frontCamera', 'bottomCamera', 'depthCamera', 'laser', 'imu', 'odometry', 'frontSonar',
         'jointState', 'tf']
SIM = ['frontCamera', 'depthCamera', 'laser', 'odometry', 'backSonar', 'jointState', 'tf']
FRAMED = [s for s in ROBOT if s not in ('jointState', 'tf')]


def emulator(profile='robot', faults=''):
    params = ['_profile:=' + profile, '_camera_resolution:=QQVGA', '_audio:=off']
    if profile == 'simulator':
        params.append('_real_time_factor:=1')
    if faults:
        params.append('_faults:=' + faults)
    return params


def frame_reasons(s):
    return [r for r in s['reasons'] + s['warnings'] if 'base_footprint' in r or '/tf' in r]


@pytest.mark.parametrize('profile, sensors', [('robot', ROBOT), ('simulator', SIM)])
def test_a_healthy_tree_places_every_frame(master, tmp_path, profile, sensors):
    res, done = run(master, tmp_path, emulator(profile), sensors, platform=profile)
    for name in sensors:
        s = res[name]
        assert s['verdict'] == 'PASS', (name, s['reasons'], done.stderr[-1500:])
        assert not frame_reasons(s), (name, s['warnings'])
    for name in sensors:
        if name in ('jointState', 'tf'):
            continue
        frame = res[name]['frame']
        assert frame['judged'] > 0 and frame['placed'] == frame['judged'], (name, frame)
        assert frame['chain'][-1] == 'base_footprint' and frame['chain'][0] == frame['frame_id'], frame
    assert 'Head' in res['frontCamera']['frame']['chain']
    tf = res['tf']['values']
    assert tf['roots'] == ['odom'] and tf['odom_compared'] > 0 and tf['head_compared'] > 0, tf


def test_no_description_fails_every_frame_and_says_why(master, tmp_path):
    res, _ = run(master, tmp_path, emulator(faults='tf:no_description'), ROBOT)
    for name in FRAMED:
        s = res[name]
        hits = [r for r in s['reasons'] if 'has no path to base_footprint' in r]
        assert s['verdict'] == 'FAIL' and hits, (name, s['reasons'])
        assert 'robot description' in hits[0], hits[0]
    assert 'CameraTop_optical_frame' in res['frontCamera']['reasons'][0]
    tf = res['tf']
    assert tf['verdict'] == 'FAIL' and any('base_footprint is not in the tree' in r for r in tf['reasons'])
    assert res['jointState']['verdict'] == 'PASS', res['jointState']['reasons']


@pytest.mark.parametrize('fault, words', [
    ('second_publisher', ('CameraTop_frame is published by 2 nodes', 'different transforms')),
    ('stale', ('/tf stamps 0.', 'median', 'old when they arrive')),
    ('future_stamps', ('/tf stamps ', 'median', 'in the future')),
])
def test_each_tree_fault_is_caught_on_the_tf_row_only(master, tmp_path, fault, words):
    res, done = run(master, tmp_path, emulator(faults='tf:' + fault), ROBOT)
    tf = res['tf']
    assert tf['verdict'] == 'FAIL' and any(all(w in r for w in words) for r in tf['reasons']), tf['reasons']
    for name in ROBOT:
        if name == 'tf':
            continue
        s = res[name]
        assert s['verdict'] == 'PASS', (fault, name, s['reasons'])
        assert not frame_reasons(s), (fault, name, s['warnings'])


def test_a_second_publisher_recorded_by_rosbag_record_is_named_in_the_bag(master, tmp_path):
    """rosbag record keeps one connection per publishing node, with its callerid: the emulator's
    second publisher (tf:second_publisher, a node named robot_state_publisher) recorded next to
    its tree is named on the tf row of sensorTest --bag as it is live."""
    log_path = tmp_path / 'emulator.log'
    with open(str(log_path), 'w') as log:
        emu = spawn(script('pepperEmulator') + ['__name:=naoqi_driver'] + emulator(faults='tf:second_publisher'),
                    master.env(), stdout=log, stderr=subprocess.STDOUT)
        try:
            wait_until(lambda: 'publishers up' in log_path.read_text(), 30, log_path.read_text)
            time.sleep(1.0)
            bag = str(tmp_path / 'second.bag')
            subprocess.run(['rosbag', 'record', '--duration=4', '-O', bag, '/tf', '/joint_states',
                            '/naoqi_driver/camera/front/image_raw'], env=master.env(), timeout=60,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        finally:
            kill_group(emu)
    out = tmp_path / 'out'
    done = subprocess.run(script('sensorTest') + ['--bag', bag, '--platform', 'robot', '--sensors', 'frontCamera,tf',
                                                  '--output-dir', str(out), '--no-history', '--no-report'],
                          env=dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:1'), capture_output=True,
                          text=True, timeout=120)
    res = {s['name']: s for s in json.loads((out / 'sensorTestResults.json').read_text())['sensors']}
    tf = res['tf']
    words = ('CameraTop_frame is published by 2 nodes', 'different transforms')
    assert tf['verdict'] == 'FAIL' and any(all(w in r for w in words) for r in tf['reasons']), \
        (tf['reasons'], done.stdout[-1500:])
    assert len(tf['values']['publishers']) == 2 and '/naoqi_driver' in tf['values']['publishers'], tf['values']
    assert res['frontCamera']['verdict'] == 'PASS', res['frontCamera']['reasons']


def test_tree_faults_parse_and_are_listed():
    from pepper_interface_tests.emulator import fault_table
    from pepper_interface_tests.emulator.faults import FaultError, format_faults, parse_faults
    f = parse_faults('tf:no_description,stale;TF:future_stamps,second_publisher')
    assert f['tf'].no_description and f['tf'].stale and f['tf'].future_stamps and f['tf'].second_publisher
    assert parse_faults(format_faults(f)) == f
    with pytest.raises(FaultError, match='does not apply to laser'):
        parse_faults('laser:no_description')
    table = fault_table.table()
    for name in ('no_description', 'second_publisher', 'stale', 'future_stamps'):
        assert name in table
    assert max(len(line) for line in table.splitlines()) <= 80


def test_the_emulators_tree_is_the_urdfs():
    """84 pairs below odom as naoqi_driver sends them (joint_state.cpp:147-185), the head chain
    turning with HeadYaw and HeadPitch, the fingers following their hand; the simulator's leg
    chain from base_footprint up."""
    import math

    from pepper_interface_tests.emulator.profiles import JOINT_NAMES
    from pepper_interface_tests.emulator.urdf_tree import JOINTS, driver_tree, simulator_tree
    positions = {j: 0.0 for j in JOINT_NAMES}
    positions.update(HeadYaw=0.4, HeadPitch=-0.2, LHand=1.0)
    tree = driver_tree(positions)
    assert len(JOINTS) == 83 and len(tree) == 83
    by_child = {c: (p, xyz, q) for p, c, xyz, q in tree}
    assert len({c for _, c, _, _ in tree} | {'base_link'}) == 84
    parent, xyz, q = by_child['Neck']
    assert parent == 'torso' and xyz == (-0.038, 0.0, 0.1699)
    assert math.isclose(2 * math.atan2(q[2], q[3]), 0.4, abs_tol=1e-9)
    assert math.isclose(2 * math.atan2(by_child['Head'][2][1], by_child['Head'][2][3]), -0.2, abs_tol=1e-9)
    assert by_child['CameraTop_optical_frame'][0] == 'CameraTop_frame'
    assert by_child['CameraTop_frame'][0] == 'Head' and by_child['base_footprint'][0] == 'Tibia'
    assert driver_tree(positions, described=False) == []
    sim = {c: p for p, c, _, _ in simulator_tree(tree)}
    assert sim['Tibia'] == 'base_footprint' and sim['torso'] == 'Hip' and sim['base_link'] == 'torso'
