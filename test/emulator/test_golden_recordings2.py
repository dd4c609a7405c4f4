"""The golden recordings of the real ros-naoqi/naoqi_driver2 (test/fixtures/real-driver2/, made by
tools/real-driver2/record-golden2.sh against the fake NAOqi, rosbag2 MCAP read with rosbags: no
ROS 2 install needed): every sensor row recorded PASSes on a healthy robot of either head (the
other head's camera SKIPPED), and on the moving one (`move`: test/motion/test_recorded.py finds
its turn and head yaws), and the microphone (`audio`, the fake's --audio-relay), the tree is placed,
and the verdicts are those of the ROS 1 driver's golden recording of the same world
(test/fixtures/real-driver/, the same fake NAOqi: audio.bag for `audio`)."""
import json
import os
import subprocess

import pytest
import yaml

from pepper_interface_tests.motion.witnesses import HEAD_CAMERAS
from pepper_interface_tests.plan import declaration, settings
from pepper_interface_tests.sources.tf_buffer import TF2_MISSING
from rosbags_support import reads_ros2
from rosmaster import script

HERE = os.path.dirname(os.path.abspath(__file__))
FIXTURES = os.path.join(os.path.dirname(HERE), 'fixtures')
GOLDEN2 = os.path.join(FIXTURES, 'real-driver2')
GOLDEN1 = os.path.join(FIXTURES, 'real-driver')
with open(os.path.join(GOLDEN2, 'manifest.json')) as _f:
    MANIFEST = json.load(_f)
RECORDINGS = sorted(MANIFEST['recordings'])
DATA = os.path.join(settings.package_dir(), 'data')
SENSOR_OF2 = {t: n for n, t in settings.read_topics(os.path.join(DATA, 'naoqi_driver2Topics.dat')).items()}
TOUCH = declaration.sensors_of('touch')


def sensors_in(recording):
    """The package's sensors on the recording's topics (as the manifest lists them)."""
    return [SENSOR_OF2[t] for t in MANIFEST['recordings'][recording]['topics'] if t in SENSOR_OF2]


def head_of(recording):
    """The head the recording shows: the one whose driver-only topic carried messages (a topic
    of the other head may be listed with none: naoqi_driver2 2.1.2 src/naoqi_driver.cpp:666-667,
    791, 810); None when it records neither (`move`: the motion witnesses only)."""
    with open(os.path.join(GOLDEN2, recording, 'metadata.yaml')) as f:
        info = yaml.safe_load(f)['rosbag2_bagfile_information']
    carried = {t['topic_metadata']['name'] for t in info['topics_with_message_count'] if t['message_count']}
    shown = [h for h, head in declaration.HEADS.items() if head.sign_part in ''.join(carried)]
    assert len(shown) <= 1, (recording, shown)
    return shown[0] if shown else None


def fake_head(recording):
    """The head the fake NAOqi was given (`--head`, its default the stereo one)."""
    args = MANIFEST['recordings'][recording]['fake_naoqi'].split()
    return args[args.index('--head') + 1] if '--head' in args else 'stereo'


def verdicts(source, names, out):
    os.makedirs(str(out), exist_ok=True)
    cmd = script('sensorTest') + ['--bag', source, '--platform', 'robot', '--sensors', ','.join(names),
                                  '--output-dir', str(out), '--no-history', '--no-report']
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=180,
                       env=dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:1'))
    with open(str(out / 'sensorTestResults.json')) as f:
        return p, {s['name']: s for s in json.load(f)['sensors']}


def test_manifest_names_the_driver_and_the_sources_built():
    sources = MANIFEST['sources']
    assert 'ros-naoqi/naoqi_driver2' in sources, sorted(sources)
    assert all(len(s['commit']) == 40 for s in sources.values())
    total = sum(os.path.getsize(os.path.join(GOLDEN2, r, f)) for r in RECORDINGS
                for f in os.listdir(os.path.join(GOLDEN2, r)))
    assert total < 10e6, 'golden ROS 2 recordings take %.1f MB' % (total / 1e6)


def test_both_heads_the_moving_robot_and_the_microphone_are_recorded():
    assert {'healthy_stereo', 'healthy_xtion', 'move', 'audio'} <= set(RECORDINGS), RECORDINGS
    assert fake_head('audio') == 'stereo' and head_of('audio') == 'stereo'
    assert '--audio-relay' in MANIFEST['recordings']['audio']['fake_naoqi'].split()
    assert fake_head('healthy_xtion') == 'xtion' and head_of('healthy_xtion') == 'xtion'
    assert fake_head('healthy_stereo') == 'stereo' and head_of('healthy_stereo') == 'stereo'


@reads_ros2
@pytest.mark.parametrize('recording', RECORDINGS)
def test_every_recorded_sensor_passes_and_matches_the_ros1_driver(recording, tmp_path):
    names = sensors_in(recording)
    if recording == 'audio':     # the microphone alone, as in the ROS 1 audio bag
        assert names == ['microphone'], names
    else:
        assert 'tf' in names and len(names) >= 10, names
    p, got = verdicts(os.path.join(GOLDEN2, recording), names, tmp_path / 'ros2')
    assert p.returncode == 0, p.stdout[-3000:]
    head = head_of(recording)
    assert head in (None, fake_head(recording)), (recording, head)
    for name in names:
        s = got[name]
        if head is not None and head not in declaration.SENSORS[name].heads:     # the other head's camera
            assert s['verdict'] == 'SKIPPED' and 'this robot has' in s['reasons'][0], (name, s['reasons'])
        elif name in TOUCH:       # nobody touched the robot: unattended, from a recording
            assert s['verdict'] == 'SKIPPED' and 'not touched' in s['reasons'][0], (name, s['reasons'])
        else:
            assert s['verdict'] == 'PASS', (name, s['reasons'], p.stdout[-2000:])
    if 'tf' in names:
        assert got['tf']['verdict'] == 'PASS'
    if 'tf' in names and not TF2_MISSING:       # the tree placed: every stamped row's frame reaches base_footprint
        framed = {n: got[n]['frame'] for n in names if got[n]['verdict'] == 'PASS' and got[n].get('frame')}
        assert len(framed) >= 6, sorted(framed)
        for name, frame in framed.items():
            assert frame['placed'] == frame['judged'] > 10 and frame['chain'][-1] == 'base_footprint', (name, frame)
            if name in HEAD_CAMERAS:
                assert ['Head', 'Neck', 'torso'] == [f for f in frame['chain'] if f in ('Head', 'Neck', 'torso')]
    # the ROS 1 driver's recording of the same world (same fake NAOqi): the same verdicts
    ros1 = os.path.join(GOLDEN1, recording + '.bag')
    if os.path.exists(ros1):
        _, was = verdicts(ros1, names, tmp_path / 'ros1')
        assert {n: got[n]['verdict'] for n in names} == {n: was[n]['verdict'] for n in names}
