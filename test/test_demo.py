"""The demo as a user runs it (tools/demo.sh: the emulator, the NAOqi endpoint and the audio
bridge from pepperEmulator.launch, then sensorTest --guided --move --yes over every robot
sensor), and what it leaves: every row PASS with no warning,
six playable mp4 files, the WAV of the four microphones and the HTML report with its plots.
The Noetic tier runs it with every node on Python 3.8 and focal's libraries
(tools/platform/noetic-tests.sh), where the audio bridge, the videos and the report once failed.

Real parts: the real demo script, roslaunch, the emulator, libqi, websockets, ffmpeg; the
videos read back by ffprobe, the WAV by soundfile."""
import json
import os
import re
import subprocess

import pytest
import soundfile

from busy_pc import DELIVERY
from pepper_interface_tests.plan import declaration
from pepper_interface_tests.plan.declaration import SENSORS
from report_chromium import chromium_binary, render_page
from rosmaster import ROOT

# the demo's sensors: every sensor of the emulator's stereo head (tools/demo.sh), and their videos
DEMO = declaration.on_head('stereo')
VIDEOS = tuple(SENSORS[n].video for n in DEMO if SENSORS[n].video)


def ffprobe(path):
    """(codec, frames, seconds) of the first video stream, read by decoding the whole file."""
    out = subprocess.run(['ffprobe', '-v', 'error', '-count_frames', '-select_streams', 'v:0',
                          '-show_entries', 'stream=codec_name,nb_read_frames:format=duration',
                          '-of', 'json', path], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, (path, out.stderr)
    info = json.loads(out.stdout)
    stream = info['streams'][0]
    return stream['codec_name'], int(stream['nb_read_frames']), float(info['format']['duration'])


def test_the_demo_passes_every_row_and_leaves_videos_wav_and_report(tmp_path):
    env = dict(os.environ, ROS_HOME=str(tmp_path / 'ros'), COLUMNS='100')
    env.pop('ROS_MASTER_URI', None)
    out_dir = tmp_path / 'out'
    res = subprocess.run([os.path.join(ROOT, 'tools', 'demo.sh'), '--output-dir', str(out_dir)],
                         env=env, stdin=subprocess.DEVNULL, capture_output=True, text=True,
                         timeout=420, start_new_session=True)
    said = res.stdout + res.stderr
    assert res.returncode == 0, said
    results = json.loads((out_dir / 'sensorTestResults.json').read_text())
    rows = {s['name']: s for s in results['sensors']}
    assert sorted(rows) == sorted(DEMO + ('motion',)), sorted(rows)
    assert {n: s['verdict'] for n, s in rows.items() if s['verdict'] != 'PASS'} == {}, said
    # beside the suite's other workers (a busy PC): a warning that names a pause of the delivery
    # is true and allowed; any other warning is not
    assert {n: [w for w in s['warnings'] if not DELIVERY.search(w)]
            for n, s in rows.items() if any(not DELIVERY.search(w) for w in s['warnings'])} == {}, said
    assert '%d passed, 0 failed, 0 skipped' % len(rows) in said, said
    for name in VIDEOS:
        codec, frames, seconds = ffprobe(str(out_dir / name))
        # the demo listens 10 s to cameras of 10-15 Hz: a finished file holds most of it
        assert codec == 'h264' and frames >= 50 and seconds >= 5.0, (name, codec, frames, seconds)
    wav, rate = soundfile.read(str(out_dir / 'microphoneOutput.wav'))
    assert wav.ndim == 2 and wav.shape[1] == 4 and rate == 48000, (wav.shape, rate)
    assert wav.shape[0] >= 5 * rate and abs(wav).max() > 0.01, (wav.shape, abs(wav).max())
    page = (out_dir / 'sensorTestReport.html').read_text()
    plots = re.findall(r'src="data:image/png;base64,([A-Za-z0-9+/=]{200})', page)
    assert len(plots) >= 10, len(plots)
    assert 'Every tested sensor passed.' in page
    report_fits_a_laptop(str(out_dir / 'sensorTestReport.html'), tmp_path)


def report_fits_a_laptop(path, tmp_path):
    """The demo's report in headless Chromium at 1024 and 1280 px does not scroll sideways
    (issue 45: its summary's reasons and the motion check's steps table ran past a 1280-pixel
    window); screenshots kept in build/test-report/ for a person to look at."""
    if chromium_binary() is None:
        pytest.skip('chromium not installed (tools/setup.sh --test installs it): the report\'s width is not checked')
    shots = os.path.join(ROOT, 'build', 'test-report')
    os.makedirs(shots, exist_ok=True)
    for width in (1024, 1280):
        shown = render_page(path, os.path.join(shots, 'demo-%d.png' % width), width=width)
        assert shown.problems() == [], shown.problems()
        state = shown.state
        assert state['inner_width'] == width and state['scroll_width'] <= width, (
            'the demo\'s report is %dpx wide in a %dpx window; past the right edge: %s'
            % (state['scroll_width'], width, state['wide']))
