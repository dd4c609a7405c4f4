"""Helpers for the camera, depth, microphone and recording tests: run media_publisher.py and
sensorTest as a user would, read results and recordings back. Nothing here imitates ROS."""
import json
import os
import subprocess
import sys

import numpy as np

from pepper_interface_tests.plan import declaration
from rosmaster import NODES, ROOT, kill_group, script, spawn

HERE = NODES   # the node scripts' folder (test/nodes/)
PUBLISHER = os.path.join(NODES, 'media_publisher.py')

TOPICS = {
    'frontCamera': '/media/front/image_raw',
    'bottomCamera': '/media/bottom/image_raw',
    'stereoCamera': '/media/stereo/image_raw',
    'realsenseRGBCamera': '/media/color/image_raw',
    'depthCamera': '/media/depth/image_raw',
    'realsenseDepthCamera': '/media/aligned_depth/image_raw',
    'microphone': '/media/audio',
}
# the head cameras' frames as naoqi_driver publishes them (plan/declaration.py)
FRAME_IDS = {n: s.stream(declaration.STOCK).frame for n, s in declaration.SENSORS.items()
             if s.camera == 'pepper' and s.stream(declaration.STOCK)}


def topics_file(tmp):
    path = os.path.join(str(tmp), 'mediaTopics.dat')
    with open(path, 'w') as f:
        f.writelines('%s %s\n' % kv for kv in TOPICS.items())
    return path


class Publishers:
    """media_publisher.py processes for one test; stopped (and reports collected) on exit."""

    def __init__(self, master, tmp):
        self.master, self.tmp, self.procs = master, str(tmp), {}

    def add(self, sensor, kind, *args):
        report = os.path.join(self.tmp, 'published_%s.json' % sensor)
        cmd = [sys.executable, PUBLISHER, kind, TOPICS[sensor], '--report', report,
               '--node', 'pub_' + sensor, '--frame-id', FRAME_IDS.get(sensor, '')] + [str(a) for a in args]
        self.procs[sensor] = (spawn(cmd, self.master.env(), stdout=subprocess.DEVNULL), report)
        return self

    def stop(self):
        counts = {}
        for sensor, (proc, report) in self.procs.items():
            kill_group(proc)
            if os.path.exists(report):
                with open(report) as f:
                    counts[sensor] = json.load(f)['published']
        self.procs = {}
        return counts

    def __enter__(self):
        # nothing to wait for: the publishers are added inside the block, sensorTest's --wait
        # covers their start-up and a --count publisher waits for its subscriber (media_publisher.py)
        return self

    def __exit__(self, *exc):
        self.stop()


def expectations_file(tmp, platform, overrides):
    """The package's expectations with some keys changed for some sensors (a temporary YAML)."""
    import yaml
    with open(os.path.join(ROOT, 'config', 'sensorExpectations.yaml')) as f:
        data = yaml.safe_load(f)
    for sensor, values in overrides.items():
        data.setdefault(platform, {}).setdefault(sensor, {}).update(values)
    path = os.path.join(str(tmp), 'mediaExpectations.yaml')
    with open(path, 'w') as f:
        yaml.safe_dump(data, f)
    return path


def sensor_test(master, tmp, sensors, duration=4, wait=6, platform='robot', extra=(), env=None,
                timeout=120, expect=None):
    """Run scripts/sensorTest as a subprocess; returns (CompletedProcess, results dict or None).

    `expect` = {sensor: {key: value}} changes expectations for this run. A publisher started
    with --count stops before the window ends: give its sensor a large max_gap_factor."""
    out = os.path.join(str(tmp), 'out')
    if expect:
        extra = list(extra) + ['--expectations', expectations_file(tmp, platform, expect)]
    cmd = script('sensorTest') + ['--topics', topics_file(tmp), '--sensors', ','.join(sensors),
                                  '--duration', str(duration), '--wait', str(wait), '--output-dir', out,
                                  '--platform', platform, '--mode', 'parallel', '--no-show',
                                  '--no-history', '--no-diagnostics', '--no-report'] + list(extra)
    environment = master.env(**(env or {}))
    done = subprocess.run(cmd, env=environment, capture_output=True, text=True, timeout=timeout)
    return done, load_results(out)


def load_results(out):
    path = os.path.join(out, 'sensorTestResults.json')
    if not os.path.exists(path):
        return None
    with open(path) as f:
        data = json.load(f)
    data['by_name'] = {s['name']: s for s in data['sensors']}
    return data


def video_info(path):
    """(frames decoded, width, height, fps) of a video, read back with OpenCV."""
    import cv2
    cap = cv2.VideoCapture(path)
    assert cap.isOpened(), path
    fps = cap.get(cv2.CAP_PROP_FPS)
    frames, size = 0, None
    while True:
        ok, frame = cap.read()
        if not ok:
            break
        frames += 1
        size = (frame.shape[1], frame.shape[0])
    cap.release()
    return frames, size[0] if size else None, size[1] if size else None, fps


def video_rate_is_the_stream_rate(fps, result):
    """The rule of media/recording.py: a video plays at the rate its frames arrived at, as
    sensorTest measured it (ffmpeg starts at the first frames' rate, and the file is corrected
    when the whole recording's rate differs by more than REMUX_TOLERANCE, 5 %). Checked against
    the rate measured in this run, not against the publisher's nominal rate: a loaded machine
    delivers 24 frames at 12 Hz as 10.4 Hz as well."""
    from pepper_interface_tests.media.recording import REMUX_TOLERANCE
    measured = result['rate_hz']
    return measured is not None and abs(fps - measured) <= REMUX_TOLERANCE * measured


def video_codec(path):
    out = subprocess.run(['ffprobe', '-v', 'error', '-select_streams', 'v:0', '-show_entries',
                          'stream=codec_name', '-of', 'csv=p=0', path], capture_output=True, text=True)
    return out.stdout.strip()


def dominant_frequency(samples, rate):
    x = np.asarray(samples, dtype=np.float64)
    x = x - x.mean()
    spectrum = np.abs(np.fft.rfft(x * np.hanning(len(x))))
    return np.fft.rfftfreq(len(x), 1.0 / rate)[int(np.argmax(spectrum))]


def explain(done, results):
    """Text for assertion messages."""
    return 'exit %s\nstdout:\n%s\nstderr:\n%s\nresults: %s' % (
        done.returncode, done.stdout[-3000:], done.stderr[-3000:],
        json.dumps({k: {'verdict': v['verdict'], 'reasons': v['reasons'], 'warnings': v['warnings']}
                    for k, v in (results or {}).get('by_name', {}).items()}, indent=1))


def make_check(sensor, tmp, platform='robot', services=None, expect=None, **options):
    """A sensor's Check built from the package's real plan (settings.load_plan), not started."""
    from pepper_interface_tests.plan import settings
    from pepper_interface_tests.sensors import check_class
    from pepper_interface_tests.sensors.base import RunContext
    opts = settings.Options(platform=platform, sensors=(sensor,), topics=topics_file(tmp),
                            output_dir=os.path.join(str(tmp), 'out'), **options)
    plan = settings.load_plan(opts)
    sp = plan.sensors[0]
    if expect:
        sp = settings.SensorPlan(sp.sensor, sp.topic, sp.expect.but(**expect))
    os.makedirs(plan.output_dir, exist_ok=True)
    ctx = RunContext(plan.output_dir, plan.platform, plan.options, services)
    return check_class(sp.sensor.family)(sp, ctx)


def pattern(w, h, i):
    yy, xx = np.mgrid[0:h, 0:w]
    return np.dstack([(xx * 2 + 5 * i) % 256, (yy * 3 + 3 * i) % 256, (xx + yy + 7 * i) % 256]).astype(np.uint8)
