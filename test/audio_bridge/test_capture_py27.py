"""The capture side on a real Python 2.7, against the real ROS side.

On the robot, scripts/naoqiAudio (audio_bridge/capture.py, frame.py, audio_bridge/__init__.py)
runs under NAOqi's Python 2.7. Here it runs on CPython 2.7.12 built from source with
websocket-client 0.59.0 (tools/platform/python27.sh; tools/setup.sh --test builds it), started
the way it is started on the robot (the script finds ../src by itself; no PYTHONPATH), and
streams to the real naoqiAudioPublisher (Python 3) under a real roscore: real frames over a
real websocket into AudioCustomMsg, read by a real subscriber (test/nodes/audio_dump.py).

Stood in: the qi session and ALAudioDevice, and only here. ``qi`` for Python 2.7 (PyPI's 1.8.3)
needs OpenSSL 1.0, which Debian 12 lacks, so test/nodes/naoqi27_standin.py gives scripts/naoqiAudio
a ``qi`` module whose ALAudioDevice calls ``processRemote(nbOfChannels, nbOfSamplesByChannel,
timeStamp, buffer)`` as NAOqi does for a Python 2 module (the driver's docstring cites the
sources). The qi path itself is tested with qi 3.1.5 against naoqiEndpoint in
test_audio_bridge.py.
"""
import os
import signal
import subprocess
import time

import numpy as np
import pytest

from audio_chain import RATE, Procs, counter_starts, finish_dump, get_param, message_count, wait_messages, wait_param
from pepper_interface_tests.audio_bridge import frame as fr
from pepper_interface_tests.emulator.audio_source import expected_counter
from rosmaster import NODES, ROOT, wait_until

STATS = '/naoqiAudioPublisher/stats'
STANDIN = os.path.join(NODES, 'naoqi27_standin.py')
SAMPLES = 8192      # NAOqi's 170 ms buffer at 48 kHz (the driver's docstring)
BUFFERS = 60        # 10.2 s of audio
# One second of buffers (5.9 of 170.7 ms), the bound of two counts around the publisher's restart:
# the buffers lost in the killed publisher's connection (the kill closes it at once and the
# capture looks for a close before each send, so in practice 0 to 2), and the buffers the
# restarted publisher counts lost again because the ~stats it continues from are written once a
# second (docs/audio-bridge.md, "Sequence accounting").
ONE_SECOND = 6


@pytest.fixture(scope='module')
def python27():
    """CPython 2.7.12 from tools/platform/python27.sh, built by tools/setup.sh --test."""
    res = subprocess.run([os.path.join(ROOT, 'tools/platform/python27.sh'), '--installed'],
                         capture_output=True)
    assert res.returncode == 0, res.stderr.decode()
    return res.stdout.decode().strip()


@pytest.fixture
def procs(tmp_path, master):
    p = Procs(tmp_path)
    yield p
    p.stop_all()
    print(p.logs())  # shown by pytest only when the test failed


def robot_env(**extra):
    """The environment of a Python 2.7 process as on the robot: none of this machine's Python 3
    settings (ROS's PYTHONPATH would hand it the Python 3 packages)."""
    env = {k: v for k, v in os.environ.items() if not k.startswith('PYTHON')}
    env.update(PYTHONUNBUFFERED='1', PYTHONDONTWRITEBYTECODE='1', PYTHONNOUSERSITE='1', **extra)
    return env


def capture27(procs, python27, raw, ws_port, *extra, **env):
    return procs.start('capture27', [python27, STANDIN, str(raw), str(SAMPLES), '--',
                                     '--ip', '127.0.0.1', '--ws', 'ws://127.0.0.1:%d' % ws_port]
                       + list(extra), robot_env(**env))


def settled(dumper):
    """True when the subscriber received nothing new for 0.5 s."""
    n = message_count(dumper)
    time.sleep(0.5)
    return message_count(dumper) == n


def token_file(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text + '\n', encoding='utf-8')
    path.chmod(0o600)
    return str(path)


# Frames built on Python 2.7 from each kind of buffer a NAOqi SDK may hand over (str, which is
# bytes there, bytearray, memoryview), with values that need Python 2's long (sequence > 2^32),
# printed in hex for the Python 3 side to compare.
FRAMES_ON_27 = r"""
import binascii, sys
from pepper_interface_tests.audio_bridge import frame as fr
raw = bytes(bytearray(range(256))) * 2          # 4 ch x 64 samples
for kind in (bytes, bytearray, memoryview):
    f = fr.encode_frame(kind(raw), 4, 64, 48000, 2 ** 40 + 7, ts_sec=1700000000, ts_usec=999999,
                        planar=False, stream_id=0xDEADBEEF)
    d = fr.decode_frame(kind(f))
    assert d.payload == raw and d.sequence == 2 ** 40 + 7, d[:8]
    sys.stdout.write(binascii.hexlify(f).decode('ascii') + '\n')
"""


def test_python27_frames_are_byte_identical_to_python3s(python27):
    """frame.py on 2.7 gives the bytes it gives on 3 for every buffer type it takes (a memoryview
    used to be encoded as its repr on 2.7: str(memoryview) is '<memory at 0x...>')."""
    res = subprocess.run([python27, '-c', FRAMES_ON_27], stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, env=robot_env(PYTHONPATH=os.path.join(ROOT, 'src')))
    assert res.returncode == 0, res.stdout.decode()
    raw = bytes(range(256)) * 2
    want = fr.encode_frame(raw, 4, 64, 48000, 2 ** 40 + 7, ts_sec=1700000000, ts_usec=999999,
                           planar=False, stream_id=0xDEADBEEF).hex()
    assert res.stdout.decode().split() == [want] * 3


def test_python27_capture_is_sample_exact_through_a_publisher_restart(procs, master, tmp_path, python27):
    fed = expected_counter(0, BUFFERS * SAMPLES)       # (samples, 4) int16, channel order of Pepper
    raw = tmp_path / 'fed.raw'
    raw.write_bytes(fed.astype('<i2').tobytes())       # interleaved, as NAOqi sends by default
    # a non-ASCII token read from a file: unicode text on Python 2, sent in the handshake header
    token = dict(PEPPER_AUDIO_TOKEN_FILE=token_file(tmp_path, 'token', 'p\u00e9pper-\u00e9t\u00e9'))
    publisher = procs.publisher(master, 0, env=token)
    out = tmp_path / 'dump.npz'
    dumper = procs.dumper(master, out)
    dumper.wait_for('connected', 30)
    # a queue longer than the restart takes, so no buffer is dropped from it: every buffer fed
    # is either published or lost in the connection the kill broke, and counted below
    capture = capture27(procs, python27, raw, publisher.port, '--queue-seconds', '10', **token)
    wait_messages(dumper, 12, 40)
    before_kill = message_count(dumper)
    wait_param(master, STATS, lambda s: s['published'] >= before_kill, 10)
    publisher.stop(signal.SIGKILL)
    stale = get_param(master, STATS)
    time.sleep(1.5)     # the publisher stays down 1.5 s while the capture keeps receiving
    publisher2 = procs.publisher(master, publisher.port, env=token)
    capture.wait_for('websocket connection lost', 20)
    capture.wait_for('websocket connected', 30, count=2)
    capture.wait_for('standin: fed all %d buffer' % BUFFERS, BUFFERS * SAMPLES / RATE + 30)
    assert capture.stop(signal.SIGTERM) == 0
    log = capture.log()
    # the last buffer fed reached the publisher and the subscriber (one TCPROS connection, in
    # order: everything publisher2 published before it is there too)
    stats = wait_param(master, STATS, lambda s: s['last_sequence'] == str(BUFFERS - 1), 10)
    wait_until(lambda: settled(dumper), 10, 'the subscriber kept receiving for 10 s')
    blocks, _ = finish_dump(dumper, out)
    starts = counter_starts(blocks, SAMPLES)           # every sample exact, in its field
    assert 'Python 2.7.12' in log, log[:500]
    assert starts[0] == 0 and starts[-1] == (BUFFERS - 1) * SAMPLES, starts
    steps = np.diff(starts) // SAMPLES
    assert set(np.diff(starts) % SAMPLES) <= {0} and steps.min() >= 1, steps
    assert np.count_nonzero(steps != 1) <= 1, 'more than one gap (the restart): %s' % steps
    lost = BUFFERS - len(blocks)
    # Counted honestly: NAOqi fed BUFFERS; the capture received and sent every one, dropped
    # none; each is at the subscriber but the `lost` ones sent into the killed publisher's
    # connection, and the restarted publisher counts those (plus its stale snapshot's share).
    assert 'unsubscribed SoundProcessingModule after %d buffer(s)' % BUFFERS in log
    assert 'stopped: %d buffer(s) received, %d sent, 0 dropped' % (BUFFERS, BUFFERS) in log, log
    assert lost <= ONE_SECOND, (lost, steps)
    assert 'continuing sequence accounting' in publisher2.log()
    assert lost <= stats['lost_in_gaps'] <= lost + ONE_SECOND, (stats, stale, lost)
    assert stats['dropped_bad'] == 0 and stats['stream_resets'] == 0, stats
    assert 'Traceback' not in log, log
