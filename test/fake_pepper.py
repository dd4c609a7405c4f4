"""Test helper: made-up Pepper messages, one builder per kind, shared by the tests' publishers
(core_publisher.py) and fixtures (report_fixtures.py).

The fixed facts come from the emulator's robot profile (src/pepper_interface_tests/emulator/
profiles.py, itself citing naoqi_driver file:line): joint names, sonar limits and field of view,
laser layout (61 slots, two blind zones of 8 at -1.0, +-2.0944 rad), frame ids, audio buffer size
and rate. What varies per test is an argument: the message index `i` (moves the content), the
stamp `t` (a rospy.Time, or seconds as a float), and `fault` (one of FAULTS, '' for a good one).
"""
import math

import numpy as np

from pepper_interface_tests.emulator import profiles

ROBOT = profiles.build_profile('robot')
JOINTS = list(profiles.JOINT_NAMES)
FAULTS = ('nan', 'out_of_range', 'broken_quaternion', 'zero_stamp', 'old_stamp', 'frame',
          'missing_joint', 'dup_joint', 'short_velocity', 'bad_limits', 'wrong_ranges')


def spec(name):
    """The robot profile's SensorSpec of `name` (e.g. 'frontSonar')."""
    return ROBOT.sensor(name)


def stamp(header, t, frame_id, fault=''):
    """Set header.stamp (t: rospy.Time or float seconds) and frame_id; the stamp faults give a
    zero stamp or one 30 s old, the `frame` fault a wrong frame id."""
    import rospy
    t = t if isinstance(t, rospy.Time) else rospy.Time.from_sec(t)
    header.stamp = (rospy.Time(0) if fault == 'zero_stamp'
                    else t - rospy.Duration(30) if fault == 'old_stamp' else t)
    header.frame_id = 'wrong_frame' if fault == 'frame' else frame_id


def sonar(i, t, fault='', frame_id=None):
    from sensor_msgs.msg import Range
    s = spec('backSonar')
    m = Range(radiation_type=Range.ULTRASOUND, field_of_view=s.field_of_view,
              min_range=s.range_min, max_range=s.range_max)
    if fault == 'bad_limits':
        m.min_range, m.max_range = 3.0, 1.0
    m.range = (float('nan') if fault == 'nan'
               else 6.0 if fault == 'out_of_range' else 1.0 + 0.5 * math.sin(i / 5.0))
    stamp(m.header, t, frame_id or s.frame_id, fault)
    return m


def laser(i, t, fault='', swing=0.2, marked=False, frame_id=None):
    """naoqi_driver's 61-slot scan; `marked` puts one NaN and one out-of-range beam in it."""
    from sensor_msgs.msg import LaserScan
    s = spec('laser')
    m = LaserScan(angle_min=-profiles.LASER_ANGLE, angle_max=profiles.LASER_ANGLE,
                  angle_increment=profiles.LASER_INCREMENT, range_min=s.range_min,
                  range_max=s.range_max, scan_time=1.0 / s.rate)
    r = [profiles.LASER_BLIND_VALUE if blind else 1.5 + swing * math.sin(k / 4.0 + i / 10.0)
         for k, blind in enumerate(profiles.laser_blind_mask())]
    if marked:
        r[5], r[50] = float('nan'), 7.5
    if fault == 'nan':
        r = [float('nan')] * len(r)
    if fault == 'wrong_ranges':
        r = r[:40]
    m.ranges = r
    stamp(m.header, t, frame_id or s.frame_id, fault)
    return m


def _middle(name):
    """The middle of a joint's URDF limits (sensors/joint_limits.py), 0 for an unlimited one."""
    from pepper_interface_tests.sensors.joint_limits import LIMITS
    lo, hi = LIMITS.get(name, (None, None))[:2]
    return 0.0 if lo is None else (lo + hi) / 2.0


def joints(i, t, fault='', varied=False, frame_id=''):
    """All 20 joints, each swinging around the middle of its URDF limits; `varied` gives each
    joint its own position, velocity and effort."""
    from sensor_msgs.msg import JointState
    names = list(JOINTS)
    if fault == 'missing_joint':
        names.remove('HeadYaw')
    if fault == 'dup_joint':
        names[1] = names[0]
    n = len(names)
    if varied:
        m = JointState(name=names, position=[_middle(x) + 0.1 * math.sin(i / 20.0 + k)
                                             for k, x in enumerate(names)],
                       velocity=[0.01 * k for k in range(n)], effort=[0.5] * n)
    else:
        m = JointState(name=names, position=[_middle(x) + 0.1 * math.sin(i / 20.0) for x in names],
                       velocity=[0.0] * (n - (1 if fault == 'short_velocity' else 0)), effort=[0.0] * n)
    if fault == 'nan':
        m.position[2] = float('nan')
    stamp(m.header, t, frame_id, fault)
    return m


def odometry(i, t, fault='', circle=False, frame_id='odom'):
    """Driving forward at 0.1 m/s; `circle` moves the pose on a circle of 0.5 m."""
    from geometry_msgs.msg import Quaternion
    from nav_msgs.msg import Odometry
    m = Odometry(child_frame_id=spec('odometry').child_frame_id or 'base_link')
    if circle:
        m.pose.pose.position.x = 0.5 * math.sin(i / 15.0)
        m.pose.pose.position.y = 0.5 - 0.5 * math.cos(i / 15.0)
    else:
        m.pose.pose.position.x = 0.01 * i
    m.pose.pose.orientation = Quaternion(0, 0, 0, 2.0 if fault == 'broken_quaternion' else 1.0)
    m.twist.twist.linear.x = 0.1
    stamp(m.header, t, frame_id, fault)
    return m


def imu(i, t, fault='', moving=False, frame_id=None):
    """Upright and still; `moving` adds a small wobble to acceleration and turn rate."""
    from geometry_msgs.msg import Quaternion
    from sensor_msgs.msg import Imu
    m = Imu()
    m.orientation = Quaternion(0, 0, 0, 0.5 if fault == 'broken_quaternion' else 1.0)
    m.linear_acceleration.z = (float('nan') if fault == 'nan'
                               else 9.81 + (0.05 * math.sin(i) if moving else 0.0))
    # the inertial board's raw values carry noise from message to message (no "stuck" IMU)
    m.angular_velocity.z = 0.1 * math.sin(i / 3.0) if moving else 0.001 * math.sin(1.3 * i)
    stamp(m.header, t, frame_id or spec('imu').frame_id, fault)
    return m


def camera_image(i, w=320, h=240, frame_id='CameraTop_optical_frame', t=0.0):
    """rgb8 gradient with a white disc moving left to right."""
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
    stamp(msg.header, t, frame_id)
    return msg


def stereo_image(i, t=0.0):
    """Side-by-side pair (two 320x180 views, the right one 3 frames ahead)."""
    from sensor_msgs.msg import Image
    left = camera_image(i, 320, 180)
    right = camera_image(i + 3, 320, 180)
    a = np.frombuffer(left.data, np.uint8).reshape(180, 320, 3)
    b = np.frombuffer(right.data, np.uint8).reshape(180, 320, 3)
    both = np.ascontiguousarray(np.concatenate([a, b], axis=1))
    msg = Image(height=180, width=640, encoding='rgb8', is_bigendian=0, step=640 * 3, data=both.tobytes())
    stamp(msg.header, t, 'CameraDepth_optical_frame')
    return msg


def depth_image(i, w=320, h=240, t=0.0):
    """16UC1 millimetres, 0.6-3.6 m across, with a patch without depth (0) in a corner."""
    from sensor_msgs.msg import Image
    y, x = np.mgrid[0:h, 0:w]
    mm = (600 + 3000 * x / (w - 1) + 300 * np.sin(y / 20.0 + i / 5.0)).astype(np.uint16)
    mm[:20, :40] = 0
    msg = Image(height=h, width=w, encoding='16UC1', is_bigendian=0, step=w * 2, data=mm.tobytes())
    stamp(msg.header, t, 'CameraDepth_optical_frame')
    return msg


def audio_buffer(i, n=profiles.AUDIO_BUFFER, rate=profiles.AUDIO_RATE):
    """AudioCustomMsg: one tone per channel, each 10 dB quieter than the one before."""
    from pepper_interface_tests.msg import AudioCustomMsg
    tt = (np.arange(n) + i * n) / float(rate)
    amps = (0.30, 0.10, 0.03, 0.01)
    freqs = (220.0, 330.0, 440.0, 660.0)
    envelope = 0.6 + 0.4 * np.sin(2 * np.pi * 0.5 * tt)
    chans = [(a * 32767 * envelope * np.sin(2 * np.pi * f * tt)).astype(np.int16) for a, f in zip(amps, freqs)]
    return AudioCustomMsg(**{name: c.tolist() for name, c in zip(profiles.MIC_CHANNELS, chans)})
