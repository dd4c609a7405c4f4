"""Recordings (recording.py), playback (playback.py), the live view (viewer.py), and recordings
that survive Ctrl-C in a real sensorTest run."""
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
import soundfile

from media_tools import Publishers, load_results, pattern, topics_file, video_info
from pepper_interface_tests.media import playback, recording
from pepper_interface_tests.media.recording import VideoRecorder, WavWriter
from pepper_interface_tests.media.viewer import Viewer
from rosmaster import script, spawn, wait_until


def record(path, frames, rate, **kw):
    rec = VideoRecorder(str(path), **kw)
    for i, f in enumerate(frames):
        rec.add(f, i / rate)
    return rec


def ffprobe_stream(path, entries='codec_name,pix_fmt'):
    out = subprocess.run(['ffprobe', '-v', 'error', '-select_streams', 'v:0', '-show_entries',
                          'stream=' + entries, '-of', 'csv=p=0', str(path)], capture_output=True, text=True)
    return out.stdout.strip()


def test_rate_is_measured_every_frame_is_written_and_the_file_appears_on_close(tmp_path):
    path = tmp_path / 'frontCameraOutput.mp4'
    rec = record(path, [pattern(160, 120, i) for i in range(36)], rate=12.0)
    wait_until(lambda: os.path.exists(rec.tmp_path), 20, 'no %s while recording' % rec.tmp_path)
    assert not path.exists()                       # written under a temporary name until close
    summary = rec.close()
    frames, w, h, fps = video_info(str(path))
    assert (frames, w, h) == (36, 160, 120)
    assert abs(fps - 12.0) < 0.05 and summary['fps'] == 12.0
    assert summary['frames_written'] == 36 and summary['frames_dropped'] == 0
    # browser-playable H.264 in one pass, straight from the raw frames
    assert ffprobe_stream(path) == 'h264,yuv420p' and summary['codec'] == 'avc1'
    assert not [p for p in os.listdir(tmp_path) if p.startswith('.')]


@pytest.mark.parametrize('pix_fmt,order', [('rgb24', (2, 1, 0)), ('bgr24', (0, 1, 2)), ('rgba', (2, 1, 0, 3)),
                                           ('bgra', (0, 1, 2, 3))])
def test_ffmpeg_converts_the_raw_colour_order(tmp_path, pix_fmt, order):
    import cv2
    bgr = np.zeros((96, 128, 3), np.uint8)
    bgr[:, :64] = (255, 0, 0)                      # blue | red, in OpenCV's BGR
    bgr[:, 64:] = (0, 0, 255)
    if len(order) == 4:
        bgr = np.dstack([bgr, np.zeros((96, 128), np.uint8)])
    raw = np.ascontiguousarray(bgr[:, :, list(order)])
    rec = VideoRecorder(str(tmp_path / 'c.mp4'))
    for i in range(6):
        rec.add(raw, i / 10.0, pix_fmt)
    assert rec.close()['frames_written'] == 6
    ok, frame = cv2.VideoCapture(str(tmp_path / 'c.mp4')).read()
    assert ok
    left, right = frame[48, 20].astype(int), frame[48, 100].astype(int)
    assert left[0] > 200 and left[2] < 60 and right[2] > 200 and right[0] < 60, (left, right)
    assert recording.save_jpeg(str(tmp_path / 'first.jpg'), *rec.first_frame)
    jpeg = cv2.imread(str(tmp_path / 'first.jpg'))   # the JPEG's colours are right whatever came in
    assert jpeg[48, 20, 0] > 200 and jpeg[48, 20, 2] < 60 and jpeg[48, 100, 2] > 200 and jpeg[48, 100, 0] < 60


def test_rate_is_corrected_when_the_stream_slows_down(tmp_path):
    path = tmp_path / 'depthCameraOutput.mp4'
    rec = VideoRecorder(str(path))
    times = [i / 30.0 for i in range(31)] + [1.0 + i / 10.0 for i in range(1, 41)]   # 30 Hz, then 10 Hz
    for i, t in enumerate(times):
        rec.add(pattern(96, 64, i), t)
    summary = rec.close()
    overall = (len(times) - 1) / (times[-1] - times[0])
    assert abs(summary['fps'] - overall) < 0.05, summary
    frames, _, _, fps = video_info(str(path))
    assert frames == len(times) and abs(fps - overall) < 0.3, fps
    assert any('frame rate corrected' in n for n in rec.notes)


def test_a_late_first_frame_and_a_start_up_burst_do_not_set_the_rate(tmp_path):
    """Seen in the benchmark: the first frames arrive late and then together; (n - 1) / span
    over the first 16 frames read 32.8 fps for a 30 fps stream and cost a remux pass."""
    path = tmp_path / 'frontCameraOutput.mp4'
    rec = VideoRecorder(str(path), max_fps=40.0)
    times = [0.12, 0.125, 0.13] + [i / 30.0 for i in range(4, 241)]   # frames 0-3 late, 0-2 together
    for i, t in enumerate(times):
        rec.add(pattern(96, 64, i), t)
    summary = rec.close()
    assert abs(rec.fps - 30.0) < 0.3, rec.fps                    # the rate ffmpeg was started with
    assert not any('frame rate corrected' in n for n in rec.notes), rec.notes
    assert summary['frames_written'] == 240 and video_info(str(path))[0] == 240


def test_odd_sizes_are_padded_to_even_for_h264(tmp_path):
    rec = record(tmp_path / 'odd.mp4', [pattern(161, 121, i) for i in range(12)], rate=10.0)
    summary = rec.close()
    assert summary['error'] is None and summary['frames_written'] == 12
    assert video_info(str(tmp_path / 'odd.mp4'))[:3] == (12, 162, 122)


def test_without_ffmpeg_there_is_no_video_and_a_clear_error(tmp_path, monkeypatch):
    monkeypatch.setenv('PATH', str(tmp_path))      # a PATH without ffmpeg
    rec = record(tmp_path / 'frontCameraOutput.mp4', [pattern(64, 48, i) for i in range(10)], rate=10.0)
    summary = rec.close()
    assert summary['error'] == 'ffmpeg not found: no video (install ffmpeg)' and summary['file'] is None
    assert summary['frames_dropped'] == 10 and summary['frames_written'] == 0
    assert not os.listdir(tmp_path)


def test_an_encoder_that_dies_is_reported_and_the_rest_counted(tmp_path):
    rec = VideoRecorder(str(tmp_path / 'bottomCameraOutput.mp4'))
    for i in range(20):
        rec.add(pattern(160, 120, i), i / 10.0)
    wait_until(lambda: rec._proc is not None, 20, 'ffmpeg never started')   # after ~1 s of frames
    os.killpg(rec._proc.pid, signal.SIGKILL)      # a real encoder crash
    wait_until(lambda: rec._proc.poll() is not None, 10, 'the killed encoder still runs')
    for i in range(20, 60):
        rec.add(pattern(160, 120, i), i / 10.0)
    summary = rec.close()
    assert summary['error'] and ('ffmpeg' in summary['error'] or 'video writer failed' in summary['error'])
    assert summary['frames_written'] + summary['frames_dropped'] == summary['frames_received'] == 60
    assert summary['frames_dropped'] > 0 and summary['file'] is None      # an unfinished mp4 is not kept
    assert not os.listdir(tmp_path)


def test_other_sizes_are_resized_grey_is_converted_and_late_frames_ignored(tmp_path):
    path = tmp_path / 'stereoCameraOutput.mp4'
    frames = [pattern(160, 120, i) if i % 3 else pattern(80, 60, i) for i in range(1, 16)]
    frames.append(np.full((120, 160), 90, np.uint8))
    rec = record(path, frames, rate=10.0)
    summary = rec.close()
    assert summary['frames_written'] == 16 and summary['frames_resized'] == 5
    assert video_info(str(path))[:3] == (16, 160, 120)
    size, mtime = path.stat().st_size, path.stat().st_mtime_ns
    rec.add(pattern(160, 120, 99), 9.0)            # a late callback after close
    rec.close()
    assert rec.late == 1 and path.stat().st_size == size and path.stat().st_mtime_ns == mtime


def test_frames_that_do_not_fit_the_queue_are_counted_not_lost_silently(tmp_path):
    path = tmp_path / 'realsenseRGBOutput.mp4'
    rec = VideoRecorder(str(path), queue_bytes=1)
    big = [pattern(640, 480, i) for i in range(6)]
    for i in range(200):                           # far faster than any encoder
        rec.add(big[i % 6], i / 30.0)
    summary = rec.close()
    assert summary['frames_dropped'] > 0
    assert summary['frames_written'] + summary['frames_dropped'] == summary['frames_received'] == 200
    assert video_info(str(path))[0] == summary['frames_written']


def test_wav_writer_is_incremental_and_appears_on_close(tmp_path):
    path = tmp_path / 'microphoneOutput.wav'
    w = WavWriter(str(path), 48000, 4)
    chunk = (np.arange(4096 * 4).reshape(4096, 4) % 2000).astype(np.int16)
    for _ in range(3):
        w.write(chunk)
    assert not path.exists()
    w.close()
    w.close()
    data, rate = soundfile.read(str(path), dtype='int16')
    assert rate == 48000 and data.shape == (3 * 4096, 4) and (data[:4096] == chunk).all()
    assert soundfile.info(str(path)).subtype == 'PCM_16'
    empty = WavWriter(str(tmp_path / 'none.wav'), 48000, 1)
    empty.close()
    assert not (tmp_path / 'none.wav').exists() and not empty.written


# ---------------------------------------------------------------- playback

def _wav(path, seconds=0.3, channels=4):
    t = np.arange(int(48000 * seconds)) / 48000.0
    data = np.stack([(3000 * np.sin(2 * np.pi * (500 * (c + 1)) * t)) for c in range(channels)], axis=1)
    soundfile.write(str(path), data.astype(np.int16), 48000, subtype='PCM_16')


def test_playback_is_off_in_ci_and_keeps_the_file(tmp_path, monkeypatch, capsys):
    path = tmp_path / 'microphoneOutput.wav'
    _wav(path)
    monkeypatch.setenv('CI', 'true')
    proc, line = playback.play_channels(str(path), ('a', 'b', 'c', 'd'), delete_after=True)
    assert proc is None and line == 'playback off (CI): microphoneOutput.wav kept'
    assert capsys.readouterr().out == line + '\n' and path.exists()


def test_playback_without_a_sound_device_says_so_in_one_line(tmp_path, monkeypatch, capsys):
    if playback.sound_device()[0]:
        pytest.skip('this machine has a sound card')
    path = tmp_path / 'microphoneOutput.wav'
    _wav(path)
    monkeypatch.delenv('CI', raising=False)
    monkeypatch.delenv('SENSORTEST_AUDIO_DEVICE', raising=False)
    proc, line = playback.play_channels(str(path), ('a', 'b', 'c', 'd'))
    assert proc is None and line == 'no sound device: playback skipped'
    assert capsys.readouterr().out == 'no sound device: playback skipped\n'


def test_playback_plays_channel_by_channel_in_the_background_and_deletes(tmp_path, monkeypatch):
    if not recording.shutil.which('aplay'):
        pytest.skip('aplay not installed')
    path = tmp_path / 'microphoneOutput.wav'
    _wav(path, seconds=0.5)
    monkeypatch.delenv('CI', raising=False)
    monkeypatch.setenv('SENSORTEST_AUDIO_DEVICE', 'null')     # ALSA's null device: plays nothing audible
    proc, line = playback.play_channels(str(path), ('rearLeft', 'rearRight', 'frontLeft', 'frontRight'),
                                        delete_after=True)
    assert proc is not None, line
    assert line == 'playing microphoneOutput.wav (rearLeft, rearRight, frontLeft, frontRight, 2 s) with aplay, ' \
                   'deleted afterwards'
    assert proc.wait(20) == 0
    assert not path.exists() and not os.listdir(tmp_path)     # recording and mono copy removed


def test_mono_sequence_puts_the_channels_one_after_another(tmp_path):
    path = tmp_path / 'microphoneOutput.wav'
    _wav(path, seconds=0.25)
    mono, seconds = playback._mono_sequence(str(path), ('a', 'b', 'c', 'd'))
    data, rate = soundfile.read(mono, dtype='int16')
    original, _ = soundfile.read(str(path), dtype='int16')
    assert seconds == 1.0 and data.ndim == 1
    assert (data[:12000] == original[:, 0]).all() and (data[36000:] == original[:, 3]).all()


# ---------------------------------------------------------------- live view

def test_viewer_off_prints_one_line_and_returns_none(monkeypatch, capsys):
    assert Viewer.create(False) is None
    assert capsys.readouterr().out == 'live view off: disabled\n'
    monkeypatch.delenv('DISPLAY', raising=False)
    assert Viewer.create(True) is None
    assert capsys.readouterr().out == 'live view off: no DISPLAY\n'


def test_viewer_with_an_unreachable_display_does_not_take_the_process_down(monkeypatch, capsys):
    from pepper_interface_tests.media import viewer
    if viewer.gui_support() is None:
        pytest.skip('headless OpenCV: the display is never tried')
    monkeypatch.setenv('DISPLAY', ':97')          # no X server there
    assert Viewer.create(True) is None
    assert capsys.readouterr().out.startswith('live view off: no window could be opened on DISPLAY=:97')


def test_viewer_keeps_only_the_newest_frame_per_window():
    v = Viewer()
    a, b = np.zeros((4, 4, 3), np.uint8), np.ones((4, 4, 3), np.uint8)
    v.post('frontCamera', a)
    v.post('frontCamera', b)
    v.post('depthCamera', a)
    assert v._latest['frontCamera'] is b and v.posted == {'frontCamera': 2, 'depthCamera': 1}


@pytest.mark.skipif(not recording.shutil.which('Xvfb'), reason='Xvfb not installed')
def test_viewer_shows_windows_on_a_real_display(tmp_path):
    code = ("import numpy as np; from pepper_interface_tests.media.viewer import Viewer; v = Viewer.create(True); "
            "assert v is not None; v.post('frontCamera', np.zeros((48, 64, 3), np.uint8)); v.pump(); "
            "v.post('frontCamera', np.ones((48, 64, 3), np.uint8)); v.pump(); v.pump(); "
            "print(v.shown, v.failed); v.close()")
    read_fd, write_fd = os.pipe()                  # Xvfb picks a free display and tells us which
    xvfb = subprocess.Popen(['Xvfb', '-displayfd', str(write_fd), '-screen', '0', '640x480x24'],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, pass_fds=(write_fd,))
    os.close(write_fd)
    try:
        with os.fdopen(read_fd) as f:
            display = ':' + f.readline().strip()
        out = subprocess.run([sys.executable, '-c', code], env=dict(os.environ, DISPLAY=display),
                             capture_output=True, text=True, timeout=60)
    finally:
        xvfb.terminate()
        xvfb.wait(10)
    assert out.returncode == 0, out.stderr
    assert "{'frontCamera': 2} None" in out.stdout


# ---------------------------------------------------------------- Ctrl-C in a real run

def test_recordings_are_finished_when_sensor_test_is_interrupted(module_master, tmp_path):
    out = os.path.join(str(tmp_path), 'out')
    with Publishers(module_master, tmp_path) as pubs:
        pubs.add('frontCamera', 'camera', '--rate', 10)
        pubs.add('microphone', 'audio', '--fault', 'tone')
        cmd = script('sensorTest') + ['--topics', topics_file(tmp_path), '--sensors', 'frontCamera,microphone',
                                      '--duration', '60', '--wait', '8', '--output-dir', out, '--platform',
                                      'robot', '--mode', 'parallel', '--no-show', '--no-history',
                                      '--no-diagnostics', '--no-report']
        proc = spawn(cmd, module_master.env(), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        deadline = time.time() + 40
        lines = []
        while time.time() < deadline:           # wait until both sensors are listening
            line = proc.stdout.readline()
            lines.append(line)
            if 'start  microphone' in line or not line:
                break
        time.sleep(4.0)    # 4 s of recording before Ctrl-C
        os.killpg(proc.pid, signal.SIGINT)
        rest, _ = proc.communicate(timeout=60)
    assert proc.returncode == 130, ''.join(lines) + rest
    res = load_results(out)
    assert res is not None and res['interrupted'], ''.join(lines) + rest
    front = res['by_name']['frontCamera']
    frames, w, h, fps = video_info(os.path.join(out, 'frontCameraOutput.mp4'))
    assert frames == front['messages'] >= 20 and (w, h) == (320, 240), (frames, front['messages'])
    mic = res['by_name']['microphone']
    info = soundfile.info(os.path.join(out, 'microphoneOutput.wav'))
    assert info.channels == 4 and info.frames == mic['values']['samples_per_channel'] >= 20 * 4096
    assert not [f for f in os.listdir(out) if f.startswith('.')]
