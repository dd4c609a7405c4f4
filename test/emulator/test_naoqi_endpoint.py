"""The NAOqi endpoint and its AudioSource, through the real libqi service directory.

A client (test/nodes/audio_qi_probe.py) registers real qi services, subscribes them to ALAudioDevice
and records what arrives in processRemote.
"""
import os
import signal
import socket
import subprocess
import sys
import time

import numpy as np
import pytest

from audio_chain import Procs
from pepper_interface_tests.emulator.audio_source import (
    CHANNEL_NAMES,
    CHANNEL_TONES_HZ,
    AudioSource,
    expected_counter,
    find_counter_start,
)
from rosmaster import NODES, script, wait_until

HERE = NODES   # the node scripts' folder (test/nodes/)
PERIOD = 4096 / 48000.0


def dominant_hz(x, rate):
    x = np.asarray(x, dtype=np.float64)
    spectrum = np.abs(np.fft.rfft((x - x.mean()) * np.hanning(len(x))))
    return np.fft.rfftfreq(len(x), 1.0 / rate)[np.argmax(spectrum)]


def rms(x):
    return float(np.sqrt(np.mean(np.asarray(x, dtype=np.float64) ** 2)))


@pytest.fixture
def procs(tmp_path):
    p = Procs(tmp_path)
    yield p
    p.stop_all()


def run_probe(port, out, seconds, modules, *extra):
    cmd = [sys.executable, os.path.join(HERE, 'audio_qi_probe.py'), '--port', str(port),
           '--out', str(out), '--seconds', str(seconds)]
    for m in modules:
        cmd += ['--module', m]
    res = subprocess.run(cmd + list(extra), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         timeout=seconds + 60)
    assert res.returncode == 0, res.stdout.decode()
    return np.load(str(out))


def buffers(data, name):
    """[(nch, nsamp, ts_seconds, recv_time, int16 array as received)] for one module."""
    meta, raw = data[name + '_meta'], data[name + '_data'].tobytes()
    out, pos = [], 0
    for nch, nsamp, sec, usec, recv in meta:
        size = int(nch) * int(nsamp) * 2
        out.append((int(nch), int(nsamp), sec + usec / 1e6, recv,
                    np.frombuffer(raw[pos:pos + size], dtype='<i2')))
        pos += size
    assert pos == len(raw)
    return out


# ---------------------------------------------------------------- AudioSource, in process

def test_audio_source_counter_is_exact_and_locatable():
    src = AudioSource(pattern='counter')
    a, b, c = src.read(1000), src.read(4096), src.read(7)
    assert a.shape == (1000, 4) and a.dtype == np.int16
    assert np.array_equal(np.concatenate([a, b, c]), expected_counter(0, 5103))
    assert find_counter_start(b) == 1000
    assert find_counter_start(b[:, 3], channel_index=3) == 1000
    far = expected_counter(987654321, 64)  # far beyond any 16-bit period
    assert find_counter_start(far) == 987654321
    broken = b.copy()
    broken[100, 2] += 1
    with pytest.raises(ValueError):
        find_counter_start(broken)
    swapped = b[:, [1, 0, 2, 3]]
    with pytest.raises(ValueError):
        find_counter_start(swapped)


def test_audio_source_tones_silence_and_speech():
    src = AudioSource(pattern='tones', silent_channels=('frontLeft',))
    x = src.read(48000)
    for c, name in enumerate(CHANNEL_NAMES):
        if name == 'frontLeft':
            assert not x[:, c].any()
        else:
            assert abs(dominant_hz(x[:, c], 48000) - CHANNEL_TONES_HZ[name]) < 5
            assert 20 * np.log10(np.abs(x[:, c]).max() / 32767.0) == pytest.approx(-30, abs=2)
    base = rms(x[:, 0])
    assert not src.speaking
    src.say('Hello, this is the Pepper microphone test.')
    assert src.speaking
    deadline = time.time() + 20
    loud = []
    while src.speaking and time.time() < deadline:
        block = src.read(4096)
        loud.append(block)
        assert not block[:, 2].any()  # a dead microphone stays dead while speech plays
        time.sleep(0.005)
    assert not src.speaking, 'speech never finished'
    speech = np.concatenate(loud)
    peak_db = 20 * np.log10(np.abs(speech[:, 0].astype(float)).max() / 32767.0)
    assert peak_db == pytest.approx(-10, abs=2.5)
    loudest = max(rms(speech[i:i + 4096, 0]) for i in range(0, len(speech), 4096))
    assert loudest > 3 * base


def test_audio_source_beeps_without_espeak(monkeypatch, tmp_path):
    monkeypatch.setenv('PATH', str(tmp_path))  # a real PATH where espeak-ng does not exist
    src = AudioSource(pattern='tones', silent_channels=('rearLeft', 'rearRight', 'frontLeft'))
    src.say('anything')
    wait_until(lambda: src.speaking and not src._rendering, 10, 'the beep was never rendered', every=0.01)
    beeps = src.read(int(0.65 * 48000))[:, 3]
    assert abs(dominant_hz(beeps, 48000) - 1000) < 10
    env = np.abs(beeps.astype(float)).reshape(-1, 480).max(axis=1)  # 10 ms windows
    loud = env > 5000
    assert np.count_nonzero(np.diff(loud.astype(int)) == 1) + int(loud[0]) == 3  # 3 beeps


def test_audio_source_rejects_unknown_names():
    with pytest.raises(ValueError, match='unknown channel'):
        AudioSource(silent_channels=('middle',))
    with pytest.raises(ValueError, match='pattern'):
        AudioSource(pattern='noise')


# ---------------------------------------------------------------- endpoint over libqi

def test_endpoint_layouts_several_subscribers_and_pace(procs, tmp_path):
    endpoint = procs.endpoint(0, '--pattern', 'counter')  # port 0: it binds a free one
    port = endpoint.port
    assert port > 0
    data = run_probe(port, tmp_path / 'probe.npz', 3.0,
                     ['Planar:0:1', 'Inter:0:0'], '--check-unsubscribe')
    planar, inter = buffers(data, 'Planar'), buffers(data, 'Inter')
    assert len(planar) >= 20 and len(inter) >= 20
    starts = {}
    for name, bufs, is_planar in (('Planar', planar, True), ('Inter', inter, False)):
        for nch, nsamp, ts, _, x in bufs:
            assert (nch, nsamp, x.size) == (4, 4096, 4 * 4096)
            block = x.reshape(4, 4096).T if is_planar else x.reshape(4096, 4)
            starts.setdefault(name, []).append((round(ts, 4), find_counter_start(block)))
        st = [s for _, s in starts[name]]
        assert set(np.diff(st)) == {4096}, name + ' stream not contiguous'
        ts = np.array([t for _, _, t, _, _ in bufs])
        assert np.allclose(np.diff(ts), PERIOD, atol=2e-6), 'timestamps not 4096/48000 apart'
        assert data[name + '_after_unsub'] == 0, name + ' got buffers after unsubscribe'
    # Both subscribers got the same samples for the same timestamp.
    common = set(starts['Planar']) & set(starts['Inter'])
    assert len(common) >= 15
    # Real-time pace measured on arrival (generous margins: the machine is shared).
    recv = np.array([b[3] for b in planar])
    rate = (len(recv) - 1) / (recv[-1] - recv[0])
    assert 9.0 < rate < 14.5, 'buffers per second %.2f, expected ~11.72' % rate
    assert endpoint.stop(signal.SIGTERM) == 0


def test_endpoint_tts_raises_level_silent_channel_and_16k(procs, tmp_path):
    endpoint = procs.endpoint(0, '--pattern', 'tones', '--silent-channel', 'rearRight')
    port = endpoint.port
    data = run_probe(port, tmp_path / 'probe.npz', 5.0, ['All:0:1', 'Left16k:1:1'],
                     '--say-at', '1.2', '--say', 'Hello, this is the Pepper microphone test.')
    say_time = float(data['say_time'])
    assert say_time > 0
    bufs = buffers(data, 'All')
    blocks = [(ts, x.reshape(4, 4096)) for _, _, ts, _, x in bufs]
    before = np.concatenate([b for ts, b in blocks if ts + PERIOD < say_time], axis=1)
    after = np.concatenate([b for ts, b in blocks if ts > say_time], axis=1)
    assert before.shape[1] >= 4096 * 5 and after.shape[1] >= 4096 * 10
    # Silent channel: all zero, speech included.
    assert not np.concatenate([b for _, b in blocks], axis=1)[1].any()
    for c, name in enumerate(CHANNEL_NAMES):
        if name == 'rearRight':
            continue
        assert abs(dominant_hz(before[c], 48000) - CHANNEL_TONES_HZ[name]) < 5
        # Speech mixed in: the loudest buffer after say() is far above the tone level.
        loudest = max(rms(after[c, i:i + 4096]) for i in range(0, after.shape[1], 4096))
        assert loudest > 3 * rms(before[c]), '%s: no speech in the stream' % name
    # 16 kHz single channel (LEFT = frontLeft's 900 Hz tone), as NAOqi gives for flags 1..4.
    left = buffers(data, 'Left16k')
    assert len(left) >= 30
    assert all(nch == 1 and nsamp in (1365, 1366) for nch, nsamp, _, _, _ in left)
    mono = np.concatenate([x for _, _, ts, _, x in left if ts + PERIOD < say_time])
    assert abs(dominant_hz(mono, 16000) - 900) < 10
    assert endpoint.stop(signal.SIGINT) == 0
    assert 'Traceback' not in endpoint.log()


def test_endpoint_usage_errors(tmp_path):
    for args in (['--port', '-1'], ['--port', 'x'], ['--silent-channel', 'middle'],
                 ['--host', 'not-an-ip'], ['--pattern', 'noise']):
        res = subprocess.run(script('naoqiEndpoint') + args, capture_output=True,
                             timeout=30)
        assert res.returncode == 2, args
        assert b'Traceback' not in res.stderr
    with socket.socket() as busy:
        busy.bind(('127.0.0.1', 0))
        busy.listen(1)
        port = busy.getsockname()[1]
        res = subprocess.run(script('naoqiEndpoint') + ['--port', str(port)],
                             capture_output=True, timeout=30)
    err = res.stderr.decode()
    assert res.returncode == 1, err
    assert 'cannot listen on tcp://127.0.0.1:%d' % port in err
    assert 'Traceback' not in err
