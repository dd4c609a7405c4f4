"""Test helper: made-up Pepper messages, one builder per message kind, shared by every test
and test publisher (the sensors' tests, test_driver_semantics, test_emulator_node, core_publisher,
driver_publisher, media_publisher, report_fixtures, ...).

The fixed facts come from the emulator's profiles (src/pepper_interface_tests/emulator/
profiles.py, itself citing naoqi_driver and the simulator file:line): joint names, sonar limits
and field of view, laser layouts (naoqi_driver's 61 slots with two blind zones of 8 at -1.0;
the simulator's 488 NaN slots), frame ids, audio buffer size and rate. What varies per test is
an argument: the message index `i` (moves the content), the stamp `t` (a rospy/genpy Time or
seconds as a float; None leaves the stamp to the caller), `fault` (one of FAULTS, '' for a good
message), and keyword options for the variants the tests need; `**fields` set message fields
last (e.g. range=4.0, angle_increment=0.0), to break one thing on purpose.
"""
import io
import math

import numpy as np

from pepper_interface_tests.emulator import profiles

ROBOT = profiles.build_profile('robot')
SIMULATOR = profiles.build_profile('simulator')
JOINTS = list(profiles.JOINT_NAMES)                        # the 20 of /joint_states, wheels last
WHEELS = list(profiles.JOINTS_WITHOUT_VELOCITY)
BLIND = [k for k, blind in enumerate(profiles.laser_blind_mask()) if blind]   # 15-22, 38-45
FAULTS = ('nan', 'out_of_range', 'broken_quaternion', 'zero_stamp', 'old_stamp', 'frame',
          'missing_joint', 'dup_joint', 'short_velocity', 'bad_limits', 'wrong_ranges')
UNKNOWN_COVARIANCE = [-1.0] + [0.0] * 8     # naoqi_driver imu.cpp:123-126: "Covariances unknown"


def _cls(type_name):
    """The genpy class of a type, also in a ROS 2 environment (where `sensor_msgs.msg` is rclpy's):
    the package's own look-up, sources/messages.py."""
    from pepper_interface_tests.sources.messages import message_class
    return message_class(type_name)


def serialized(msg):
    """The message's bytes on the wire (what a subscriber's AnyMsg or a bag holds)."""
    buff = io.BytesIO()
    msg.serialize(buff)
    return buff.getvalue()


def spec(name, platform='robot'):
    """The robot (or simulator) profile's SensorSpec of `name` (e.g. 'frontSonar')."""
    return (SIMULATOR if platform == 'simulator' else ROBOT).sensor(name)


def stamp(header, t, frame_id, fault=''):
    """Set header.stamp (t: rospy/genpy Time or float seconds; None leaves it) and frame_id;
    the stamp faults give a zero stamp or one 30 s old, the `frame` fault a wrong frame id."""
    import genpy
    if t is not None or fault in ('zero_stamp', 'old_stamp'):
        t = t if isinstance(t, genpy.Time) else genpy.Time.from_sec(t or 0.0)
        header.stamp = (genpy.Time(0) if fault == 'zero_stamp'
                        else t - genpy.Duration(30) if fault == 'old_stamp' else t)
    header.frame_id = 'wrong_frame' if fault == 'frame' else frame_id


def _fields(m, fields):
    for k, v in fields.items():
        setattr(m, k, v)
    return m


def sonar(i=0, t=None, fault='', frame_id=None, platform='robot', sensor='backSonar', **fields):
    """A sonar Range with the profile's limits, field of view and frame id; the range swings
    between 0.5 and 1.5 m."""
    Range = _cls('sensor_msgs/Range')
    s = spec(sensor, platform)
    m = Range(radiation_type=Range.ULTRASOUND, field_of_view=s.field_of_view,
              min_range=s.range_min, max_range=s.range_max)
    if fault == 'bad_limits':
        m.min_range, m.max_range = 3.0, 1.0
    m.range = (float('nan') if fault == 'nan'
               else 6.0 if fault == 'out_of_range' else 1.0 + 0.5 * math.sin(i / 5.0))
    stamp(m.header, t, s.frame_id if frame_id is None else frame_id, fault)
    return _fields(m, fields)


def laser(i=0, t=None, fault='', swing=0.2, distance=1.5, marked=False, frame_id=None, blind=BLIND,
          n=profiles.LASER_BEAMS, **fields):
    """naoqi_driver's 61-slot scan: `distance` m +- `swing` moving from scan to scan, -1.0 in
    the `blind` slots; `marked` puts one NaN and one out-of-range beam in it; `n` keeps the
    first n ranges only."""
    LaserScan = _cls('sensor_msgs/LaserScan')
    s = spec('laser')
    m = LaserScan(angle_min=-profiles.LASER_ANGLE, angle_max=profiles.LASER_ANGLE,
                  angle_increment=profiles.LASER_INCREMENT, range_min=s.range_min,
                  range_max=s.range_max, scan_time=1.0 / s.rate)
    r = [distance + swing * math.sin(k / 4.0 + i / 10.0) for k in range(profiles.LASER_BEAMS)]
    for k in blind:
        r[k] = profiles.LASER_BLIND_VALUE
    if marked:
        r[5], r[50] = float('nan'), 7.5
    if fault == 'nan':
        r = [float('nan')] * len(r)
    m.ranges = r[:40] if fault == 'wrong_ranges' else r[:n]
    stamp(m.header, t, s.frame_id if frame_id is None else frame_id, fault)
    return _fields(m, fields)


def sim_laser(i=0, t=None, returns=range(150, 190), beyond=(), distance=1.5):
    """The simulator's /pepper/laser_2 (laser_publisher.py:427-434): 488 slots of NaN over
    +-120 deg, filled where a point is (`returns`, `distance` m with the model's Gaussian noise,
    sd 0.01 m, moving them per scan); `beyond` slots hold 9 m, beyond range_max (real)."""
    LaserScan = _cls('sensor_msgs/LaserScan')
    s = spec('laser', 'simulator')
    n, half = profiles.SIM_LASER_SLOTS, profiles.SIM_LASER_ANGLE
    m = LaserScan(angle_min=-half, angle_max=half, angle_increment=2 * half / n,
                  range_min=s.range_min, range_max=s.range_max)
    r = [float('nan')] * n
    for k in returns:
        r[k] = distance + 0.01 * (k % 9) + 0.005 * math.sin(1.7 * i + k)
    for k in beyond:
        r[k] = 9.0
    m.ranges = r
    stamp(m.header, t, s.frame_id)
    return m


def _middle(name):
    """The middle of a joint's URDF limits (sensors/joint_limits.py), 0 for an unlimited one."""
    from pepper_interface_tests.sensors.joint_limits import LIMITS
    lo, hi = LIMITS.get(name, (None, None))[:2]
    return 0.0 if lo is None else (lo + hi) / 2.0


def joints(i=0, t=None, fault='', varied=False, frame_id='', names=None, position=None,
           velocity=None, effort=None):
    """All 20 joints (or `names`), each swinging by 0.1 rad around the middle of its URDF limits,
    velocity 0.01 and effort 0.5 each; `varied` gives each joint its own position and velocity;
    `position`, `velocity`, `effort` replace the lists."""
    JointState = _cls('sensor_msgs/JointState')
    names = list(JOINTS if names is None else names)
    if fault == 'missing_joint':
        names.remove('HeadYaw')
    if fault == 'dup_joint':
        names[1] = names[0]
    n = len(names)
    m = JointState(name=names,
                   position=[_middle(x) + 0.1 * math.sin(i / 20.0 + (k if varied else 0))
                             for k, x in enumerate(names)],
                   velocity=[0.01 * k if varied else 0.01 for k in range(n)], effort=[0.5] * n)
    if fault == 'short_velocity':
        m.velocity = m.velocity[:-1]
    if fault == 'nan':
        m.position[2] = float('nan')
    for field, value in (('position', position), ('velocity', velocity), ('effort', effort)):
        if value is not None:
            setattr(m, field, list(value))
    stamp(m.header, t, frame_id, fault)
    return m


def odometry(i=0, t=None, fault='', circle=False, frame_id='odom', child_frame_id=None, x=None,
             w=1.0, pose_covariance=None):
    """Driving forward at 0.1 m/s (or at `x`); `circle` moves the pose on a circle of 0.5 m;
    `w` is the orientation quaternion's w (0, 0, 0, w)."""
    Quaternion = _cls('geometry_msgs/Quaternion')
    Odometry = _cls('nav_msgs/Odometry')
    m = Odometry(child_frame_id=spec('odometry').child_frame_id if child_frame_id is None else child_frame_id)
    if circle:
        m.pose.pose.position.x = 0.5 * math.sin(i / 15.0)
        m.pose.pose.position.y = 0.5 - 0.5 * math.cos(i / 15.0)
    else:
        m.pose.pose.position.x = 0.01 * i if x is None else x
    m.pose.pose.orientation = Quaternion(0, 0, 0, 2.0 if fault == 'broken_quaternion' else w)
    m.twist.twist.linear.x = 0.1
    if pose_covariance is not None:
        m.pose.covariance = pose_covariance
    stamp(m.header, t, frame_id, fault)
    return m


def imu(i=0, t=None, fault='', moving=False, frame_id=None, orientation=(0, 0, 0, 1.0), acc_z=9.81,
        covariance=None, orientation_covariance=None, acceleration_covariance=None,
        velocity_covariance=None):
    """Upright and still (`orientation` x, y, z, w; gravity `acc_z`); `moving` adds a small
    wobble to acceleration and turn rate; `covariance` sets all three covariances at once
    (UNKNOWN_COVARIANCE: what naoqi_driver publishes), the other three one each."""
    Quaternion = _cls('geometry_msgs/Quaternion')
    Imu = _cls('sensor_msgs/Imu')
    m = Imu()
    m.orientation = Quaternion(*(orientation[:3] + (0.5,) if fault == 'broken_quaternion' else orientation))
    m.linear_acceleration.z = (float('nan') if fault == 'nan'
                               else acc_z + (0.05 * math.sin(i) if moving else 0.0))
    # the inertial board's raw values carry noise from message to message (no "stuck" IMU)
    m.angular_velocity.z = 0.1 * math.sin(i / 3.0) if moving else 0.001 * math.sin(1.3 * i)
    for field, value in (('orientation_covariance', orientation_covariance or covariance),
                         ('linear_acceleration_covariance', acceleration_covariance or covariance),
                         ('angular_velocity_covariance', velocity_covariance or covariance)):
        if value is not None:
            setattr(m, field, list(value))
    stamp(m.header, t, spec('imu').frame_id if frame_id is None else frame_id, fault)
    return m


def image(pixels, encoding, step=None, width=None, height=None, t=None, frame_id=''):
    """A sensor_msgs/Image of a numpy array (step/width/height overridable to break the layout)."""
    Image = _cls('sensor_msgs/Image')
    h, w = pixels.shape[:2]
    row = pixels.strides[0] if pixels.flags['C_CONTIGUOUS'] else w * pixels.itemsize * (
        pixels.shape[2] if pixels.ndim == 3 else 1)
    m = Image(width=width or w, height=height or h, encoding=encoding, is_bigendian=0,
              step=row if step is None else step, data=np.ascontiguousarray(pixels).tobytes())
    stamp(m.header, t, frame_id)
    return m


def camera_image(i, w=320, h=240, frame_id='CameraTop_optical_frame', t=0.0):
    """rgb8 gradient with a white disc moving left to right."""
    y, x = np.mgrid[0:h, 0:w]
    r = (x * 255 // max(1, w - 1)).astype(np.uint8)
    g = (y * 255 // max(1, h - 1)).astype(np.uint8)
    b = np.full((h, w), 60, np.uint8)
    cx, cy = int(w * (0.2 + 0.6 * (i % 40) / 40.0)), h // 2
    disc = (x - cx) ** 2 + (y - cy) ** 2 < (h // 6) ** 2
    rgb = np.dstack([r, g, b])
    rgb[disc] = (255, 255, 255)
    return image(rgb, 'rgb8', t=t, frame_id=frame_id)


def stereo_image(i, t=0.0):
    """Side-by-side pair (two 320x180 views, the right one 3 frames ahead)."""
    left = camera_image(i, 320, 180)
    right = camera_image(i + 3, 320, 180)
    a = np.frombuffer(left.data, np.uint8).reshape(180, 320, 3)
    b = np.frombuffer(right.data, np.uint8).reshape(180, 320, 3)
    return image(np.concatenate([a, b], axis=1), 'rgb8', t=t, frame_id='CameraDepth_optical_frame')


def depth_image(i, w=320, h=240, t=0.0):
    """16UC1 millimetres, 0.6-3.6 m across, with a patch without depth (0) in a corner."""
    y, x = np.mgrid[0:h, 0:w]
    mm = (600 + 3000 * x / (w - 1) + 300 * np.sin(y / 20.0 + i / 5.0)).astype(np.uint16)
    mm[:20, :40] = 0
    return image(mm, '16UC1', t=t, frame_id='CameraDepth_optical_frame')


MIC_TONES = {'rearLeft': 500.0, 'rearRight': 1000.0, 'frontLeft': 1500.0, 'frontRight': 2500.0}   # Hz


def audio_buffer(i=0, n=profiles.AUDIO_BUFFER, rate=profiles.AUDIO_RATE, tones=False, amplitude=3000.0,
                 channels=None, silent=None, short=None):
    """AudioCustomMsg (the CSSR4Africa bridge's four int16 microphones) of buffer `i`: by default
    one tone per channel, each 10 dB quieter than the one before; `tones` gives each microphone
    its MIC_TONES sine at `amplitude` (clipped to int16); `channels` gives the four channels'
    samples instead; the `silent` microphone is all zeros, the `short` one a sample short."""
    AudioCustomMsg = _cls('pepper_interface_tests/AudioCustomMsg')
    tt = (np.arange(n) + i * n) / float(rate)
    if channels is None and tones:
        channels = [amplitude * np.sin(2 * np.pi * MIC_TONES[name] * tt) for name in profiles.MIC_CHANNELS]
    elif channels is None:
        envelope = 0.6 + 0.4 * np.sin(2 * np.pi * 0.5 * tt)
        channels = [a * 32767 * envelope * np.sin(2 * np.pi * f * tt)
                    for a, f in zip((0.30, 0.10, 0.03, 0.01), (220.0, 330.0, 440.0, 660.0))]
    out = {}
    for name, x in zip(profiles.MIC_CHANNELS, channels):
        x = np.clip(np.asarray(x, dtype=float), -32768, 32767).astype(np.int16)
        if name == silent:
            x[:] = 0
        out[name] = (x[:-1] if name == short else x).tolist()
    return AudioCustomMsg(**out)


def stock_audio_buffer(i, cmap=(3, 5, 0, 2), dead=None, samples=profiles.STOCK_AUDIO_BUFFER,
                       frequency=profiles.AUDIO_RATE):
    """Stock naoqi_driver's naoqi_bridge_msgs/AudioBuffer (event/audio.cpp:170-180): interleaved
    int16 in the order of `cmap` (channelMap codes), `frequency`; the channel named by code c
    carries the tone MIC_TONES[name] (700 Hz for a code that is no microphone), the `dead`
    microphone all zeros."""
    from pepper_interface_tests.sources.naoqi_msgs import CHANNEL_NAMES, audio_buffer_class
    tt = (np.arange(samples) + i * samples) / float(profiles.AUDIO_RATE)
    cols = [np.zeros(samples, np.int16) if CHANNEL_NAMES[c] == dead
            else (3000 * np.sin(2 * np.pi * MIC_TONES.get(CHANNEL_NAMES[c], 700.0) * tt)).astype(np.int16)
            for c in cmap]
    m = audio_buffer_class()()
    m.frequency, m.channelMap = frequency, bytes(cmap)
    m.data = np.stack(cols, axis=1).reshape(-1).tolist()
    return m
