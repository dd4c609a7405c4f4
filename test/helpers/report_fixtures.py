"""Test helper: a RunResult with real recordings, built in-process for the report tests.

`media_run(folder)` runs the package's real checks (SensorRun from sensors/window.py, the camera,
depth, microphone, laser, sonar, joint, odometry and IMU checks) over serialized ROS messages
made here, exactly as the runner feeds them from a subscription, but without a ROS master: the
camera checks write real mp4 files with cv2 (through recording.VideoRecorder) and JPEG frames,
the microphone check writes a real 4-channel WAV with soundfile. A speech result and an extra
"depth histogram" are added by hand (the speech check needs a live master; the depth check
does not record a histogram yet), so every section of the report has something to show.

`handmade_media(folder)` writes a small H.264 mp4 with cv2.VideoWriter and a WAV with
soundfile directly, for tests that need files of a known size.
"""
import dataclasses
import os
import time

import numpy as np

import fake_pepper as fake
from fake_pepper import audio_buffer, camera_image, depth_image, stereo_image
from pepper_interface_tests.sensors.values.depth import DepthHistogram
from pepper_interface_tests.sensors.values.speech import SpeechValues


def _core_message(kind, i, t):
    """Good messages of the core kinds, stamped at t, with more variety than core_publisher's."""
    if kind == 'range':
        return fake.sonar(i, t)
    if kind == 'laser':
        return fake.laser(i, t, swing=0.8, marked=True)     # two invalid beams to mark
    if kind == 'joints':
        return fake.joints(i, t, varied=True)
    if kind == 'odometry':
        return fake.odometry(i, t, circle=True)
    if kind == 'imu':
        return fake.imu(i, t, moving=True)
    raise ValueError(kind)


# sensor -> (message type name, rate Hz, count, maker(i, stamp))
def _feeds():
    return {
        'frontCamera': ('sensor_msgs/Image', 10.0, 30, lambda i, t: camera_image(i, t=t)),
        'stereoCamera': ('sensor_msgs/Image', 10.0, 20, lambda i, t: stereo_image(i, t=t)),
        'depthCamera': ('sensor_msgs/Image', 10.0, 30, lambda i, t: depth_image(i, t=t)),
        'microphone': ('pepper_interface_tests/AudioCustomMsg', 48000 / 4096.0, 30, lambda i, t: audio_buffer(i)),
        'backSonar': ('sensor_msgs/Range', 10.0, 30, lambda i, t: _core_message('range', i, t)),
        'laser': ('sensor_msgs/LaserScan', 10.0, 30, lambda i, t: _core_message('laser', i, t)),
        'jointState': ('sensor_msgs/JointState', 50.0, 120, lambda i, t: _core_message('joints', i, t)),
        'odometry': ('nav_msgs/Odometry', 15.0, 45, lambda i, t: _core_message('odometry', i, t)),
        'imu': ('sensor_msgs/Imu', 10.0, 30, lambda i, t: _core_message('imu', i, t)),
    }


MEDIA_SENSORS = ('frontCamera', 'stereoCamera', 'depthCamera', 'microphone', 'backSonar', 'laser',
                 'jointState', 'odometry', 'imu', 'speech')


def media_run(folder, sensors=MEDIA_SENSORS):
    """A RunResult whose results come from the real checks fed with made-up messages."""
    import rospy.rostime

    from pepper_interface_tests.plan import settings
    from pepper_interface_tests.results import PASS, RunResult, SensorResult
    from pepper_interface_tests.sensors.base import RunContext
    from pepper_interface_tests.sensors.window import SensorRun
    rospy.rostime.set_rostime_initialized(True)      # message stamps without a node
    os.makedirs(folder, exist_ok=True)
    plan = settings.load_plan(settings.Options(sensors=tuple(sensors), output_dir=folder, duration=3.0))
    ctx = RunContext(folder, plan.platform, plan.options)
    run = RunResult(platform=plan.platform, mode='sequential', start=time.time(), output_dir=folder,
                    run_id='test-media', files=dict(plan.files))
    feeds = _feeds()
    clock = 1000.0         # the runner's clock (monotonic seconds); messages are fed at their rate
    wall = time.time()
    for sp in plan.sensors:
        if sp.name == 'speech':
            run.sensors.append(SensorResult(
                name='speech', title='SPEECH', topic=sp.topic, msg_type=sp.sensor.msg_type, verdict=PASS,
                messages=1, window_s=4.2, stopped_because='finished', started_at=round(clock - 1000.0, 3),
                ended_at=round(clock - 1000.0 + 4.2, 3), fields=[['Text', 'This is the CSSR4Africa speaker test.']],
                family='speech', values=SpeechValues('This is the CSSR4Africa speaker test.', ['/naoqi_driver'],
                                                     True, 17.5),
                notes=['Sentence delivered to /naoqi_driver', 'Heard by the microphones: level rose 17.5 dB']))
            clock += 4.2
            continue
        type_name, rate, count, make = feeds[sp.name]
        sr = SensorRun(sp, ctx, 1000.0, wait=plan.wait, duration=plan.duration)
        sr.begin(clock)
        for i in range(count):
            t = clock + i / rate
            stamp = wall + (t - 1000.0)
            sr.feed_raw(type_name, fake.serialized(make(i, stamp)), t, stamp + 0.002)
        clock += count / rate
        result = sr.close(clock, 'window ended')
        run.sensors.append(result)
        clock += 0.1
    run.end = run.start + (clock - 1000.0)
    for r in run.sensors:       # what the depth check may add later: a histogram of the depths
        if r.name == 'depthCamera' and r.values.depth_histogram is None:
            edges = [round(0.5 * k, 2) for k in range(11)]
            r.values = dataclasses.replace(r.values, depth_histogram=DepthHistogram(
                edges, [0, 120, 900, 1500, 1400, 1300, 1200, 1000, 300, 40]))
    return run


def handmade_media(folder, name='clip.mp4', wav='clip.wav', seconds=2.0, fps=10):
    """A small H.264 mp4 (ffmpeg's libx264, as media/recording.py encodes) and a 4-channel
    48 kHz WAV (soundfile); returns their paths. Not OpenCV's VideoWriter: the pip wheels of
    OpenCV 4.2 (the Noetic tier's) have no H.264 encoder."""
    import subprocess

    import soundfile
    path = os.path.join(folder, name)
    frames = b''.join(np.ascontiguousarray(np.frombuffer(camera_image(i).data, np.uint8)
                                           .reshape(240, 320, 3)[:, :, ::-1]).tobytes()
                      for i in range(int(seconds * fps)))
    subprocess.run(['ffmpeg', '-y', '-loglevel', 'error', '-f', 'rawvideo', '-pix_fmt', 'bgr24',
                    '-s', '320x240', '-r', str(fps), '-i', '-', '-c:v', 'libx264', '-pix_fmt',
                    'yuv420p', path], input=frames, check=True, timeout=60)
    rate = 48000
    t = np.arange(int(seconds * rate)) / float(rate)
    data = np.stack([0.2 * np.sin(2 * np.pi * f * t) for f in (220, 330, 440, 550)], axis=1)
    wav_path = os.path.join(folder, wav)
    soundfile.write(wav_path, data, rate, subtype='PCM_16')
    return path, wav_path


def rate_series(rate, seconds):
    """A check's 1 s rate bins: [(bin centre s, messages in that bin)]."""
    return [[k + 0.5, rate] for k in range(int(seconds))]


def sensor(name, verdict='PASS', **kw):
    """A SensorResult of the catalog's sensor `name` with plausible defaults, for report tests.
    `values`, `series` and `stats` are given as a run's JSON holds them (keys and lists) and read
    into the family's values dataclass and a StreamSummary as sensorTestHistory reads that JSON
    back."""
    from pepper_interface_tests import codec
    from pepper_interface_tests.plan import catalog
    from pepper_interface_tests.results import SensorResult
    from pepper_interface_tests.sensors import families
    from pepper_interface_tests.stats import StreamSummary
    s = catalog.SENSORS[name]
    fields = dict(name=name, title=name.upper(), topic='/t/' + name, msg_type=s.msg_type, verdict=verdict,
                  messages=30, rate_hz=10.0, expected_rate_hz=[4.0, 16.0], window_s=3.0, started_at=0.0,
                  ended_at=3.0, stopped_because='window ended', family=s.family)
    fields.update(kw)
    series = fields.pop('series', None)
    if series is None and fields['rate_hz'] is not None:
        series = {'rate_hz': rate_series(fields['rate_hz'], fields['window_s'])}
    if series and 'rate_hz' in series:
        fields['rate_series'] = [tuple(p) for p in series['rate_hz']]
    if isinstance(fields.get('stats'), dict):
        fields['stats'] = codec.from_json(StreamSummary, fields['stats'])
    values = fields.pop('values', None)
    if values is not None or series:
        fields['values'] = codec.join(families.values_of(s.family), values, series)
    return SensorResult(**fields)


def run_of(folder, sensors, **kw):
    from pepper_interface_tests.results import RunResult
    return RunResult(platform='robot', mode='parallel', start=1.7e9, end=1.7e9 + 4, output_dir=folder,
                     run_id=kw.pop('run_id', 'handmade'), sensors=list(sensors), **kw)
