"""The audio bridge on ROS 2: the capture side on a real Python 2.7 (scripts/naoqiAudio under
CPython 2.7.12, NAOqi's ALAudioDevice stood in by test/nodes/naoqi27_standin.py as in
test/audio_bridge/test_capture_py27.py) streams over the real websocket, with a token, to
naoqiAudioPublisher on rclpy (`ros2 run`), which publishes naoqi_driver2's AudioBuffer or the
ROS 1 bridge's AudioCustomMsg; an rclpy subscriber receives every sample exactly, in its
microphone's place, and sensorTest on ROS 2 hears the microphones and records them sample-exact
in its WAV file. Run by the ROS 2 tier (tools/ros2/tests.sh)."""
import glob
import os
import re
import signal
import subprocess
import sys

import numpy as np
import pytest

from audio_chain import Procs, python27_or_skip, robot_env
from pepper_interface_tests.emulator.audio_source import expected_counter, find_counter_start
from ros2_runs import domain_env, program, results
from rosmaster import NODES

HELPERS = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'helpers')
STANDIN = os.path.join(NODES, 'naoqi27_standin.py')
SAMPLES = 8192      # NAOqi's 170 ms buffer at 48 kHz


@pytest.fixture
def procs(tmp_path):
    p = Procs(tmp_path)
    yield p
    p.stop_all()
    print(p.logs())  # shown by pytest only when the test failed


def start_chain(procs, tmp_path, env, message, buffers):
    """publisher (ros2 run, any free port, a token) and the ROS 2 dump; returns (publisher,
    dump, the samples fed, the token's environment)."""
    token = tmp_path / 'token'
    token.write_text('p\u00e9pper\n', encoding='utf-8')
    token.chmod(0o600)
    tok = dict(PEPPER_AUDIO_TOKEN_FILE=str(token))
    publisher = procs.start('publisher', program('naoqiAudioPublisher') + ['--port', '0', '--message', message],
                            dict(env, **tok))
    text = publisher.wait_for(r'listening on ws://127\.0\.0\.1:\d+', 40)
    publisher.port = int(re.findall(r'listening on ws://127\.0\.0\.1:(\d+)', text)[-1])
    assert ('(token required), publishing /audio (%s)' % ('naoqi_bridge_msgs/AudioBuffer' if message == 'AudioBuffer'
                                                          else 'pepper_interface_tests/AudioCustomMsg')) in text, text
    dump = procs.start('dump', [sys.executable, os.path.join(HELPERS, 'ros2_audio_dump.py'), '/audio', message,
                                str(tmp_path / 'dump.raw')], env)
    dump.wait_for('dump up', 40)
    fed = expected_counter(0, buffers * SAMPLES)
    raw = tmp_path / 'fed.raw'
    raw.write_bytes(fed.astype('<i2').tobytes())
    return publisher, dump, fed, raw, tok


def capture27(procs, python27, raw, port, tok):
    return procs.start('capture27', [python27, STANDIN, str(raw), str(SAMPLES), '--', '--ip', '127.0.0.1',
                                     '--ws', 'ws://127.0.0.1:%d' % port, '--queue-seconds', '10'], robot_env(**tok))


@pytest.mark.parametrize('message', ['AudioBuffer', 'AudioCustomMsg'])
def test_a_python27_capture_reaches_a_ros2_subscriber_sample_exact(procs, tmp_path, message):
    python27 = python27_or_skip()
    buffers = 24        # 4.1 s of audio
    env = domain_env()
    publisher, dump, fed, raw, tok = start_chain(procs, tmp_path, env, message, buffers)
    capture = capture27(procs, python27, raw, publisher.port, tok)
    capture.wait_for('standin: fed all %d buffer' % buffers, buffers * SAMPLES / 48000.0 + 30)
    dump.wait_for(r'got %d\b' % buffers, 30)
    assert capture.stop(signal.SIGTERM) == 0
    got = np.frombuffer((tmp_path / 'dump.raw').read_bytes(), dtype='<i2').reshape(-1, 4)
    assert 'Python 2.7.12' in capture.log()
    assert got.shape == fed.shape and np.array_equal(got, fed), 'not sample-exact: %s vs %s' % (got.shape, fed.shape)
    assert publisher.stop(signal.SIGINT) == 0
    log = publisher.log()
    assert "'published': %d" % buffers in log and "'lost_in_gaps': 0" in log, log[-2000:]
    assert 'Traceback' not in log + capture.log(), log + capture.log()


def test_sensor_test_on_ros2_hears_the_bridge_and_records_it_sample_exact(procs, tmp_path):
    python27 = python27_or_skip()
    buffers = 60        # 10.2 s: sensorTest's 4 s window falls inside
    env = domain_env()
    publisher, dump, fed, raw, tok = start_chain(procs, tmp_path, env, 'AudioBuffer', buffers)
    capture = capture27(procs, python27, raw, publisher.port, tok)
    capture.wait_for('standin: fed 1\\b|websocket connected', 30)
    out = tmp_path / 'out'
    p = subprocess.run(program('sensorTest') + ['--sensors', 'microphone', '--duration', '4', '--wait', '10',
                       '--output-dir', str(out), '--no-history', '--no-show', '--no-report'],
                       env=env, capture_output=True, text=True, timeout=120, stdin=subprocess.DEVNULL)
    assert 'Traceback' not in p.stdout + p.stderr, p.stdout + p.stderr
    _, rows = results(out)
    mic = rows['microphone']
    assert mic['topic'] == '/audio' and mic['messages'] >= 15, mic
    wavs = glob.glob(os.path.join(str(out), '**', '*.wav'), recursive=True)
    assert len(wavs) == 1, (wavs, p.stdout[-2000:])
    import soundfile
    wav, rate = soundfile.read(wavs[0], dtype='int16', always_2d=True)
    assert rate == 48000 and wav.shape[1] == 4 and len(wav) >= 15 * SAMPLES, (rate, wav.shape)
    # each recorded column is one fed microphone (whatever the WAV's channel order), and together
    # they are the fed samples from one instant on, every sample exact
    order = []
    for col in range(4):
        found = [c for c in range(4) if _one_channel(wav[:, col], c)]
        assert len(found) == 1, 'WAV channel %d is %s of the fed microphones' % (col, found)
        order += found
    assert sorted(order) == [0, 1, 2, 3], order
    fed_order = np.empty_like(wav)
    fed_order[:, order] = wav
    start = find_counter_start(fed_order)
    assert np.array_equal(fed_order, expected_counter(start, len(wav))) and start % SAMPLES == 0, start
    print('\nsensorTest on ROS 2, the bridge from Python 2.7: %s, %d messages, WAV %d samples from fed sample %d, '
          'WAV channels = fed %s' % (mic['verdict'], mic['messages'], len(wav), start, order))


def _one_channel(column, c):
    try:
        start = find_counter_start(column, c)       # the start modulo that channel's period
    except ValueError:
        return False
    return np.array_equal(column, expected_counter(start, len(column))[:, c])
