"""Microphone check (sensors/audio.py): channel lengths, sample rate, silent channels by place,
clipping, gaps, the WAV recordings (together / sequential), the LevelMonitor used by the speech
check; and the whole path through sensorTest with a real rospy publisher."""
import json
import os
import re
import subprocess
import sys

import numpy as np
import soundfile

from check_feed import feed
from fake_pepper import MIC_TONES, audio_buffer
from media_tools import HERE, TOPICS, Publishers, dominant_frequency, explain, make_check, sensor_test
from pepper_interface_tests.emulator import profiles
from rosmaster import kill_group, spawn

CHANNELS = profiles.MIC_CHANNELS
TONES = tuple(MIC_TONES[c] for c in CHANNELS)      # as media_publisher.py sends with --fault tone


def buffers(n_buffers, n=4096, rate=48000.0, silent=None, amplitude=3000.0, short=None):
    return [audio_buffer(i, n, rate, tones=True, amplitude=amplitude, silent=silent, short=short)
            for i in range(n_buffers)]


def feed_buffers(check, msgs, interval=4096 / 48000.0, start=0.0):
    for i, m in enumerate(msgs):
        check.feed(m, start + i * interval)
    check.close()
    return check


def test_levels_rate_and_the_four_channel_wav(tmp_path):
    c = make_check('microphone', tmp_path)
    c.start()
    c = feed_buffers(c, buffers(12))
    assert c.failure_reasons() == [] and c.warning_reasons() == []
    assert c.result_values().sample_rate_hz == 48000.0
    assert c.result_values().samples_per_channel == 12 * 4096
    for name in CHANNELS:   # a sine of amplitude 3000: RMS -23.8 dBFS, peak -20.8 dBFS
        assert abs(c.result_values().channels[name].rms_dbfs - (-23.78)) < 0.05
        assert abs(c.result_values().channels[name].peak_dbfs - (-20.77)) < 0.05
    data, rate = soundfile.read(os.path.join(str(tmp_path), 'out', 'microphoneOutput.wav'), dtype='int16')
    info = soundfile.info(os.path.join(str(tmp_path), 'out', 'microphoneOutput.wav'))
    assert (info.channels, info.samplerate, info.subtype) == (4, 48000, 'PCM_16')
    assert data.shape == (12 * 4096, 4)
    for i in range(4):
        assert abs(dominant_frequency(data[:, i], rate) - TONES[i]) < 5
    assert c.artifacts['audio'] == 'microphoneOutput.wav'


def test_a_silent_channel_fails_by_its_place(tmp_path):
    c = feed_buffers(make_check('microphone', tmp_path, record=False), buffers(6, silent='frontLeft'))
    assert c.failure_reasons() == ['microphone frontLeft is silent: all samples are zero']
    levels = [n for n in c.notes if n.startswith('Levels')]
    assert levels and 'frontLeft - / -' in levels[0] and 'None' not in ' '.join(c.notes), c.notes
    c = feed_buffers(make_check('microphone', tmp_path, record=False), buffers(6, amplitude=5))
    assert len(c.failure_reasons()) == 4
    # amplitude 5 truncated to int16 gives about -81 dBFS; the exact tenth depends on the last bit of
    # np.sin, which differs between CPUs (numpy's SIMD sin), so the level is read, not spelled
    silent = [re.match(r'microphone (\w+) is silent: RMS (-\d+\.\d) dBFS below silence_dbfs -70$', r)
              for r in c.failure_reasons()]
    assert all(silent) and [m.group(1) for m in silent] == list(CHANNELS), c.failure_reasons()
    assert all(-82.0 < float(m.group(2)) < -79.0 for m in silent), c.failure_reasons()


def test_sample_rate_outside_the_tolerance_fails(tmp_path):
    slow = 4096 / 44100.0        # buffers of 4096 arriving at the pace of 44.1 kHz
    c = feed_buffers(make_check('microphone', tmp_path, record=False), buffers(10), interval=slow)
    assert c.failure_reasons() == ['sample rate 44100 Hz, expected 48000 Hz +- 5%']
    c = feed_buffers(make_check('microphone', tmp_path, record=False), buffers(10), interval=4096 / 46000.0)
    assert c.failure_reasons() == []     # 4 % off: within the tolerance


def test_unequal_channel_lengths_are_counted(tmp_path):
    msgs = buffers(4) + buffers(2, short='frontRight')
    c = feed_buffers(make_check('microphone', tmp_path, record=False), msgs)
    assert 'channel arrays of different lengths in 2 of 6 messages (e.g. rearLeft=4096 rearRight=4096 ' \
           'frontLeft=4096 frontRight=4095)' in c.failure_reasons()


def test_clipping_and_gaps_are_reported(tmp_path):
    c = make_check('microphone', tmp_path, record=False)
    msgs = buffers(8, amplitude=40000.0)     # beyond full scale: clipped
    for i, m in enumerate(msgs):
        c.feed(m, i * 0.0853 + (1.0 if i >= 4 else 0.0))     # one 1 s pause
    c.close()
    warnings = ' | '.join(c.warning_reasons())
    assert 'microphone rearLeft clips in ' in warnings and '(max_clipping_share 1%)' in warnings
    assert '1 gap in the audio stream (pause > 3 buffer periods), longest 1.09 s' in c.warning_reasons()
    assert c.result_values().channels['rearLeft'].clipping_share > 0.01


def test_sequential_mode_records_each_microphone_in_turn(tmp_path):
    c = make_check('microphone', tmp_path, mic_mode='sequential')
    assert c.window(1.0) == 4.0
    c.start()
    c = feed_buffers(c, buffers(47))           # 4.01 s of audio, 1 s per microphone
    out = os.path.join(str(tmp_path), 'out')
    for i, name in enumerate(CHANNELS):
        data, rate = soundfile.read(os.path.join(out, 'microphoneOutput_%s.wav' % name), dtype='int16')
        assert data.ndim == 1 and 0.9 <= len(data) / rate <= 1.1
        assert abs(dominant_frequency(data, rate) - TONES[i]) < 5, name     # that microphone's signal
    whole = soundfile.info(os.path.join(out, 'microphoneOutput.wav'))
    assert whole.channels == 1 and abs(whole.duration - 47 * 4096 / 48000.0) < 0.01
    assert c.artifacts['audio_frontRight'] == 'microphoneOutput_frontRight.wav'


def test_level_monitor_compares_with_the_baseline():
    from pepper_interface_tests.sensors.audio import LevelMonitor
    m = LevelMonitor('/unused')
    rng = np.random.default_rng(0)
    for k in range(40):                       # 0.1 s apart; loud from t = 3.0
        amp = 4000.0 if k >= 30 else 100.0
        m.add([rng.normal(0, amp, 4096).astype(np.int16) for _ in range(4)], 100.0 + k * 0.1)
    assert m.has_baseline(now=102.9)
    loud = m.heard(103.0, 104.0)
    assert loud['heard'] and 30 < loud['rise_db'] < 34
    quiet = m.heard(101.5, 102.9)
    assert not quiet['heard'] and quiet['why'].startswith('level rose only')
    assert m.heard(200.0, 201.0) == {'heard': False, 'rise_db': None, 'why': 'no microphone data while speaking'}


def test_a_prompt_spoken_during_the_baseline_does_not_hide_the_sentence():
    """A guided run: the guide's prompt plays through the same loudspeaker over most of the
    baseline (its words with short gaps); the sentence after it is as loud as the prompt and
    is heard over the room's floor, which shows in the gaps and before the prompt. A baseline
    that is only the prompt (no gap, nothing before it) is not a floor, and the same sentence
    is then not heard."""
    from pepper_interface_tests.sensors.audio import LevelMonitor
    rng = np.random.default_rng(1)
    period = 8192 / 48000.0                    # naoqi_driver's stock AudioBuffer
    for gaps in (True, False):
        m = LevelMonitor('/unused')
        for k in range(36):                    # 6.1 s; the sentence from t = 103.1
            t = 100.0 + k * period
            prompt = (101.0 if gaps else 0.0) <= t < 103.1 and not (gaps and k % 4 == 0)
            amp = 1500.0 if prompt or t >= 103.1 else 100.0
            m.add([rng.normal(0, amp, 8192).astype(np.int16) for _ in range(4)], t)
        got = m.heard(103.1, 106.0)
        if gaps:    # 9 of 12 baseline buffers are the prompt: the median is the prompt's level
            assert got['heard'] and got['rise_db'] > 20, got
        else:
            assert not got['heard'], got


def test_the_baseline_waits_for_enough_of_the_room():
    from pepper_interface_tests.sensors.audio import LevelMonitor
    m = LevelMonitor('/unused')
    for k in range(8):                         # 8 buffers over 1.2 s
        m.add([np.full(4096, 100, dtype=np.int16)] * 4, 100.0 + k * 0.17)
    assert not m.has_baseline(now=101.2)
    assert m.has_baseline(now=101.6)


# ---------------------------------------------------------------- real ROS

def test_level_monitor_on_a_real_topic(module_master, tmp_path):
    loud_file = os.path.join(str(tmp_path), 'loud_at')
    pub = spawn([sys.executable, os.path.join(HERE, 'media_publisher.py'), 'audio', TOPICS['microphone'],
                 '--loud-after', '5', '--loud-file', loud_file], module_master.env(), stdout=subprocess.DEVNULL)
    try:
        probe = subprocess.run([sys.executable, os.path.join(HERE, 'media_level_probe.py'), TOPICS['microphone'],
                                '8', loud_file], env=module_master.env(), capture_output=True, text=True, timeout=60)
    finally:
        kill_group(pub)
    assert probe.returncode == 0, probe.stderr
    result = json.loads(probe.stdout.strip().splitlines()[-1])
    assert result['has_baseline'] and result['levels'] > 40
    assert result['loud']['heard'] and result['loud']['rise_db'] > 20, result
    assert not result['quiet']['heard'], result


def test_sensor_test_records_each_tone_in_its_channel(module_master, tmp_path):
    with Publishers(module_master, tmp_path) as pubs:
        pubs.add('microphone', 'audio', '--fault', 'tone', '--count', 40)
        done, res = sensor_test(module_master, tmp_path, ['microphone'], duration=5, extra=['--play-audio'],
                                expect={'microphone': {'max_gap_factor': 40}}, env={'CI': 'true'})
        published = pubs.stop()
    assert res is not None, explain(done, res)
    mic = res['by_name']['microphone']
    assert mic['verdict'] == 'PASS' and done.returncode == 0, explain(done, res)
    assert published['microphone'] == 40 and mic['messages'] == 40
    assert abs(mic['values']['sample_rate_hz'] - 48000) < 2400
    path = os.path.join(str(tmp_path), 'out', 'microphoneOutput.wav')
    info = soundfile.info(path)
    assert (info.channels, info.samplerate, info.subtype, info.frames) == (4, 48000, 'PCM_16', 40 * 4096)
    data, rate = soundfile.read(path, dtype='int16')
    for i, name in enumerate(CHANNELS):
        assert abs(dominant_frequency(data[:, i], rate) - TONES[i]) < 5, name
    assert 'playback off (CI): microphoneOutput.wav kept' in mic['notes']
    assert os.path.exists(path)


def test_sensor_test_fails_a_silent_channel_and_a_wrong_sample_rate(module_master, tmp_path):
    with Publishers(module_master, tmp_path) as pubs:
        pubs.add('microphone', 'audio', '--fault', 'silent:rearRight', '--sample-rate', 44100)
        done, res = sensor_test(module_master, tmp_path, ['microphone'], duration=4)
    assert res is not None, explain(done, res)
    mic = res['by_name']['microphone']
    assert mic['verdict'] == 'FAIL' and done.returncode == 1, explain(done, res)
    assert 'microphone rearRight is silent: all samples are zero' in mic['reasons']
    # the rule: a rate outside 48000 Hz +- 5 % fails, naming the rate measured over the window
    # (on receive times: a 44.1 kHz stream read 43979 Hz on a loaded machine), not its digits
    # (on a busy PC the reason goes on with the hint that a starved publisher may be the cause)
    rates = [float(m.group(1)) for m in (re.match(r'sample rate (\d+) Hz, expected 48000 Hz \+- 5%(;|$)', r)
                                         for r in mic['reasons']) if m]
    assert len(rates) == 1, mic['reasons']
    assert not 48000 * 0.95 <= rates[0] <= 48000 * 1.05, rates      # outside the band: caught
    assert abs(rates[0] - 44100) <= 0.05 * 44100, rates             # the injected rate, within the rule's 5 %
    assert mic['values']['channels']['rearLeft']['rms_dbfs'] > -40


def test_a_start_up_burst_does_not_read_as_a_wrong_sample_rate(tmp_path):
    """A bridge started with the test flushes the buffers NAOqi captured while it connected:
    four buffers at once, then the steady 48 kHz pace (5 s window). The sample rate is 48 kHz;
    a stream whose every buffer comes at the 44.1 kHz pace still fails after the same burst."""
    def burst_then(interval, n=60):
        c = make_check('microphone', tmp_path, record=False)
        times = [0.001 * i for i in range(4)] + [0.003 + interval * (i + 1) for i in range(n - 4)]
        for m, t in zip(buffers(n), times):
            c.feed(m, t)
        c.close()
        return c
    healthy = burst_then(4096 / 48000.0)
    assert healthy.failure_reasons() == [], healthy.failure_reasons()
    assert healthy.result_values().sample_rate_hz == 48000.0
    slow = burst_then(4096 / 44100.0)
    assert slow.failure_reasons() == ['sample rate 44100 Hz, expected 48000 Hz +- 5%']


def custom(i, n=4096, dead=None, dead_from=None):
    """Tones of 500, 800, 1100 and 1400 Hz with a little noise (no two buffers alike); `dead`
    all zeros from buffer `dead_from` on."""
    rng = np.random.default_rng(i)
    tt = (np.arange(n) + i * n) / 48000.0
    return audio_buffer(i, n, channels=[(2000 * np.sin(2 * np.pi * (500 + 300 * k) * tt) + rng.normal(0, 50, n))
                                        .astype(np.int16) for k in range(4)],
                        silent=dead if dead_from is not None and i >= dead_from else None)


def test_microphone_buffers_that_repeat_fail(tmp_path):
    msgs = [custom(i) for i in range(5)] + [custom(5)] * 10
    c = feed(make_check('microphone', tmp_path, record=False), msgs, rate=48000 / 4096.0)
    assert any(r.startswith('microphone stream stuck: 10 identical buffers in a row from t = ')
               and r.endswith('to the end of the window (stuck_buffers 3)') for r in c.failure_reasons()), \
        c.failure_reasons()
    c = feed(make_check('microphone', tmp_path, record=False), [custom(i) for i in range(15)],
             rate=48000 / 4096.0)
    assert c.failure_reasons() == []


def test_a_microphone_channel_that_dies_halfway_fails_by_name_and_time(tmp_path):
    msgs = [custom(i, dead='frontLeft', dead_from=12) for i in range(30)]
    c = feed(make_check('microphone', tmp_path, record=False), msgs, rate=48000 / 4096.0)
    hits = [r for r in c.failure_reasons() if r.startswith('microphone frontLeft went silent from t = 1.07 s '
                                                           'to the end of the window (18 buffers')]
    assert hits, c.failure_reasons()
    assert not any('rearLeft' in r or 'frontRight' in r for r in c.failure_reasons())
