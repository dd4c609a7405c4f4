"""The NAOqi audio bridge end to end, with real processes only:

naoqiEndpoint (libqi) -> naoqiAudio -> websocket -> naoqiAudioPublisher -> roscore -> audio_dump

Each chain test gets a fresh roscore and free ports, so it can run next to other tests.
"""
import ast
import os
import re
import signal
import socket
import subprocess
import sys
import time

import numpy as np
import psutil
import pytest
import websocket  # websocket-client: the raw (hostile) client of these tests

from audio_chain import (
    BUFFER,
    RATE,
    Procs,
    counter_starts,
    finish_dump,
    free_port,
    get_param,
    message_count,
    wait_messages,
    wait_param,
)
from check_runs import ROBOT
from pepper_interface_tests.audio_bridge import frame as fr
from pepper_interface_tests.audio_bridge.publisher import STATS_INTERVAL
from pepper_interface_tests.emulator.audio_source import (
    CHANNEL_NAMES,
    CHANNEL_TONES_HZ,
    AudioSource,
    expected_counter,
)
from rosmaster import ROOT, kill_group, script, wait_until

STATS = '/naoqiAudioPublisher/stats'
CAPTURE_SIDE = [os.path.join(ROOT, 'src/pepper_interface_tests/audio_bridge/capture.py'),
                os.path.join(ROOT, 'src/pepper_interface_tests/audio_bridge/frame.py'),
                os.path.join(ROOT, 'src/pepper_interface_tests/audio_bridge/__init__.py'),
                os.path.join(ROOT, 'scripts/naoqiAudio')]


def chain(procs, master, tmp_path, pattern='counter', endpoint_args=(), capture_args=(),
          publisher_args=(), with_capture=True, publisher_env=None):
    """Start the whole chain; return (naoqi_port, ws_port, dump_path, processes dict). Both
    servers bind port 0 and report the port they got, so no two tests can collide."""
    endpoint = procs.endpoint(0, '--pattern', pattern, *endpoint_args)
    publisher = procs.publisher(master, 0, *publisher_args, env=publisher_env)
    naoqi_port, ws_port = endpoint.port, publisher.port
    out = tmp_path / ('dump-%d.npz' % ws_port)
    dumper = procs.dumper(master, out)
    dumper.wait_for('connected', 30)
    capture = procs.capture(naoqi_port, ws_port, *capture_args) if with_capture else None
    return naoqi_port, ws_port, out, dict(endpoint=endpoint, publisher=publisher,
                                          dumper=dumper, capture=capture)


def dominant_hz(x, rate=RATE):
    x = np.asarray(x, dtype=np.float64)
    spectrum = np.abs(np.fft.rfft((x - x.mean()) * np.hanning(len(x))))
    return np.fft.rfftfreq(len(x), 1.0 / rate)[np.argmax(spectrum)]


# ---------------------------------------------------------------- frame format (pure code)

def good_frame(seq=0, planar=True, channels=4, samples=BUFFER, stream_id=1):
    payload = expected_counter(seq * samples, samples, channels)
    payload = (payload.T if planar else payload).astype('<i2').tobytes()
    return fr.encode_frame(payload, channels, samples, RATE, seq, 100, 5, planar=planar,
                           stream_id=stream_id)


def test_frame_roundtrip_and_every_rejection():
    data = good_frame(seq=7, planar=False)
    f = fr.decode_frame(data)
    assert (f.planar, f.channels, f.samples_per_channel, f.sample_rate, f.sequence, f.ts_sec,
            f.ts_usec, f.stream_id) == (False, 4, BUFFER, RATE, 7, 100, 5, 1)
    assert len(data) == fr.HEADER_SIZE + 4 * BUFFER * 2 and fr.HEADER_SIZE == 40
    assert f.payload == data[40:]
    assert fr.decode_frame(bytearray(data)) == f
    assert fr.decode_frame(memoryview(data)) == f
    header = list(fr.HEADER.unpack_from(data))

    def with_header(**changes):
        h = list(header)
        names = ['magic', 'version', 'flags', 'channels', 'samples', 'rate', 'stream_id',
                 'sequence', 'ts_sec', 'ts_usec', 'payload_bytes']
        for k, v in changes.items():
            h[names.index(k)] = v
        return fr.HEADER.pack(*h) + data[40:]

    cases = {
        'bad magic': [b'XXXX' + data[4:], b'GET / HTTP/1.1', b'Q'],
        'truncated': [data[:20], data[:-2], b'PAU1', b'P'],
        'oversized': [with_header(samples=20000, payload_bytes=4 * 20000 * 2),
                      data + b'\0' * (fr.MAX_FRAME_BYTES)],
        'length mismatch': [with_header(payload_bytes=10), data + b'\0\0'],
        'bad channel count': [with_header(channels=0), with_header(channels=9)],
        'bad version': [with_header(version=9)],
        'bad flags': [with_header(flags=0x80)],
        'bad sample rate': [with_header(rate=0)],
    }
    for cause, messages in cases.items():
        for m in messages:
            with pytest.raises(fr.FrameError) as err:
                fr.decode_frame(m)
            assert err.value.cause == cause, (cause, str(err.value))
            assert cause in str(err.value)
    with pytest.raises(fr.FrameError, match='length mismatch'):
        fr.encode_frame(b'\0' * 10, 4, BUFFER, RATE, 0)


def test_capture_side_is_python27_compatible(tmp_path):
    """vermin (source level) on the capture side, with a control that vermin does flag py3-only
    code; and, where a Python 2.7 interpreter exists, the real thing."""
    vermin = os.path.join(os.path.dirname(sys.executable), 'vermin')
    cmd = [vermin, '-t=2.7-', '-t=3.7-', '--no-tips', '--violations']
    res = subprocess.run(cmd + CAPTURE_SIDE, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    assert res.returncode == 0, res.stdout.decode()
    bad = tmp_path / 'py3only.py'
    bad.write_text('x = 1\nprint(f"{x}")\n')
    res = subprocess.run(cmd + [str(bad)], stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    assert res.returncode != 0, 'vermin did not flag an f-string: the check is blind'
    for path in CAPTURE_SIDE:  # it may run on the robot: no ROS, no numpy
        tree = ast.parse(open(path).read())
        modules = [a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names]
        modules += [n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)]
        assert not [m for m in modules if m.split('.')[0] in (
            'rospy', 'roslib', 'rosgraph', 'genpy', 'std_msgs', 'numpy')], (path, modules)
    # CPython 2.7.12 as tools/setup.sh --test builds it (test_capture_py27.py runs the whole
    # capture side on it), or $PYTHON27
    built = subprocess.run([os.path.join(ROOT, 'tools/platform/python27.sh'), '--installed'],
                           capture_output=True)
    py27 = os.environ.get('PYTHON27') or (built.stdout.decode().strip() if built.returncode == 0 else None)
    if not py27:
        return  # the static check above is the requirement; no 2.7 interpreter here
    env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, 'src'))
    code = ('from pepper_interface_tests.audio_bridge import frame, capture\n'
            'f = frame.encode_frame(bytearray(b"\\x01\\x00" * 16), 4, 4, 48000, 3)\n'
            'assert frame.decode_frame(f).sequence == 3\n'
            'assert frame.decode_frame(f).payload == b"\\x01\\x00" * 16\n'
            'assert capture.parse_args(["--ip", "10.0.0.2"]).port == 9559\n')
    res = subprocess.run([py27, '-c', code], env=env, stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT)
    assert res.returncode == 0, res.stdout.decode()
    res = subprocess.run([py27, script('naoqiAudio')[1], '--ip', '300.1.1.1'], env=env,
                         capture_output=True)
    assert res.returncode == 2 and b'not a valid IPv4 address' in res.stderr


# ---------------------------------------------------------------- the whole chain

@pytest.mark.parametrize('layout', ['planar', 'interleaved'])
def test_chain_counter_is_sample_exact_in_the_right_fields(procs, master, tmp_path, layout):
    extra = ('--planar',) if layout == 'planar' else ()  # interleaved: the default
    _, _, out, p = chain(procs, master, tmp_path, 'counter', capture_args=extra)
    wait_messages(p['dumper'], 25, 40)
    assert p['capture'].stop(signal.SIGTERM) == 0
    assert 'unsubscribed from ALAudioDevice' in p['capture'].log()
    p['endpoint'].wait_for('SoundProcessingModule unsubscribed', 10)
    blocks, _ = finish_dump(p['dumper'], out)
    starts = counter_starts(blocks)
    assert len(starts) >= 25
    assert set(np.diff(starts)) == {BUFFER}, 'stream not contiguous: %s' % np.diff(starts)
    assert layout in p['publisher'].log()
    # What NAOqi was asked for, as the endpoint saw it (naoqi_driver asks for interleaved).
    assert 'SoundProcessingModule subscribed: channels ALL, %s' % layout in p['endpoint'].log()
    # ~stats is written once a second (audio_bridge/publisher.py STATS_INTERVAL): the last
    # buffers reach the dump before the count that includes them reaches the server
    stats = wait_until(lambda: (lambda s: s if s['published'] >= len(blocks) else None)(get_param(master, STATS)),
                       3 * STATS_INTERVAL, lambda: 'published %s < %d dumped' % (get_param(master, STATS), len(blocks)))
    assert stats['lost_in_gaps'] == 0 and stats['dropped_bad'] == 0


def test_chain_tones_identify_each_field_and_a_dead_microphone(procs, master, tmp_path):
    _, _, out, p = chain(procs, master, tmp_path, 'tones',
                         endpoint_args=('--silent-channel', 'frontLeft'))
    wait_messages(p['dumper'], 15, 40)
    blocks, _ = finish_dump(p['dumper'], out)
    audio = np.concatenate(blocks)
    for c, name in enumerate(CHANNEL_NAMES):
        if name == 'frontLeft':
            assert not audio[:, c].any(), 'silent microphone is not silent'
        else:
            assert abs(dominant_hz(audio[:, c]) - CHANNEL_TONES_HZ[name]) < 5, name


def test_chain_60s_realtime_no_lost_buffer(procs, master, tmp_path):
    _, _, out, p = chain(procs, master, tmp_path, 'counter')
    wait_messages(p['dumper'], 1, 40)
    time.sleep(61.5)    # the 60 s soak
    stats = get_param(master, STATS)
    blocks, recv = finish_dump(p['dumper'], out)
    starts = counter_starts(blocks)
    assert set(np.diff(starts)) == {BUFFER}, 'gap in the stream'
    in_60s = np.count_nonzero(recv < recv[0] + 60.0)
    expected = 60.0 * RATE / BUFFER  # 703.1
    # real time as the microphone check judges it: 48 kHz within its sample_rate_tolerance
    # (5 %; the buffers counted on arrival, which a loaded machine bunches); no buffer lost is
    # the counter's business (contiguous above, lost_in_gaps below)
    assert abs(in_60s - expected) <= ROBOT['microphone'].sample_rate_tolerance * expected, (in_60s, expected)
    assert stats['lost_in_gaps'] == 0 and stats['dropped_bad'] == 0
    assert 'dropped' not in p['capture'].log().replace('0 dropped', '')
    rate = (len(recv) - 1) / (recv[-1] - recv[0])
    intervals = np.diff(recv)
    print('\n60 s run: %d buffers in the first 60 s (expected %.1f), %.3f buffers/s, '
          'arrival interval mean %.1f ms sd %.1f ms max %.1f ms, bridge latency (buffer end '
          '-> publish) mean %.1f ms max %.1f ms in the last second, lost %d'
          % (in_60s, expected, rate, intervals.mean() * 1e3, intervals.std() * 1e3,
             intervals.max() * 1e3, stats['latency_ms_mean'], stats['latency_ms_max'],
             stats['lost_in_gaps']))


def test_publisher_killed_and_restarted_mid_stream(procs, master, tmp_path):
    naoqi_port, ws_port, out, p = chain(procs, master, tmp_path, 'counter')
    wait_messages(p['dumper'], 20, 40)
    before_kill = message_count(p['dumper'])
    # a ~stats snapshot of the publisher covering these buffers (it writes one about every second)
    wait_param(master, STATS, lambda s: s['published'] >= before_kill, 10)
    p['publisher'].stop(signal.SIGKILL)
    stale = get_param(master, STATS)     # what the killed publisher left on the server
    time.sleep(2.0)     # the publisher stays down 2 s: buffers are lost (what is counted)
    publisher2 = procs.publisher(master, ws_port)
    p['capture'].wait_for('websocket connection lost', 20)
    p['capture'].wait_for('websocket connected', 30, count=2)
    n = message_count(p['dumper'])
    wait_messages(p['dumper'], max(n, before_kill) + 15, 40)
    # a snapshot written by the restarted publisher, not the killed one's (also >= 15 published)
    stats = wait_param(master, STATS, lambda s: s['published'] >= 15 and
                       int(s['last_sequence']) > int(stale['last_sequence']), 10)
    blocks, _ = finish_dump(p['dumper'], out)
    starts = counter_starts(blocks)
    jumps = np.nonzero(np.diff(starts) != BUFFER)[0]
    assert len(jumps) == 1, 'expected exactly one gap (the restart): %s' % np.diff(starts)
    gap_at_subscriber = (starts[jumps[0] + 1] - starts[jumps[0]]) // BUFFER - 1
    assert 'continuing sequence accounting' in publisher2.log()
    assert 'lost' in publisher2.log() and stats['connections'] >= 1
    # The restarted publisher counts what never reached it; its reference point (the last
    # ~stats of the killed one) may be up to one second (~12 buffers) old.
    assert 1 <= stats['lost_in_gaps'] <= gap_at_subscriber + 13, (stats, gap_at_subscriber)
    # Buffers the capture side dropped from its full queue never reached any publisher.
    dropped = sum(int(n) for n in re.findall(r'dropped (\d+) buffer\(s\) while the websocket',
                                             p['capture'].log()))
    assert dropped <= stats['lost_in_gaps'], (dropped, stats)
    assert 'Traceback' not in p['capture'].log()


def test_capture_resubscribes_after_naoqi_restart(procs, master, tmp_path):
    naoqi_port, ws_port, out, p = chain(procs, master, tmp_path, 'counter')
    wait_messages(p['dumper'], 10, 40)
    p['endpoint'].stop(signal.SIGKILL)
    p['capture'].wait_for('NAOqi connection lost', 20)
    time.sleep(1.0)    # NAOqi stays down 1 s
    n = message_count(p['dumper'])
    procs.endpoint(naoqi_port, '--pattern', 'counter')
    p['capture'].wait_for('subscribed to ALAudioDevice', 30, count=2)
    wait_messages(p['dumper'], n + 10, 40)
    stats = get_param(master, STATS)
    blocks, _ = finish_dump(p['dumper'], out)
    starts = counter_starts(blocks)
    # Contiguous on both sides of the restart, the new endpoint's buffers after the old ones. Its
    # counter runs from its own start, as a microphone does, subscribed or not (naoqi_endpoint
    # _pump): its first buffer's index is its time until the capture resubscribed, which can by
    # chance continue the old run exactly (seen once: 11 buffers, then 21 from index 22), so the
    # restart is one discontinuity or none.
    assert len(starts) >= n + 10, (len(starts), n)
    assert np.count_nonzero(np.diff(starts) != BUFFER) <= 1, starts
    assert stats['lost_in_gaps'] == 0 and stats['stream_resets'] == 0
    assert 'Traceback' not in p['capture'].log()


def test_hostile_frames_rejected_then_good_traffic_flows(procs, master, tmp_path):
    token = 's3cret-token'
    naoqi_port, ws_port, out, p = chain(procs, master, tmp_path, 'counter', with_capture=False,
                                        publisher_env={'PEPPER_AUDIO_TOKEN': token})
    url = 'ws://127.0.0.1:%d' % ws_port
    for header in ([], [fr.TOKEN_HEADER + ': wrong']):
        with pytest.raises(websocket.WebSocketBadStatusException) as err:
            websocket.create_connection(url, header=header, timeout=5)
        assert err.value.status_code == 401
    ws = websocket.create_connection(url, header=[fr.TOKEN_HEADER + ': ' + token], timeout=5)
    good = good_frame()
    bad = {
        'truncated': good[:100],
        'bad magic': b'EVIL' + good[4:],
        'oversized': fr.HEADER.pack(fr.MAGIC, 1, 1, 4, 16385, RATE, 1, 0, 0, 0,
                                    4 * 16385 * 2) + b'\0' * 64,
        'length mismatch': good + b'\0\0',
        'bad channel count': fr.HEADER.pack(fr.MAGIC, 1, 1, 0, 16, RATE, 1, 0, 0, 0, 0),
        'not 4 channels': good_frame(channels=2),
    }
    for _ in range(20):  # a flood: warnings must stay rate-limited
        for message in bad.values():
            ws.send_binary(message)
    ws.send('a text message')
    ws.close()
    stats = None
    for attempt in range(3):   # a handshake can time out on a loaded machine: try again
        try:
            huge = websocket.create_connection(url, header=[fr.TOKEN_HEADER + ': ' + token], timeout=5)
            huge.send_binary(b'PAU1' + b'\0' * (fr.MAX_FRAME_BYTES + 10))  # over the ws limit
            with pytest.raises(websocket.WebSocketException):
                for _ in range(10):
                    huge.recv()  # the server closes this connection (1009)
        except (OSError, websocket.WebSocketException):
            pass  # closed while we were still sending: just as good
        try:
            stats = wait_param(master, STATS, lambda s: s['bad_causes'].get('oversized', 0) >= 21, 10)
            break
        except AssertionError:
            if attempt == 2:
                raise
    # The real capture (token from the environment, as the launch files pass it) now streams.
    p['capture'] = procs.capture(naoqi_port, ws_port, env={'PEPPER_AUDIO_TOKEN': token})
    wait_messages(p['dumper'], 12, 40)
    blocks, _ = finish_dump(p['dumper'], out)
    starts = counter_starts(blocks)
    assert set(np.diff(starts)) == {BUFFER}, 'good traffic was disturbed'
    causes = stats['bad_causes']
    for cause in bad:
        assert causes.get(cause, 0) >= 20, (cause, causes)
    assert causes['no token'] == 1 and causes['wrong token'] == 1
    assert causes['text message'] == 1
    assert stats['rejected_connections'] == 2 and stats['lost_in_gaps'] == 0
    log = p['publisher'].log()
    assert p['publisher'].alive() and 'Traceback' not in log
    assert len([x for x in log.splitlines() if 'bad magic' in x]) <= 2, 'warnings not limited'
    assert token not in log + p['capture'].log()


def test_second_capture_is_refused_never_mixed(procs, master, tmp_path):
    """Issue 8/9: a second capture process, with the same NAOqi module name (refused by NAOqi:
    reported with the holder and the fix) or another one (refused by the publisher: 409)."""
    naoqi_port, ws_port, out, p = chain(procs, master, tmp_path, 'counter')
    wait_messages(p['dumper'], 5, 40)
    same = procs.capture(naoqi_port, ws_port, name='capture-same')
    text = same.wait_for('already registered', 20)
    assert 'SoundProcessingModule' in text and '--module-name' in text
    assert 'held by process %d' % p['capture'].proc.pid in text, text
    other = procs.capture(naoqi_port, ws_port, '--module-name', 'SecondCapture',
                          name='capture-other')
    other.wait_for('subscribed to ALAudioDevice', 30)
    other.wait_for('refuses this capture: HTTP 409', 20)
    n = message_count(p['dumper'])
    wait_messages(p['dumper'], n + 15, 40)
    assert same.log().count('already registered') == 1, 'the report repeats:\n' + same.log()
    stats = get_param(master, STATS)
    blocks, _ = finish_dump(p['dumper'], out)
    starts = counter_starts(blocks)
    # Both captures get the same samples from NAOqi: any frame of the second one in the topic
    # would repeat a block (difference 0) or go back.
    assert set(np.diff(starts)) == {BUFFER}, 'streams were mixed: %s' % np.diff(starts)
    assert stats['bad_causes'].get('second capture', 0) >= 1, stats
    assert stats['rejected_connections'] >= 1 and stats['stream_resets'] == 0
    log = p['publisher'].log()
    assert 'refused a second capture connection' in log and 'Fix:' in log
    assert len([x for x in log.splitlines() if 'refused a second' in x]) <= 3


def raw_publisher_frames(stream_id, first, n, planar=False, pattern='counter', declared=None):
    """n good 4 x BUFFER frames of one stream from AudioSource; ``declared`` may lie about the
    layout (default: the truth)."""
    src = AudioSource(pattern=pattern)
    frames = []
    for seq in range(first, first + n):
        block = src.read(BUFFER)
        data = (np.ascontiguousarray(block.T) if planar else block).astype('<i2').tobytes()
        frames.append(fr.encode_frame(data, 4, BUFFER, RATE, seq, 0, 0,
                                      planar=planar if declared is None else declared,
                                      stream_id=stream_id))
    return frames


def test_stats_keep_updating_after_a_huge_sequence_number(procs, master, tmp_path):
    """One frame with the stream's own id and sequence 10**12 once stopped ~stats for good
    (XML-RPC ints are 32-bit). It is dropped as implausible; the stream goes on, no loss."""
    pub = procs.publisher(master, 0)
    ws = websocket.create_connection('ws://127.0.0.1:%d' % pub.port, timeout=5)
    frames = raw_publisher_frames(0xABCDEF01, 0, 10)
    for f in frames[:5]:
        ws.send_binary(f)
    wait_param(master, STATS, lambda s: s['published'] == 5, 10)
    forged = fr.decode_frame(frames[5])
    ws.send_binary(fr.encode_frame(forged.payload, 4, BUFFER, RATE, 10 ** 12, 0, 0,
                                   planar=False, stream_id=0xABCDEF01))
    for f in frames[5:]:
        ws.send_binary(f)
    stats = wait_param(master, STATS, lambda s: s['received'] == 11, 10)
    assert stats['published'] == 10 and stats['last_sequence'] == '9', stats
    assert stats['lost_in_gaps'] == 0 and stats['bad_causes'] == {'implausible sequence': 1}
    # A new stream whose first sequence is beyond 2**31 is accounted too, as a string.
    for f in raw_publisher_frames(0x01, 10 ** 12, 3):
        ws.send_binary(f)
    stats = wait_param(master, STATS, lambda s: s['received'] == 14, 10)
    assert stats['last_sequence'] == str(10 ** 12 + 2) and stats['stream_resets'] == 1
    ws.close()
    assert 'implausible' in pub.log() and 'could not update ~stats' not in pub.log()


def test_non_ascii_token_gets_401_counted_and_logged(procs, master, tmp_path):
    token = 's\u00e9cret-\u4f60\u597d'
    pub = procs.publisher(master, 0, env={'PEPPER_AUDIO_TOKEN': token})

    def handshake(value):
        with socket.create_connection(('127.0.0.1', pub.port), timeout=5) as s:
            s.sendall(b'GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\n'
                      b'Connection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n'
                      b'Sec-WebSocket-Version: 13\r\n' + fr.TOKEN_HEADER.encode() + b': '
                      + value + b'\r\n\r\n')
            return s.recv(200).split(b'\r\n')[0]
    assert b' 401 ' in handshake('wr\u00f6ng-\u00e9'.encode('utf-8'))
    assert b' 401 ' in handshake(b'\xff\xfe latin junk')
    assert b' 101 ' in handshake(token.encode('utf-8'))  # the right UTF-8 token is accepted
    stats = wait_param(master, STATS, lambda s: s['rejected_connections'] == 2, 10)
    assert stats['bad_causes'] == {'wrong token': 2}, stats
    log = pub.wait_for('rejected websocket connection from 127.0.0.1:\\d+: wrong token')
    assert 'Traceback' not in log and token not in log


def test_mislabelled_layout_is_refused_not_mixed(procs, master, tmp_path):
    """A buffer declared interleaved that is planar (and the reverse) is never published; a
    correctly labelled stream of either layout is, with each microphone in its field."""
    pub = procs.publisher(master, 0)
    out = tmp_path / 'dump.npz'
    dumper = procs.dumper(master, out)
    ws = websocket.create_connection('ws://127.0.0.1:%d' % pub.port, timeout=5)
    dumper.wait_for('connected', 30)
    for f in raw_publisher_frames(1, 0, 6, planar=True, pattern='tones', declared=False):
        ws.send_binary(f)
    for f in raw_publisher_frames(2, 0, 6, planar=False, pattern='tones', declared=True):
        ws.send_binary(f)
    for sid, planar in ((3, True), (4, False)):
        for f in raw_publisher_frames(sid, 0, 6, planar=planar, pattern='tones'):
            ws.send_binary(f)
    stats = wait_param(master, STATS, lambda s: s['received'] == 24, 15)
    assert stats['published'] == 12 and stats['bad_causes'] == {'layout mismatch': 12}, stats
    wait_messages(dumper, 12, 20)
    ws.close()
    blocks, _ = finish_dump(dumper, out)
    assert len(blocks) == 12
    for block in blocks:
        for c, name in enumerate(CHANNEL_NAMES):
            assert abs(dominant_hz(block[:, c]) - CHANNEL_TONES_HZ[name]) < 15, name
    log = pub.log()
    assert 'declared interleaved but looks planar' in log
    assert 'declared planar but looks interleaved' in log
    assert 'refused from now on' in log


def test_layout_rule_on_the_emulated_microphones():
    """The rule's margins on every signal the emulator makes, speech included (pure code)."""
    from pepper_interface_tests.audio_bridge.layout import suspect
    for pattern, silent in (('tones', ()), ('counter', ()), ('tones', ('rearRight',))):
        src = AudioSource(pattern=pattern, silent_channels=silent)
        src.say('Hello, this is the Pepper microphone test.')
        wait_until(lambda s=src: s._rendering == 0, 30, 'espeak-ng did not render the sentence')
        for _ in range(30):
            block = src.read(BUFFER)
            inter = block.astype('<i2').tobytes()
            planar = np.ascontiguousarray(block.T).astype('<i2').tobytes()
            assert suspect(False, inter, 4) is None and suspect(True, planar, 4) is None
            assert suspect(True, inter, 4) and suspect(False, planar, 4)
    assert suspect(False, b'\0' * 8 * BUFFER, 4) is None  # silence decides nothing


def test_usage_errors_and_waiting_for_peers(master, tmp_path):
    for args in (['--ip', '300.1.1.1'], ['--ip', 'no such host.invalid'], ['--port', '0'],
                 ['--ws', 'http://127.0.0.1:1'], ['--queue-seconds', '0']):
        res = subprocess.run(script('naoqiAudio') + args, capture_output=True,
                             timeout=60)
        err = res.stderr.decode()
        assert res.returncode == 2, (args, err)
        assert 'Traceback' not in err and len(err.strip().splitlines()) == 1, err
    # Nobody listening on either side: it waits with backoff, quietly, and stops cleanly.
    procs = Procs(tmp_path)
    try:
        cap = procs.capture(free_port(), free_port())
        cap.wait_for('NAOqi not reachable', 20)
        time.sleep(3)    # 3 s of retries, which must not flood the log
        assert cap.alive()
        assert cap.log().count('not reachable') == 1, 'retry messages flood:\n' + cap.log()
        assert cap.stop(signal.SIGTERM, timeout=15) == 0
        assert 'Traceback' not in cap.log()
        for args in (['--port', '70000'], ['--port', 'x']):
            res = subprocess.run(script('naoqiAudioPublisher') + args, env=master.env(),
                                 stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=60)
            assert res.returncode == 2, res.stdout.decode()
            assert b'Traceback' not in res.stdout
        port = free_port()
        first = procs.publisher(master, port)
        res = subprocess.run(script('naoqiAudioPublisher') + ['--port', str(port),
                                                              '__name:=second'],
                             env=master.env(), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                             timeout=60)
        assert res.returncode == 1 and b'cannot listen on 127.0.0.1:%d' % port in res.stdout
        assert b'Traceback' not in res.stdout
        assert first.stop(signal.SIGTERM) == 0
    finally:
        procs.stop_all()


def test_a_taken_port_stops_the_bridge_before_it_advertises_its_topic(tmp_path):
    """Issue 24: the port held by another program's real socket. The bridge must say "cannot
    listen on 127.0.0.1:N" and never have advertised /naoqi_driver/audio (a launch watcher
    takes that topic for "the bridge is up"); checked in the master's own record of every
    registration (master.log: "+PUB [topic] node uri"), so even a moment's advertising counts."""
    from pepper_interface_tests.rosmaster import PrivateMaster
    ros_home = tmp_path / 'ros_home'
    with PrivateMaster('/test', ros_home=str(ros_home)) as master:
        port = free_port()
        with socket.socket() as holder:
            holder.bind(('127.0.0.1', port))
            holder.listen(1)
            res = subprocess.run(script('naoqiAudioPublisher') + ['--port', str(port)],
                                 env=master.env(), stdout=subprocess.PIPE,
                                 stderr=subprocess.STDOUT, timeout=60)
        out = res.stdout.decode('utf-8', 'replace')
        assert res.returncode == 1 and 'cannot listen on 127.0.0.1:%d' % port in out, out
        assert 'Traceback' not in out, out
        with open(str(ros_home / 'log' / 'latest' / 'master.log')) as f:
            registrations = [ln for ln in f if '+PUB [' in ln]
    assert any('/naoqiAudioPublisher' in ln for ln in registrations), registrations  # log read
    assert not [ln for ln in registrations if '[/naoqi_driver/audio]' in ln], registrations


def test_launch_keeps_the_token_out_of_ps_params_and_logs(procs, master, tmp_path):
    """pepperEmulator.launch with the token in a file named by $PEPPER_AUDIO_TOKEN_FILE: the
    bridge works with it, and it is in no command line, no parameter and no log (roslaunch
    writes every process's environment into its log, so the token itself must not be in one)."""
    from pepper_interface_tests.rosmaster import free_ports
    token = 'tok-%d-secret' % os.getpid()
    token_file = tmp_path / 'token'
    token_file.write_text(token + '\n')
    token_file.chmod(0o600)
    ros_home = tmp_path / 'ros_home'
    naoqi_port, ws_port = free_ports(2)
    log_path = tmp_path / 'roslaunch.log'
    env = master.env(PEPPER_AUDIO_TOKEN_FILE=str(token_file), ROS_HOME=str(ros_home))
    with open(str(log_path), 'wb') as log:
        launch = subprocess.Popen(
            ['roslaunch', os.path.join(ROOT, 'launch', 'pepperEmulator.launch'),
             'naoqi_port:=%d' % naoqi_port, 'ws_port:=%d' % ws_port], env=env, stdout=log,
            stderr=subprocess.STDOUT, start_new_session=True)
    try:
        dumper = procs.dumper(master, tmp_path / 'dump.npz')
        wait_messages(dumper, 5, 90)
        with pytest.raises(websocket.WebSocketBadStatusException) as err:
            websocket.create_connection('ws://127.0.0.1:%d' % ws_port, timeout=5)
        assert err.value.status_code == 401  # the publisher did get the token
        mine = [launch.pid] + [c.pid for c in psutil.Process(launch.pid).children(recursive=True)]
        assert len(mine) >= 4, mine  # roslaunch, endpoint, emulator, publisher, capture
        for pid in mine:
            try:
                cmdline = ' '.join(psutil.Process(pid).cmdline())
            except psutil.Error:
                continue
            assert token not in cmdline, cmdline
        params = xmlrpc_get(master, '/')
        assert token not in repr(params)
        assert '/naoqiAudioPublisher/port' in repr(params) or 'naoqiAudioPublisher' in repr(params)
    finally:
        kill_group(launch, signal.SIGINT, 30)
    texts = [log_path.read_text()]
    for root, _, files in os.walk(str(ros_home)):
        for name in files:
            with open(os.path.join(root, name), 'rb') as f:
                texts.append(f.read().decode('utf-8', 'replace'))
    assert len(texts) > 1 and str(token_file) in ''.join(texts)  # the logs were read
    assert not [t for t in texts if token in t], 'token found in a log'


def xmlrpc_get(master, name):
    import xmlrpc.client
    code, _, value = xmlrpc.client.ServerProxy(master.uri).getParam('/audio_test', name)
    return value if code == 1 else None


def test_token_file_errors_are_one_line(tmp_path):
    missing = tmp_path / 'nope'
    empty = tmp_path / 'empty'
    empty.write_text('\n')
    for path, words in ((missing, 'cannot read the token file'), (empty, 'is empty')):
        res = subprocess.run(script('naoqiAudio') + ['--token-file', str(path)],
                             capture_output=True, timeout=60)
        err = res.stderr.decode()
        assert res.returncode == 2 and words in err and str(path) in err, err
        assert len(err.strip().splitlines()) == 1 and 'Traceback' not in err
