"""The robot's transform tree, end to end: the real emulator publishes /tf as naoqi_driver does
(emulator/tf_publisher.py), the real sensorTest listens and looks every sensor's frame up with
tf2 (sensors/frames.py) and judges the tree on the tf row (sensors/tf.py).

* healthy robot and simulator: every frame placed, the tf row passes, no frame reason anywhere;
* each tree fault of the emulator is caught on its row(s) and nowhere else.
"""
import pytest

from emulator_runs import run

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
    ('stale', ('/tf stamps up to', 'old when they arrive')),
    ('future_stamps', ('/tf stamps up to', 'in the future')),
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
