"""The HTML report (the report package), rendered in real headless Chromium.

* a live run (real roscore, test/nodes/core_publisher.py publishers, one of them faulty, one sensor
  without a publisher, one skipped) writes sensorTestReport.html; Chromium loads it without
  console errors or failed resources, every sensor of the run has its section, and the verdicts
  and reasons shown are the run's;
* a run built in-process from the real camera, depth, microphone and core checks (real mp4,
  JPEG and WAV files) shows its media: the short videos are embedded, the WAV (above the
  embedding limit) is linked, all play in Chromium, frames load, every link resolves;
* a recording above the embedding limit is linked, not embedded, and still plays; an MPEG-4
  part 2 video is linked with a note instead of a player that cannot play it;
* a report that cannot be written is one warning line, never an exception;
* hostile strings (<script>, control characters) are shown as text; no 'None' reaches the page;
  a verdict the report does not know is shown neutrally; the rates figure colours each line by
  the rate's own verdict; a camera without a video says why; a silent microphone channel has
  its own marked level plot.

Screenshots of the pages are kept in build/test-report/ for a person to look at.
"""
import json
import os
import re
import shutil

import pytest

import report_fixtures
from report_chromium import chromium_binary, render_page
from report_helpers import printed_path, sensor_test, start_publishers, stop

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
SHOTS = os.path.join(ROOT, 'build', 'test-report')

pytestmark = pytest.mark.skipif(chromium_binary() is None,
                                reason='chromium not installed (tools/setup.sh --test installs it)')


def keep_screenshot(png, name):
    os.makedirs(SHOTS, exist_ok=True)
    shutil.copy(png, os.path.join(SHOTS, name))


def no_external_resources(text):
    """Nothing the page loads comes from the network."""
    return re.findall(r'(?:src|href)\s*=\s*"(?:https?:)?//[^"]*"|@import|url\(\s*["\']?https?:', text)


NONE = re.compile(r'\bNone\b')


def assert_links_resolve(page, folder):
    """Every relative link and media src of the page names a file next to the report."""
    for ref in page.state['hrefs'] + page.state['mediaSrcs']:
        if ref.startswith(('#', 'data:')):
            continue
        assert os.path.exists(os.path.join(folder, ref)), ref


def section(dom, name):
    m = re.search(r'<section[^>]*id="sensor-%s".*?</section>' % re.escape(name), dom, re.S)
    assert m, 'no section for %s' % name
    return m.group(0)


def test_live_run_report_loads_and_shows_every_sensor(module_master, tmp_path):
    pubs = start_publishers(module_master, [
        ('range', '/naoqi_driver/sonar/back'),
        ('range', '/naoqi_driver/sonar/front', '--fault', 'nan'),     # fails: NaN ranges
        ('laser', '/naoqi_driver/laser'),
        ('joints', '/joint_states', '--rate', '50'),
        ('odometry', '/naoqi_driver/odom', '--rate', '15'),
        ('imu', '/naoqi_driver/imu/base'),
    ])
    out = tmp_path / 'out'
    sensors = ['backSonar', 'frontSonar', 'laser', 'jointState', 'odometry', 'imu',
               'frontCamera',            # no publisher: fails
               'realsenseRGBCamera']     # skipped by --cameras pepper
    try:
        proc = sensor_test(module_master, ['--sensors', ','.join(sensors), '--cameras', 'pepper',
                                           '--mode', 'parallel', '--duration', '3', '--wait', '2',
                                           '--output-dir', str(out)])
    finally:
        stop(pubs)
    assert proc.returncode == 1, proc.stdout + proc.stderr
    path = printed_path(proc.stdout, 'report')
    assert path and os.path.exists(path), proc.stdout
    assert os.path.dirname(path).startswith(str(out / 'runs')), path
    assert os.path.exists(out / 'sensorTestReport.html')           # the latest run's copy
    assert 'HTML report not written' not in proc.stdout
    data = json.loads((out / 'sensorTestResults.json').read_text())
    verdicts = {s['name']: s['verdict'] for s in data['sensors']}
    assert verdicts['frontSonar'] == 'FAIL' and verdicts['frontCamera'] == 'FAIL'
    assert verdicts['backSonar'] == 'PASS' and verdicts['realsenseRGBCamera'] == 'SKIPPED'

    text = open(path, encoding='utf-8').read()
    assert not no_external_resources(text)
    png = str(tmp_path / 'live.png')
    page = render_page(path, png)
    keep_screenshot(png, 'live-run.png')
    assert page.problems() == []
    assert page.state['sections'] == ['sensor-' + s for s in sensors]
    for s in data['sensors']:       # each section shows the run's verdict and reasons
        sec = section(page.dom, s['name'])
        assert 'badge %s' % s['verdict'] in sec
        for reason in s['reasons']:
            assert reason.replace('"', '&quot;') in sec or reason in sec, (s['name'], reason)
    assert 'range is NaN' in section(page.dom, 'frontSonar')
    assert 'Last scan' in section(page.dom, 'laser')
    assert 'Joints (20)' in section(page.dom, 'jointState')
    assert page.state['height'] > 2000
    assert os.path.getsize(png) > 50000
    assert all(i['width'] > 100 for i in page.state['imgs'])      # the plots are real images
    assert not NONE.search(page.state['alltext']), NONE.search(page.state['alltext'])
    assert_links_resolve(page, os.path.dirname(path))


def test_media_sections_play_in_chromium(tmp_path):
    folder = str(tmp_path / 'run')
    run = report_fixtures.media_run(folder)
    by_name = {r.name: r for r in run.sensors}
    assert by_name['frontCamera'].artifacts.get('video'), by_name['frontCamera'].warnings
    assert by_name['microphone'].artifacts.get('audio')
    from pepper_interface_tests.outputs import report
    path = report.write_report(run)
    png = str(tmp_path / 'media.png')
    page = render_page(path, png)
    keep_screenshot(png, 'media-run.png')
    assert page.problems() == []
    assert page.state['sections'] == ['sensor-' + r.name for r in run.sensors]
    media = page.state['media']
    videos = [m for m in media if m['tag'] == 'video']
    audios = [m for m in media if m['tag'] == 'audio']
    assert len(videos) == 3 and len(audios) == 1
    assert all(m['ready'] >= 1 and m['duration'] > 1 for m in media), media   # decodable, not empty
    assert all(v['src'].startswith('data:') for v in videos)     # short clips: inside the page
    assert all(a['src'].startswith('file://') for a in audios)    # the 1 MB WAV: linked, next to it
    assert os.path.getsize(path) < 1.5e6
    assert {v['width'] for v in videos} == {320, 640}
    cam = section(page.dom, 'frontCamera')
    assert cam.count('<img class="frame"') == 2 and 'longest run of identical frames' in cam
    depth = section(page.dom, 'depthCamera')
    assert 'Depth histogram' in depth and 'colour-mapped' in depth and 'depth colour scale' in depth
    mic = section(page.dom, 'microphone')
    for ch in ('rearLeft', 'rearRight', 'frontLeft', 'frontRight'):
        assert ch in mic
    assert 'Waveform' in mic and 'heard by the microphones: <b>yes</b>' in mic
    assert 'heard by the microphones' in section(page.dom, 'speech')
    for name, title in (('odometry', 'Position over time'), ('imu', 'Over time'),
                        ('backSonar', 'Range over time'), ('laser', 'Last scan')):
        assert title in section(page.dom, name)
    assert len(page.state['imgs']) >= 16
    assert 'microphone level over time, one plot per channel' in [i['alt'] for i in page.state['imgs']]
    plots = [i for i in page.state['imgs'] if i['cls'] == 'plot']
    # every figure is shown at its own size in a 1400 px window (not shrunk), so its 11 pt text
    # stays about 15 px high: readable at 100 % zoom
    assert len(plots) >= 10 and all(abs(i['shown'] - i['width']) <= 1 for i in plots), plots
    assert not NONE.search(page.state['alltext']), NONE.search(page.state['alltext'])
    assert_links_resolve(page, folder)


def test_large_recordings_are_linked_and_mp4v_is_not_offered_to_the_browser(tmp_path):
    import cv2
    import numpy as np

    from pepper_interface_tests.outputs import report
    from pepper_interface_tests.results import PASS, RunResult, SensorResult
    from pepper_interface_tests.sensors.values.camera import CameraValues, VideoSummary
    folder = str(tmp_path)
    video, wav = report_fixtures.handmade_media(folder)
    old = os.path.join(folder, 'old.mp4')      # MPEG-4 part 2: browsers cannot decode it
    w = cv2.VideoWriter(old, cv2.VideoWriter_fourcc(*'mp4v'), 10, (64, 48))
    for i in range(10):
        w.write(np.full((48, 64, 3), i * 20, np.uint8))
    w.release()
    cams = [SensorResult(name='frontCamera', title='FRONT CAMERA', topic='/front', msg_type='sensor_msgs/Image',
                         verdict=PASS, messages=20, artifacts={'video': os.path.basename(video)}),
            SensorResult(name='bottomCamera', title='BOTTOM CAMERA', topic='/bottom', msg_type='sensor_msgs/Image',
                         verdict=PASS, messages=10, artifacts={'video': 'old.mp4'},
                         family='camera', values=CameraValues(video=VideoSummary(codec='mp4v'))),
            SensorResult(name='microphone', title='MICROPHONE', topic='/audio',
                         msg_type='pepper_interface_tests/AudioCustomMsg', verdict=PASS, messages=20,
                         artifacts={'audio': os.path.basename(wav)})]
    run = RunResult(platform='robot', mode='sequential', start=1.7e9, end=1.7e9 + 5, output_dir=folder,
                    run_id='linked', sensors=cams)
    path = report.write_report(run, max_embed=1000)
    text = open(path, encoding='utf-8').read()
    assert os.path.getsize(path) < 200000            # nothing big inside
    assert 'src="clip.mp4"' in text and 'src="clip.wav"' in text
    assert 'browsers cannot play this codec' in section(text, 'bottomCamera')
    assert '<video' not in section(text, 'bottomCamera')
    page = render_page(path, None)
    assert page.problems() == []
    assert [m['src'].startswith('file://') for m in page.state['media']] == [True, True]
    assert all(m['ready'] >= 1 for m in page.state['media'])
    assert_links_resolve(page, folder)


def test_report_error_is_one_warning_line(tmp_path):
    import io

    from pepper_interface_tests.outputs.report import HtmlReport
    from pepper_interface_tests.results import RunResult
    run = RunResult(platform='robot', mode='sequential', start=1.7e9, end=1.7e9 + 1)
    out = io.StringIO()
    HtmlReport(str(tmp_path / 'missing' / 'folder'), out=out).run_ended(run)   # cannot be written
    lines = out.getvalue().splitlines()
    assert len(lines) == 1 and lines[0].startswith('sensorTest: warning: HTML report not written'), lines


def test_hostile_strings_are_text_and_no_none_reaches_the_page(tmp_path):
    from pepper_interface_tests.outputs import report
    from report_fixtures import run_of, sensor
    folder = str(tmp_path)
    evil = '<script>alert(1)</script>'
    sonar = sensor('frontSonar', 'FAIL', title=evil, topic='/sonar/<b>x</b>',
                   reasons=['frame_id "%s" is not SonarFront_frame \x1b[31mred\x00' % evil],
                   warnings=['<img src=x onerror=alert(2)>'], notes=['rearRight None / None'],
                   fields=[['Frame id', evil], ['Range', None]], values={'frame_id': evil, 'limits': None},
                   stats={'delay_s': {'mean': None, 'max': None}, 'zero_stamps': None}, stamp_rate_hz=None)
    odd = sensor('laser', 'INTERRUPTED', reasons=['run interrupted before the window ended'])
    run = run_of(folder, [sonar, odd], interrupted=True, interrupt_reason='Ctrl-C <now>')
    path = report.write_report(run)
    page = render_page(path, None)
    assert page.problems() == []               # the <img onerror> did not become an image
    assert page.state['scripts'] == 0 and '<img src=x' not in page.dom
    text = page.state['alltext']
    assert evil in text and '<img src=x onerror=alert(2)>' in text and 'Ctrl-C <now>' in text
    assert '\\x1b[31mred\\x00' in text and '\x1b' not in text and '\x00' not in text
    assert not NONE.search(text), NONE.search(text)
    assert 'rearRight - / -' in text
    sec = section(page.dom, 'laser')                       # an unknown verdict: neutral badge
    assert 'badge OTHER' in sec and 'INTERRUPTED' in sec
    assert '1 INTERRUPTED' in text and '1 failed' in text


def _rates_pixels(html_text, rgb):
    """How many pixels of the rates figure have colour `rgb` (0-255 each, +-12)."""
    import base64
    import io

    import matplotlib.image
    import numpy as np
    m = re.search(r'alt="rate of every sensor over the run" src="data:image/png;base64,([^"]+)"', html_text)
    img = matplotlib.image.imread(io.BytesIO(base64.b64decode(m.group(1))), format='png')[:, :, :3] * 255
    return int((np.abs(img - np.array(rgb)).max(axis=2) <= 12).sum())


def test_rates_lines_are_coloured_by_the_rates_own_verdict(tmp_path):
    from pepper_interface_tests.outputs import report
    from report_fixtures import run_of, sensor
    red, blue = (0xcf, 0x22, 0x2e), (0x09, 0x69, 0xda)
    # fails for NaN ranges, but its rate is in band: blue, no red anywhere in the figure
    in_band = run_of(str(tmp_path), [sensor('frontSonar', 'FAIL', reasons=['range is NaN in 30 messages'])])
    text = report.render(in_band)
    assert _rates_pixels(text, red) == 0 and _rates_pixels(text, blue) > 200
    # passes (say, a lenient run) with a rate outside its band: red
    slow = run_of(str(tmp_path), [sensor('frontSonar', 'PASS', rate_hz=2.0)])
    text = report.render(slow)
    assert _rates_pixels(text, red) > 200 and '2.0 Hz out of band' not in text   # said in the figure


def test_a_pass_with_warnings_is_marked_at_a_glance(tmp_path):
    """The summary's badge reads PASS* for a PASS that carries warnings (as on the terminal)."""
    from pepper_interface_tests.outputs import report
    from report_fixtures import run_of, sensor
    text = report.render(run_of(str(tmp_path), [
        sensor('frontSonar', 'PASS', warnings=['rate 4.3 Hz within 10 % of the band\'s edge']),
        sensor('backSonar', 'PASS')]))
    assert text.count('title="passed with warnings">PASS*</span>') == 1, text


def test_camera_without_video_says_why(tmp_path):
    from pepper_interface_tests.outputs import report
    from report_fixtures import run_of, sensor
    failed = {'file': None, 'codec': None, 'fps': None, 'width': None, 'height': None, 'frames_received': 25,
              'frames_written': 0, 'frames_dropped': 25, 'error': 'cannot open a video writer for /x/front.mp4'}
    cams = [sensor('frontCamera', values={'video': failed, 'width': 320, 'height': 240, 'encoding': 'rgb8'}),
            sensor('bottomCamera', values={'video': dict(failed, error=None, frames_received=0)}),
            sensor('stereoCamera', notes=['recording off'])]
    text = report.render(run_of(str(tmp_path), cams))
    front = section(text, 'frontCamera')
    assert 'No video written: cannot open a video writer for /x/front.mp4; none of the 25 frames' in front
    assert '0 frames' not in front and 'codec -' not in front and 'None' not in front
    assert 'No video written: no frame reached the video writer' in section(text, 'bottomCamera')
    assert 'No video written: recording is off for this run' in section(text, 'stereoCamera')


def test_silent_channel_has_its_own_marked_level_plot(tmp_path):
    import base64
    import io

    import matplotlib.image
    import numpy as np

    from pepper_interface_tests.outputs import report
    from report_fixtures import run_of, sensor
    chans = {'rearLeft': -20.0, 'rearRight': None, 'frontLeft': -30.0, 'frontRight': -35.0}
    series = {'level_dbfs_' + c: [[0.1 * k, None if v is None else v + k % 3] for k in range(30)]
              for c, v in chans.items()}
    values = {'channels': {c: {'rms_dbfs': v, 'peak_dbfs': None if v is None else v + 6, 'clipping_share': 0.0,
                               'all_zero': v is None} for c, v in chans.items()}}
    mic = sensor('microphone', 'FAIL', reasons=['microphone rearRight is silent: RMS -inf dBFS'],
                 notes=['Levels (RMS / peak dBFS): rearLeft -20 / -14, rearRight None / None'],
                 values=values, series=series)
    text = report.render(run_of(str(tmp_path), [mic]))
    sec = section(text, 'microphone')
    assert not NONE.search(re.sub(r'data:[^"]+', '', sec))
    assert re.search(r'<td>rearRight</td><td class="num">-inf</td><td class="num">-inf</td>.*?silent', sec)
    m = re.search(r'alt="microphone level over time, one plot per channel" src="data:image/png;base64,([^"]+)"', sec)
    img = matplotlib.image.imread(io.BytesIO(base64.b64decode(m.group(1))), format='png')[:, :, :3] * 255
    pink = (np.abs(img - np.array((0xff, 0xeb, 0xe9))).max(axis=2) <= 3)
    rows = np.nonzero(pink.any(axis=1))[0]
    # the silent channel's strip (2nd of 4) is pink, and only that one
    assert len(rows) > 20 and rows.min() > img.shape[0] * 0.2 and rows.max() < img.shape[0] * 0.55, \
        (rows.min(), rows.max(), img.shape)


def test_media_budget_embeds_short_clips_and_links_the_rest(tmp_path):
    from pepper_interface_tests.outputs.report.blocks import Media, Para
    from pepper_interface_tests.outputs.report.files import EMBED_BUDGET_BYTES, MAX_EMBED_BYTES, RunFiles
    assert (MAX_EMBED_BYTES, EMBED_BUDGET_BYTES) == (512 * 1024, 1024 * 1024)   # as docs/results.md says
    sizes = {'a.wav': 400000, 'b.wav': 400000, 'c.wav': 400000, 'big.wav': MAX_EMBED_BYTES + 1, 'd.wav': 100000}
    for name, size in sizes.items():
        (tmp_path / name).write_bytes(os.urandom(size))
    files = RunFiles(str(tmp_path))
    blocks = {name: files.media('audio', name, 'audio/wav') for name in sizes}
    assert all(isinstance(b, Media) for b in blocks.values())
    embedded = sorted(n for n, b in blocks.items() if b.src.startswith('data:'))
    # a and b fit (800 kB); c would pass the 1 MB budget; big is over 512 kB; d still fits
    assert embedded == ['a.wav', 'b.wav', 'd.wav'], embedded
    assert blocks['c.wav'].src == 'c.wav' and blocks['big.wav'].src == 'big.wav'
    assert files.embedded == 900000
    missing = files.media('video', 'gone.mp4', 'video/mp4')
    assert isinstance(missing, Para) and 'gone.mp4 not found' in missing.parts[0]


def assert_fits(page, width):
    """The page does not scroll sideways: nothing runs past the window's right edge (a table
    wider than its place scrolls inside its own box)."""
    state = page.state
    assert state['inner_width'] == width, state['inner_width']
    assert state['scroll_width'] <= state['inner_width'], (
        'the page is %dpx wide in a %dpx window; past the right edge: %s'
        % (state['scroll_width'], state['inner_width'], state['wide']))


def test_long_reasons_on_every_row_and_a_wide_steps_table_fit_1024_and_1280_pixels(tmp_path):
    """Issue 45: the summary's reasons and the motion check's steps table (a column per
    witness) ran past a 1280-pixel window. Every row with long reasons and warnings (a long
    word among them: a path), long topics, and the steps table of a --move run with every
    witness: the page fits 1024 and 1280 px, the reasons shown whole."""
    from pepper_interface_tests.outputs import report
    from report_fixtures import run_of, sensor
    folder = str(tmp_path)
    long_reason = ('the 60 s window saw 3 of the 10 expected messages, %s, the rest too late or never '
                   'sent: the publisher stopped at t = 4.2 s and did not come back, check the driver '
                   'and /very/long/path/to/the/driver/configuration/file/that/does/not/break/anywhere.yaml')
    names = ['frontSonar', 'backSonar', 'frontCamera', 'realsenseDepthCamera', 'laser', 'microphone',
             'jointState', 'odometry', 'imu']
    rows = [sensor(n, 'FAIL', topic='/naoqi_driver/a/very/long/namespace/for/%s/image_raw_compressed_depth' % n,
                   reasons=[long_reason % ('reason %d' % i) for i in range(3)],
                   warnings=['warning: ' + long_reason % 'also'])
            for n in names]
    witnesses = ['HeadYaw', 'frontCamera', 'bottomCamera', 'stereoCamera', 'depthCamera', 'realsenseRGBCamera',
                 'odometry', 'gyro_z', 'gyro_x', 'gyro_y', 'laser', 'wheels', 'frontSonar', 'backSonar']
    steps = [{'part': part, 'commanded': c, 'sent': 1.0 + i, 'ended': 2.0 + i, 'settled': True,
              'measured': {w: c * 0.97 for w in witnesses}}
             for i, (part, c) in enumerate([('head', 0.5), ('head', -1.0), ('base', 0.5), ('base', -0.5)])]
    motion = sensor('motion', 'FAIL', topic='/move_base_simple/goal', reasons=[long_reason % 'moved'],
                    values={'head': 'moved', 'base': 'moved', 'steps': steps})
    run = run_of(folder, [motion] + rows)
    path = report.write_report(run)
    for width in (1024, 1280):
        png = str(tmp_path / ('long-%d.png' % width))
        page = render_page(path, png, width=width)
        keep_screenshot(png, 'long-reasons-%d.png' % width)
        assert page.problems() == []
        assert_fits(page, width)
        # each shown whole, in the summary and in its section
        assert page.state['text'].count('reason 2, the rest too late') == 2 * len(rows)
