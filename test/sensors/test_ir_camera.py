"""The Xtion head's infrared camera (irCamera), added as one declaration row: naoqi_driver publishes
it on an Xtion head only (src/naoqi_driver.cpp:610-611, 753-762; camera.cpp:215-224: 16UC1,
CameraDepth_optical_frame). The emulator's healthy Xtion head PASSes it, its frozen and black
faults FAIL it, a stereo head SKIPs it with its reason, and so do the real driver's golden
recordings (test/fixtures/real-driver): real roscore, real emulator, real sensorTest."""
import json
import os
import subprocess

import pytest

from emulator_runs import run
from pepper_interface_tests.emulator.profiles import build_profile
from pepper_interface_tests.plan import catalog
from rosmaster import script

pytestmark = pytest.mark.integration     # every test here but the first starts real processes
GOLDEN = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), 'fixtures', 'real-driver')
STOCK = ['_profile:=robot-stock', '_audio:=off', '_camera_resolution:=QQVGA']


def test_declared_on_the_xtion_head_only():
    row = catalog.SENSORS['irCamera']
    assert row.family == 'camera' and row.heads == ('xtion',) and not row.simulator
    for profile in ('robot', 'robot-stock'):
        spec = build_profile(profile, head='xtion').sensor('irCamera')
        assert (spec.topic, spec.encoding, spec.width, spec.height, spec.rate, spec.frame_id) == (
            '/naoqi_driver/camera/ir/image_raw', '16UC1', 320, 240, 10.0, 'CameraDepth_optical_frame')
        assert build_profile(profile, head='stereo').sensor('irCamera') is None
        assert build_profile(profile, head='xtion').sensor('depthCamera').extra == ()   # its own stream now
    sign = catalog.head_sign_topic('irCamera', '/naoqi_driver/camera/ir/image_raw')
    assert sign == '/naoqi_driver/camera/stereo/image_raw'


def test_the_emulator_xtion_head_passes_and_its_faults_fail(master, tmp_path):
    res, done = run(master, tmp_path, STOCK + ['_head:=xtion'], ['irCamera', 'stereoCamera'], tag='healthy')
    ir = res['irCamera']
    assert ir['verdict'] == 'PASS', (ir['reasons'], done.stdout[-2000:])
    assert ir['values']['encoding'] == '16UC1' and ir['values']['width'] == 320, ir['values']
    assert any('own range: 10 bits' in n for n in ir['notes']), ir['notes']
    assert res['stereoCamera']['verdict'] == 'SKIPPED'
    assert 'this robot has an Xtion head' in res['stereoCamera']['reasons'][0]
    for fault, words in (('frozen', 'image frozen'), ('black', 'image black')):
        res, done = run(master, tmp_path, STOCK + ['_head:=xtion', '_faults:=irCamera:' + fault], ['irCamera'],
                        tag=fault)
        ir = res['irCamera']
        assert ir['verdict'] == 'FAIL' and any(words in r for r in ir['reasons']), (fault, ir['reasons'])


def test_a_stereo_head_skips_it_with_its_reason(master, tmp_path):
    res, done = run(master, tmp_path, STOCK + ['_head:=stereo'], ['irCamera', 'stereoCamera'])
    ir = res['irCamera']
    assert ir['verdict'] == 'SKIPPED', (ir['reasons'], done.stdout[-2000:])
    assert ir['reasons'][0].startswith('this robot has a stereo head (Pepper 1.8): naoqi_driver publishes '
                                       'its stereo camera on /naoqi_driver/camera/stereo/image_raw'), ir['reasons']
    assert res['stereoCamera']['verdict'] == 'PASS' and done.returncode == 0, done.stdout[-2000:]


@pytest.mark.parametrize('bag, verdict', [('healthy_xtion', 'PASS'), ('healthy_stereo', 'SKIPPED')])
def test_the_real_drivers_recordings(bag, verdict, tmp_path):
    cmd = script('sensorTest') + ['--bag', os.path.join(GOLDEN, bag + '.bag'), '--platform', 'robot',
                                  '--sensors', 'irCamera', '--output-dir', str(tmp_path), '--no-history',
                                  '--no-report']
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120,
                       env=dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:1'))
    with open(str(tmp_path / 'sensorTestResults.json')) as f:
        ir = json.load(f)['sensors'][0]
    assert ir['verdict'] == verdict, (ir['reasons'], p.stdout[-2000:])
    if verdict == 'PASS':       # the fake NAOqi's IR frames: 16UC1 320x240 at 10 Hz, a real video
        assert ir['messages'] >= 30 and ir['values']['encoding'] == '16UC1', ir
        assert ir['values']['video']['frames_written'] >= 30, ir['values']['video']
