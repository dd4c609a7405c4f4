"""Test helper: a RunResult with real recordings, built in-process for the report tests.

`media_run(folder)` runs the package's real checks (SensorRun from runner.py, the camera,
depth, microphone, laser, sonar, joint, odometry and IMU checks) over serialized ROS messages
made here, exactly as the runner feeds them from a subscription, but without a ROS master: the
camera checks write real mp4 files with cv2 (through recording.VideoRecorder) and JPEG frames,
the microphone check writes a real 4-channel WAV with soundfile. A speech result and an extra
"depth histogram" are added by hand (the speech check needs a live master; the depth check
does not record a histogram yet), so every section of the report has something to show.

`handmade_media(folder)` writes a small H.264 mp4 with cv2.VideoWriter and a WAV with
soundfile directly, for tests that need files of a known size.
"""
import io
import math
import os
import time

import numpy as np


def _serialize(msg):
    buf = io.BytesIO()
    msg.serialize(buf)
    return buf.getvalue()


def _stamp(header, t, frame):
    import rospy
    header.stamp = rospy.Time.from_sec(t)
    header.frame_id = frame


def camera_image(i, w=320, h=240, frame='CameraTop_optical_frame', t=0.0):
    from sensor_msgs.msg import Image
    y, x = np.mgrid[0:h, 0:w]
    r = (x * 255 // max(1, w - 1)).astype(np.uint8)
    g = (y * 255 // max(1, h - 1)).astype(np.uint8)
    b = np.full((h, w), 60, np.uint8)
    cx, cy = int(w * (0.2 + 0.6 * (i % 40) / 40.0)), h // 2
    disc = (x - cx) ** 2 + (y - cy) ** 2 < (h // 6) ** 2
    rgb = np.dstack([r, g, b])
    rgb[disc] = (255, 255, 255)
    msg = Image(height=h, width=w, encoding='rgb8', is_bigendian=0, step=w * 3, data=rgb.tobytes())
    _stamp(msg.header, t, frame)
    return msg


def stereo_image(i, t=0.0):
    from sensor_msgs.msg import Image
    left = camera_image(i, 320, 180)
    right = camera_image(i + 3, 320, 180)
    a = np.frombuffer(left.data, np.uint8).reshape(180, 320, 3)
    b = np.frombuffer(right.data, np.uint8).reshape(180, 320, 3)
    both = np.ascontiguousarray(np.concatenate([a, b], axis=1))
    msg = Image(height=180, width=640, encoding='rgb8', is_bigendian=0, step=640 * 3, data=both.tobytes())
    _stamp(msg.header, t, 'CameraDepth_optical_frame')
    return msg


def depth_image(i, w=320, h=240, t=0.0):
    from sensor_msgs.msg import Image
    y, x = np.mgrid[0:h, 0:w]
    mm = (600 + 3000 * x / (w - 1) + 300 * np.sin(y / 20.0 + i / 5.0)).astype(np.uint16)
    mm[:20, :40] = 0                 # a patch without depth
    msg = Image(height=h, width=w, encoding='16UC1', is_bigendian=0, step=w * 2, data=mm.tobytes())
    _stamp(msg.header, t, 'CameraDepth_optical_frame')
    return msg


def audio_buffer(i, n=4096, rate=48000):
    from pepper_interface_tests.msg import AudioCustomMsg
    t = (np.arange(n) + i * n) / float(rate)
    amps = (0.30, 0.10, 0.03, 0.01)
    freqs = (220.0, 330.0, 440.0, 660.0)
    envelope = 0.6 + 0.4 * np.sin(2 * np.pi * 0.5 * t)
    chans = [(a * 32767 * envelope * np.sin(2 * np.pi * f * t)).astype(np.int16) for a, f in zip(amps, freqs)]
    return AudioCustomMsg(rearLeft=chans[0].tolist(), rearRight=chans[1].tolist(),
                          frontLeft=chans[2].tolist(), frontRight=chans[3].tolist())


def _core_message(kind, i, t):
    """Good messages of the core kinds (as test/core_publisher.py makes them), stamped at t."""
    from geometry_msgs.msg import Quaternion
    from nav_msgs.msg import Odometry
    from sensor_msgs.msg import Imu, JointState, LaserScan, Range

    from core_publisher import JOINTS
    if kind == 'range':
        m = Range(radiation_type=Range.ULTRASOUND, field_of_view=0.5236, min_range=0.25, max_range=2.55,
                  range=1.0 + 0.5 * math.sin(i / 5.0))
        _stamp(m.header, t, 'SonarBack_frame')
        return m
    if kind == 'laser':
        m = LaserScan(angle_min=-2.0944, angle_max=2.0944, range_min=0.1, range_max=3.0, scan_time=0.1)
        m.angle_increment = (m.angle_max - m.angle_min) / 60
        r = [1.5 + 0.8 * math.sin(k / 4.0 + i / 10.0) for k in range(61)]
        for k in list(range(15, 23)) + list(range(38, 46)):
            r[k] = -1.0
        r[5], r[50] = float('nan'), 7.5        # two invalid beams to mark
        m.ranges = r
        _stamp(m.header, t, 'base_footprint')
        return m
    if kind == 'joints':
        m = JointState(name=list(JOINTS), position=[0.1 * math.sin(i / 20.0 + k) for k in range(len(JOINTS))],
                       velocity=[0.01 * k for k in range(len(JOINTS))], effort=[0.5] * len(JOINTS))
        _stamp(m.header, t, '')
        return m
    if kind == 'odometry':
        m = Odometry(child_frame_id='base_link')
        m.pose.pose.position.x = 0.5 * math.sin(i / 15.0)
        m.pose.pose.position.y = 0.5 - 0.5 * math.cos(i / 15.0)
        m.pose.pose.orientation = Quaternion(0, 0, 0, 1.0)
        m.twist.twist.linear.x = 0.1
        _stamp(m.header, t, 'odom')
        return m
    if kind == 'imu':
        m = Imu()
        m.orientation = Quaternion(0, 0, 0, 1.0)
        m.linear_acceleration.z = 9.81 + 0.05 * math.sin(i)
        m.angular_velocity.z = 0.1 * math.sin(i / 3.0)
        _stamp(m.header, t, 'base_footprint')
        return m
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

    from pepper_interface_tests import settings
    from pepper_interface_tests.results import PASS, RunResult, SensorResult
    from pepper_interface_tests.runner import SensorRun
    from pepper_interface_tests.sensors.base import RunContext
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
                values={'text': 'This is the CSSR4Africa speaker test.', 'subscribers': ['/naoqi_driver'],
                        'heard': True, 'level_rise_db': 17.5},
                notes=['Sentence delivered to /naoqi_driver', 'Heard by the microphones: level rose 17.5 dB']))
            clock += 4.2
            continue
        type_name, rate, count, make = feeds[sp.name]
        sr = SensorRun(sp, ctx, 1000.0, wait=plan.wait, duration=plan.duration)
        sr.begin(clock)
        for i in range(count):
            t = clock + i / rate
            stamp = wall + (t - 1000.0)
            sr.feed_raw(type_name, _serialize(make(i, stamp)), t, stamp + 0.002)
        clock += count / rate
        result = sr.close(clock, 'window ended')
        run.sensors.append(result)
        clock += 0.1
    run.end = run.start + (clock - 1000.0)
    for r in run.sensors:       # what the depth check may add later: a histogram of the depths
        if r.name == 'depthCamera' and 'depth_histogram' not in r.values:
            edges = [round(0.5 * k, 2) for k in range(11)]
            r.values['depth_histogram'] = {'edges': edges, 'counts': [0, 120, 900, 1500, 1400, 1300,
                                                                      1200, 1000, 300, 40]}
    return run


def handmade_media(folder, name='clip.mp4', wav='clip.wav', seconds=2.0, fps=10):
    """A small H.264 mp4 (cv2) and a 4-channel 48 kHz WAV (soundfile); returns their paths."""
    import cv2
    import soundfile
    path = os.path.join(folder, name)
    writer = cv2.VideoWriter(path, cv2.VideoWriter_fourcc(*'avc1'), fps, (320, 240))
    if not writer.isOpened():
        writer = cv2.VideoWriter(path, cv2.VideoWriter_fourcc(*'mp4v'), fps, (320, 240))
    for i in range(int(seconds * fps)):
        msg = camera_image(i)
        frame = np.frombuffer(msg.data, np.uint8).reshape(240, 320, 3)[:, :, ::-1]
        writer.write(np.ascontiguousarray(frame))
    writer.release()
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
    """A SensorResult of the catalog's sensor `name` with plausible defaults, for report tests."""
    from pepper_interface_tests import catalog
    from pepper_interface_tests.results import SensorResult
    s = catalog.SENSORS[name]
    fields = dict(name=name, title=name.upper(), topic='/t/' + name, msg_type=s.msg_type, verdict=verdict,
                  messages=30, rate_hz=10.0, expected_rate_hz=[4.0, 16.0], window_s=3.0, started_at=0.0,
                  ended_at=3.0, stopped_because='window ended')
    fields.update(kw)
    if 'series' not in kw and fields['rate_hz'] is not None:
        fields['series'] = {'rate_hz': rate_series(fields['rate_hz'], fields['window_s'])}
    return SensorResult(**fields)


def run_of(folder, sensors, **kw):
    from pepper_interface_tests.results import RunResult
    return RunResult(platform='robot', mode='parallel', start=1.7e9, end=1.7e9 + 4, output_dir=folder,
                     run_id=kw.pop('run_id', 'handmade'), sensors=list(sensors), **kw)
