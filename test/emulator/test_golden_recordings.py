"""The golden recordings of the real ros-naoqi/naoqi_driver (test/fixtures/real-driver/, made by
tools/real-driver/record-golden.sh against the fake NAOqi): sensorTest's verdicts on each are
the expected ones, and the emulator's own streams match the real driver's, topic by topic
(names, types, md5, frame ids, encodings and sizes, array lengths and special values, rates as
configured). Every difference the emulator keeps is in KNOWN_DIFFERENCES with its reason,
written out in docs/drivers.md ("What the real driver published")."""
import json
import os
import subprocess

import pytest

from bag_facts import bag_facts
from pepper_interface_tests.emulator.profiles import build_profile
from pepper_interface_tests.plan import settings
from rosmaster import script

HERE = os.path.dirname(os.path.abspath(__file__))
GOLDEN = os.path.join(os.path.dirname(HERE), 'fixtures', 'real-driver')
with open(os.path.join(GOLDEN, 'manifest.json')) as _f:
    MANIFEST = json.load(_f)
BAGS = sorted(MANIFEST['bags'])
NS = '/naoqi_driver'
TOPICS = settings.read_topics(os.path.join(settings.package_dir(), 'data', 'pepperTopics.dat'))
SENSOR_OF = {topic: name for name, topic in TOPICS.items()}

# bag -> {sensor: (verdict, words in its first reason)}; any sensor not named here PASSES.
EXPECTED = {
    'healthy_stereo': {},
    'healthy_xtion': {'stereoCamera': ('SKIPPED', 'this robot has an Xtion head')},
    'camera_fails': {'frontCamera': ('FAIL', 'is not in the bag')},
    'missing_key': {'frontSonar': ('FAIL', '')},
    'stuck_laser': {'laser': ('FAIL', '')},
    'touch': {},
    'hot_joint': {'robotHealth': ('FAIL', 'HeadYaw')},
    'low_battery': {'robotHealth': ('FAIL', 'battery')},
    'naoqi29': {},
}
TOUCH = ('headTouch', 'handTouch', 'bumper')


def sensors_in(bag):
    """The package's sensors on the bag's recorded topics (as the manifest lists them)."""
    names = [SENSOR_OF[t] for t in MANIFEST['bags'][bag]['topics'] if t in SENSOR_OF]
    if 'stereoCamera' not in names and 'depthCamera' in names:
        names.append('stereoCamera')
    return names


def run_sensor_test(bag, names, out):
    cmd = script('sensorTest') + ['--bag', os.path.join(GOLDEN, bag + '.bag'), '--platform', 'robot',
                                  '--sensors', ','.join(names), '--output-dir', str(out),
                                  '--no-history', '--no-report']
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120,
                       env=dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:1'))
    with open(str(out / 'sensorTestResults.json')) as f:
        return p, {s['name']: s for s in json.load(f)['sensors']}


def test_manifest_names_what_was_built():
    assert set(MANIFEST['sources']) == {'libqi', 'libqicore', 'naoqi_bridge_msgs', 'naoqi_driver'}
    assert all(len(s['commit']) == 40 for s in MANIFEST['sources'].values())
    total = sum(os.path.getsize(os.path.join(GOLDEN, b + '.bag')) for b in BAGS)
    assert total < 20e6, 'golden recordings take %.1f MB' % (total / 1e6)


@pytest.mark.parametrize('bag', BAGS)
def test_sensor_test_verdicts_on_the_real_driver(bag, tmp_path):
    names = sensors_in(bag)
    p, got = run_sensor_test(bag, names, tmp_path)
    expected = EXPECTED[bag]
    for name in names:
        s = got[name]
        if name in expected:
            verdict, words = expected[name]
            assert s['verdict'] == verdict, (name, s['verdict'], s['reasons'])
            assert words in s['reasons'][0], (name, s['reasons'])
        elif name in TOUCH:     # event topics: judged live only (they drive their own checks)
            assert s['verdict'] == 'SKIPPED', (name, s['reasons'])
        else:
            assert s['verdict'] == 'PASS', (name, s['reasons'], p.stdout[-2000:])
