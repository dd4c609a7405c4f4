"""The fake NAOqi (emulator/fake_naoqi.py): a real libqi client (test/nodes/fake_naoqi_probe.py)
asks each service what ros-naoqi/naoqi_driver asks it, with the driver's own arguments, and the
answers have the shapes the driver reads (file:line in fake_naoqi.py) and the emulator's world in
them; the faults change exactly what the driver turns into data."""
import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from driver_views import driver_scan
from pepper_interface_tests.emulator import scene
from pepper_interface_tests.emulator.profiles import JOINT_NAMES
from rosmaster import NODES, kill_group, script, spawn

PROBE = os.path.join(NODES, 'fake_naoqi_probe.py')


def ask(*args, seconds=0.0, probe=()):
    """Start pepperFakeNaoqi with `args`, probe it, stop it: the probe's answers."""
    proc = spawn(script('pepperFakeNaoqi') + ['--port', '0'] + list(args), os.environ.copy(),
                 stdout=subprocess.PIPE)
    try:
        url = None
        for _ in range(200):
            line = proc.stdout.readline().decode()
            if not line:
                break
            if line.startswith('fake NAOqi ready on '):
                url = line.split()[4]
                break
        assert url, 'the fake NAOqi did not start'
        done = subprocess.run([sys.executable, PROBE, '--url', url, '--seconds', str(seconds)] + list(probe),
                              capture_output=True, text=True, timeout=60)
        assert done.returncode == 0, done.stderr[-3000:]
        return json.loads(done.stdout.strip().splitlines()[-1])
    finally:
        kill_group(proc)


@pytest.fixture(scope='module')
def healthy():
    return ask(seconds=0.0)


def test_answers_have_the_shapes_the_driver_reads(healthy):
    got = healthy
    assert got['type'] == 'juliette' and got['version'] == '2.5.10.7' and got['mic'] == 1
    assert got['joints'] == list(JOINT_NAMES)
    assert len(got['angles']) == len(JOINT_NAMES) and len(got['position']) == 6 and len(got['velocity']) == 3
    assert np.array(got['limits']).shape == (1, 4)
    assert 'CameraStereo' in got['sensor_names']
    names, values = got['config']
    assert names[:3] == ['Model Type', 'Head Version', 'Body Version'] and len(values) == len(names)
    # the wheels have no velocity key: getData raises, the driver writes NaN (joint_state.cpp:128-132)
    assert got['velocity_key'].startswith('raised: ')
    # images: ints, the buffer as Raw (bytearray here; a String would fail from_any_value.cpp:110-118)
    front, depth, stereo = got['images']['front'], got['images']['depth'], got['images']['stereo']
    assert front[0][:3] == [320, 240, 3] and front[1] == 'bytearray' and front[2] == 320 * 240 * 3
    assert depth[0][:3] == [640, 360, 2] and depth[2] == 640 * 360 * 2
    assert stereo[0][:3] == [640, 180, 3] and stereo[2] == 640 * 180 * 3
    assert got['images']['xtion'][0][:3] == [320, 240, 2] and got['images']['ir'][0][:3] == [320, 240, 2]
    assert len(got['imu']) == 10 and abs(got['imu'][9] - scene.GRAVITY) < 0.2


def test_the_world_is_the_emulator_scene(healthy):
    """Sonar in the scene's range band; the laser's 90 keys give, through the driver's own
    arithmetic, the emulator's 61-slot scan layout with -1 in 15-22 and 38-45."""
    for front, back in healthy['sonar']:
        assert 0.2 < front < 5.0 and 0.2 < back < 5.0
    scan = driver_scan(healthy['laser'][0])
    blind = np.r_[15:23, 38:46]
    assert np.all(scan[blind] == -1.0)
    seen = np.delete(scan, blind)
    assert np.all((seen > 0.1) & (seen < 8.0)), seen
    # the world moves: consecutive readings differ
    assert healthy['laser'][0] != healthy['laser'][2]
    temps, battery = healthy['diag'][0:-4:2], healthy['diag'][-4]
    assert max(temps) < 68 and battery > 60       # diagnostics.cpp: OK levels


def test_faults_change_what_the_driver_reads():
    got = ask('--fault', 'missing-key', '--fault', 'stuck-laser', '--fault', 'hot-joint',
              '--fault', 'low-battery', '--fault', 'camera-fails', '--fault', 'touch', '--naoqi',
              '2.9.5.172', '--head', 'xtion', seconds=2.5)
    assert all(front is None and back is not None for front, back in got['sonar'])
    front_keys = slice(30, 60)
    assert got['laser'][0][front_keys] == got['laser'][2][front_keys]       # stuck
    assert got['laser'][0][:30] != got['laser'][2][:30]                      # the others move
    assert got['diag'][0] == 75.0 and got['diag'][-4] == 20.0             # HeadYaw hot, battery low
    assert got['images']['front'].startswith('raised: ')
    assert got['images']['depth'][0][:3] == [640, 360, 2]
    assert got['version'] == '2.9.5.172' and 'CameraStereo' not in got['sensor_names']
    assert [1.0, 0.0] == [v for _, v in got['touch'][:2]] or [0.0, 1.0] == [v for _, v in got['touch'][:2]], \
        got['touch']
    assert all(k == 'FrontTactilTouched' for k, _ in got['touch'])
    # naoqi_driver2's subscriber object gets the same events on its signal (touch.cpp:91-92)
    assert got['touch_signal'] == got['touch'], (got['touch_signal'], got['touch'])


def test_almotion_commands_move_the_world_the_driver_reads():
    """The driver's subscribers call ALMotion.moveTo and setAngles (moveto.cpp, teleop.cpp): the
    fake's body (emulator/body.py) turns and the head yaws, so getPosition and getAngles, which
    the driver's odometry and joint_states read, follow the commands."""
    out = ask(probe=['--move'])
    (pos0, angles0), (pos1, angles1) = out['before'], out['after']
    turned = math.atan2(math.sin(pos1[5] - pos0[5]), math.cos(pos1[5] - pos0[5]))
    # a turn to the right; the idle drive (0.15 rad/s to the left) stops at the command
    assert turned == pytest.approx(-0.5, abs=0.08)
    yaw = JOINT_NAMES.index('HeadYaw')
    assert angles1[yaw] == pytest.approx(0.4, abs=0.02)
    assert abs(angles0[yaw] - 0.4) > 0.2


def test_audio_relay_takes_raw_buffers_at_real_time_pace():
    """--audio-relay: ALAudioDevice is left to audio_relay.cpp, which takes each buffer from
    FakeAudioFrames.next_buffer: 4 channels x 4096 samples for the driver's preferences
    (48000, 0 = all channels, interleaved: src/event/audio.cpp:107-113), the samples as Raw
    (bytearray here; a bytes argument would travel as its str() text), one per 85.3 ms."""
    plain = ask(seconds=0.0)
    assert plain['audio_services'] == ['ALAudioDevice']
    got = ask('--audio-relay', seconds=0.0, probe=['--audio-relay'])
    assert got['audio_services'] == ['FakeAudioFrames']
    bufs = got['buffers']
    assert all(b[:2] == [4, 4096] and b[3] == 'bytearray' and b[4] == 4 * 4096 * 2 for b in bufs), bufs
    steps = np.diff([b[2] for b in bufs])       # NAOqi's timestamps: one buffer apart
    assert np.allclose(steps, 4096 / 48000.0, atol=1e-3), steps
    assert got['after_unsubscribe'].startswith('raised: ') and 'not subscribed' in got['after_unsubscribe']
