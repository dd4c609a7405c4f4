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

from audio_chain import (
    RATE,
    counter_starts,
    finish_dump,
    get_param,
    message_count,
    python27_or_skip,
    robot_env,
    wait_messages,
    wait_param,
)
from pepper_interface_tests.audio_bridge import frame as fr
from pepper_interface_tests.emulator.audio_source import expected_counter
from rosmaster import NODES, ROOT, wait_until

STATS = '/naoqiAudioPublisher/stats'
STANDIN = os.path.join(NODES, 'naoqi27_standin.py')
SAMPLES = 8192      # NAOqi's 170 ms buffer at 48 kHz (the driver's docstring)
BUFFERS = 120       # 20.5 s of audio: two restarts take about 12 s
# Buffers lost in a connection the kill broke: the kill closes it at once and the capture looks
# for a close before each send, so in practice 0 to 2; bounded at one second of buffers (5.9).
IN_FLIGHT = 6
# A publisher restarted after a kill counts from the ~stats the killed one left, written once a
# second (docs/audio-bridge.md, "Sequence accounting"): the buffers published since then are
# counted lost again. One second is 5.9 buffers; two allow for a late write on a loaded machine.
STALE_STATS = 12


@pytest.fixture(scope='module')
def python27():
    return python27_or_skip()


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


def test_python27_capture_is_sample_exact_through_publisher_restarts(procs, master, tmp_path, python27):
    """The publisher killed (SIGKILL) and later stopped (SIGTERM) mid-stream, each time restarted
    1.5 s later on its port: the capture reconnects each time and every buffer fed is either at
    the subscriber, sample-exact, or counted lost by the publisher that came back."""
    fed = expected_counter(0, BUFFERS * SAMPLES)       # (samples, 4) int16, channel order of Pepper
    raw = tmp_path / 'fed.raw'
    raw.write_bytes(fed.astype('<i2').tobytes())       # interleaved, as NAOqi sends by default
    # a non-ASCII token read from a file: unicode text on Python 2, sent in the handshake header
    token = dict(PEPPER_AUDIO_TOKEN_FILE=token_file(tmp_path, 'token', 'p\u00e9pper-\u00e9t\u00e9'))
    publisher = procs.publisher(master, 0, env=token)
    out = tmp_path / 'dump.npz'
    dumper = procs.dumper(master, out)
    dumper.wait_for('connected', 30)
    # a queue longer than a restart takes, so no buffer is dropped from it: every buffer fed is
    # either published or lost in the connection the restart broke, and counted below
    capture = capture27(procs, python27, raw, publisher.port, '--queue-seconds', '10', **token)
    restarts = []
    for n, sig in enumerate((signal.SIGKILL, signal.SIGTERM), 1):
        wait_messages(dumper, message_count(dumper) + 12, 40)   # 2 s of streaming
        publisher.stop(sig)
        left = get_param(master, STATS)     # after SIGTERM: written at its exit, exact
        time.sleep(1.5)     # the publisher stays down 1.5 s while the capture keeps receiving
        publisher = procs.publisher(master, publisher.port, env=token)
        capture.wait_for('websocket connection lost', 20, count=n)
        capture.wait_for('websocket connected', 30, count=n + 1)
        restarts.append((sig, left, publisher))
    capture.wait_for('standin: fed all %d buffer' % BUFFERS, BUFFERS * SAMPLES / RATE + 30)
    # the last buffer fed reached the publisher, then the subscriber (one TCPROS connection, in
    # order: everything the last publisher published before it is there too)
    final = wait_param(master, STATS, lambda s: s['last_sequence'] == str(BUFFERS - 1), 30)
    assert capture.stop(signal.SIGTERM) == 0
    log = capture.log()
    wait_until(lambda: settled(dumper), 10, 'the subscriber kept receiving for 10 s')
    blocks, _ = finish_dump(dumper, out)
    starts = counter_starts(blocks, SAMPLES)           # every sample exact, in its field
    assert 'Python 2.7.12' in log, log[:500]
    assert set(starts % SAMPLES) == {0} and (np.diff(starts) > 0).all(), starts
    received = set((starts // SAMPLES).tolist())
    assert min(received) == 0 and max(received) == BUFFERS - 1, sorted(received)
    # Counted honestly: NAOqi fed BUFFERS; the capture received and sent every one and dropped
    # none; each is at the subscriber but the ones sent into a connection a restart broke, and
    # the publisher that came back counts those.
    assert 'unsubscribed SoundProcessingModule after %d buffer(s)' % BUFFERS in log
    assert 'stopped: %d buffer(s) received, %d sent, 0 dropped' % (BUFFERS, BUFFERS) in log, log
    (_, killed, second), (_, stopped, third) = restarts
    second_stats = stopped              # what the second publisher wrote at its exit
    assert 'after sequence %s' % stopped['last_sequence'] in third.log()
    missing = sorted(set(range(BUFFERS)) - received)
    at_kill = [s for s in missing if s <= int(stopped['last_sequence'])]
    at_stop = [s for s in missing if s > int(stopped['last_sequence'])]
    # a stopping publisher closes the connection first: only a buffer in flight can be lost
    assert len(at_kill) <= IN_FLIGHT and len(at_stop) <= 1, missing
    # after the kill, the second publisher counts from ~stats up to a second old
    assert len(at_kill) <= second_stats['lost_in_gaps'] <= len(at_kill) + STALE_STATS, (
        second_stats, killed, at_kill)
    # after SIGTERM, the third continues from the exact count its predecessor left
    assert final['lost_in_gaps'] == len(at_stop), (final, stopped, at_stop)
    for stats in (second_stats, final):
        assert stats['dropped_bad'] == 0 and stats['stream_resets'] == 0, stats
    assert 'continuing sequence accounting' in second.log()
    assert 'Traceback' not in log, log
    print('\nPython 2.7 capture: %d buffers fed, %d at the subscriber; lost at the kill %d '
          '(counted %d), at the stop %d (counted %d)' % (
              BUFFERS, len(blocks), len(at_kill), second_stats['lost_in_gaps'], len(at_stop),
              final['lost_in_gaps']))


def test_python27_capture_refused_for_its_token_says_why_and_counts_what_it_drops(procs, master, tmp_path,
                                                                                 python27):
    """HTTP 401 as websocket-client 0.59 reports it on 2.7 (its status_code) gives the one ERROR
    line; the queue keeps --queue-seconds of audio and counts every buffer it drops."""
    fed = 20
    raw = tmp_path / 'fed.raw'
    raw.write_bytes(expected_counter(0, fed * SAMPLES).astype('<i2').tobytes())
    publisher = procs.publisher(master, 0, env=dict(
        PEPPER_AUDIO_TOKEN_FILE=token_file(tmp_path, 'right', 'right')))
    capture = capture27(procs, python27, raw, publisher.port, '--queue-seconds', '0.5',
                        PEPPER_AUDIO_TOKEN_FILE=token_file(tmp_path, 'wrong', 'wr\u00f6ng'))
    capture.wait_for('standin: fed all %d buffer' % fed, fed * SAMPLES / RATE + 30)
    assert capture.stop(signal.SIGTERM) == 0
    log = capture.log()
    assert 'ERROR: publisher at ws://127.0.0.1:%d refuses this capture: HTTP 401' % publisher.port in log
    # 0.5 s holds 2 buffers of 170.7 ms (3 would be 0.51 s): the other 18 are dropped, counted
    assert 'stopped: %d buffer(s) received, 0 sent, %d dropped (queue full)' % (fed, fed - 2) in log, log
    stats = wait_param(master, STATS, lambda s: s['bad_causes'].get('wrong token', 0) >= 1, 10)
    assert stats['received'] == 0 and stats['rejected_connections'] >= 1, stats
    assert 'Traceback' not in log, log
