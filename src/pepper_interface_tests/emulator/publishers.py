"""One publisher thread per sensor stream, on an absolute schedule, with faults applied.

Each `StreamPublisher` owns its rospy publisher(s), its renderer state and its counters; nothing
is shared between threads except the read-only world model (scene.py) and the stop event.
Ticks are scheduled at t0 + k / rate (monotonic clock), so rates do not drift; when a tick is
late by more than one period the missed slots are skipped rather than sent in a burst.
Like naoqi_driver, a stream is only rendered and published while it has a subscriber.
"""
import math
import threading
import time

import numpy as np
import rospy
from geometry_msgs.msg import Quaternion
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Image, Imu, JointState, LaserScan, Range
from std_msgs.msg import String

from . import scene
from .faults import HEALTHY
from .profiles import AUDIO_BUFFER, JOINT_NAMES, LASER_ANGLE, LASER_BEAMS, laser_blind_mask

BYTES_PER_PIXEL = {'rgb8': 3, '16UC1': 2}
WRONG_ENCODING = {'rgb8': 'bgr8', '16UC1': '32FC1'}
BROKEN_QUATERNION_SCALE = 1.8


class Clock(object):
    """Seconds since the emulator started (the scene's time base), monotonic."""

    def __init__(self):
        self.t0 = time.monotonic()

    def now(self):
        return time.monotonic() - self.t0


class StreamPublisher(threading.Thread):
    """Base class: scheduling, faults common to all sensors, publisher life cycle."""

    queue_size = 10

    def __init__(self, spec, faults, clock, stop, rate_factor=1.0, seed=0):
        super().__init__(name='pub-' + spec.name, daemon=True)
        self.spec = spec
        self.faults = faults or HEALTHY
        self.clock = clock
        self.stop = stop
        self.rate = spec.rate * rate_factor * self.faults.rate
        self.rng = np.random.default_rng(seed)
        self.published = 0
        self.dead = False
        self.error = None
        topics = [(spec.topic, spec.frame_id)] + list(spec.extra)
        msg_class = String if self.faults.wrong_type else self.msg_class()
        self.outputs = [(rospy.Publisher(topic, msg_class, queue_size=self.queue_size), frame)
                        for topic, frame in topics]

    # -- to override
    def msg_class(self):
        raise NotImplementedError

    def build(self, t, frame_id, index):
        """The message for output `index` (0 = main topic) at scene time t."""
        raise NotImplementedError

    def always_tick(self, t):
        """Work done on every tick, subscribed or not (the audio stream keeps flowing)."""

    # -- machinery
    def wanted(self):
        return any(pub.get_num_connections() > 0 for pub, _ in self.outputs)

    def tick(self):
        t = self.clock.now()
        self.always_tick(t)
        if self.faults.silent or not self.wanted():
            return
        for index, (pub, frame) in enumerate(self.outputs):
            if self.faults.wrong_type:
                msg = String(data='emulator fault wrong_type: %s should be %s'
                             % (self.spec.name, self.spec.msg_type))
            else:
                msg = self.build(t, frame, index)
                if hasattr(msg, 'header'):
                    msg.header.stamp = rospy.Time.now()
                    msg.header.frame_id = frame
            pub.publish(msg)
        self.published += 1

    def die(self):
        self.dead = True
        for pub, _ in self.outputs:
            pub.unregister()
        rospy.loginfo('pepperEmulator: %s stopped after %.1f s (fault die_after)',
                      self.spec.topic, self.faults.die_after)

    def run(self):
        period = 1.0 / self.rate
        t0 = time.monotonic()
        k = 0
        while not self.stop.is_set():
            delay = t0 + k * period - time.monotonic()
            if delay > 0 and self.stop.wait(delay):
                break
            if self.faults.die_after is not None and time.monotonic() - t0 >= self.faults.die_after:
                self.die()
                return
            try:
                self.tick()
            except Exception as e:     # keep publishing; report each new kind of error once
                if rospy.is_shutdown() or self.stop.is_set():
                    break
                if repr(e) != self.error:
                    self.error = repr(e)
                    rospy.logerr('pepperEmulator: %s: %r', self.spec.topic, e)
            k += 1
            late = time.monotonic() - (t0 + k * period)
            if late > period:
                k += int(late / period)

    def close(self):
        for pub, _ in self.outputs:
            if not self.dead:
                pub.unregister()


# ---------------------------------------------------------------- cameras

class ImagePublisher(StreamPublisher):
    queue_size = 2

    def __init__(self, spec, faults, clock, stop, rate_factor=1.0, seed=0):
        super().__init__(spec, faults, clock, stop, rate_factor, seed)
        if spec.kind == 'depth':
            self.renderer = scene.DepthCamera(spec.width, spec.height, spec.hfov, seed=seed)
        elif spec.kind == 'stereo':
            self.renderer = scene.StereoCamera(spec.width, spec.height, spec.hfov)
        else:
            self.renderer = scene.ColourCamera(spec.width, spec.height, spec.hfov, view=spec.view)
        self.bpp = BYTES_PER_PIXEL[spec.encoding]
        self.cached = None

    def msg_class(self):
        return Image

    def pixels(self, t):
        f = self.faults
        if f.black:
            if self.cached is None:
                shape = (self.spec.height, self.spec.width) + ((3,) if self.bpp == 3 else ())
                self.cached = np.zeros(shape, np.uint8 if self.bpp == 3 else np.uint16).tobytes()
            return self.cached
        if f.frozen:
            if self.cached is None:
                self.cached = self.renderer.render(t).tobytes()
            return self.cached
        return self.renderer.render(t).tobytes()

    def build(self, t, frame_id, index):
        s, f = self.spec, self.faults
        msg = Image()
        msg.height, msg.width = s.height, s.width
        msg.encoding = WRONG_ENCODING[s.encoding] if f.wrong_encoding else s.encoding
        msg.is_bigendian = 0
        msg.step = s.width * self.bpp
        if f.wrong_step:
            msg.step = s.width * self.bpp // 2
        msg.data = self.pixels(t)
        return msg


# ---------------------------------------------------------------- range sensors

class LaserPublisher(StreamPublisher):
    def __init__(self, *a, **kw):
        super().__init__(*a, **kw)
        self.blind = laser_blind_mask()
        self.increment = 2 * LASER_ANGLE / (LASER_BEAMS - 1)

    def msg_class(self):
        return LaserScan

    def build(self, t, frame_id, index):
        s, f = self.spec, self.faults
        ranges = scene.laser_ranges(t, -LASER_ANGLE, self.increment, LASER_BEAMS, self.blind,
                                    s.range_min, s.range_max, self.rng)
        valid = ~np.asarray(self.blind)
        if f.nan:
            ranges[valid] = np.nan
        if f.out_of_range:
            idx = np.flatnonzero(valid)
            ranges[idx[0::2]] = s.range_max + 2.0
            ranges[idx[1::2]] = s.range_min / 2.0
        msg = LaserScan()
        msg.angle_min, msg.angle_max = -LASER_ANGLE, LASER_ANGLE
        msg.angle_increment = self.increment
        msg.time_increment = 0.0
        msg.scan_time = 1.0 / s.rate
        msg.range_min, msg.range_max = s.range_min, s.range_max
        msg.ranges = ranges.tolist()
        return msg


class SonarPublisher(StreamPublisher):
    def msg_class(self):
        return Range

    def build(self, t, frame_id, index):
        s, f = self.spec, self.faults
        msg = Range()
        msg.radiation_type = Range.ULTRASOUND
        msg.field_of_view = s.field_of_view
        msg.min_range, msg.max_range = s.range_min, s.range_max
        msg.range = scene.sonar_range(t, s.name == 'backSonar', s.range_min, s.range_max, self.rng)
        if f.nan:
            msg.range = float('nan')
        elif f.out_of_range:
            msg.range = s.range_max + 1.5 if (self.published % 2 == 0 or s.range_min <= 0) \
                else s.range_min / 2.0
        return msg


# ---------------------------------------------------------------- body

def _quaternion(yaw, broken):
    x, y, z, w = scene.yaw_quaternion(yaw)
    k = BROKEN_QUATERNION_SCALE if broken else 1.0
    return Quaternion(x * k, y * k, z * k, w * k)


class OdometryPublisher(StreamPublisher):
    def msg_class(self):
        return Odometry

    def build(self, t, frame_id, index):
        f = self.faults
        x, y, yaw = scene.robot_pose(t)
        msg = Odometry()
        msg.child_frame_id = self.spec.child_frame_id
        msg.pose.pose.position.x = float('nan') if f.nan else x
        msg.pose.pose.position.y = y
        msg.pose.pose.orientation = _quaternion(yaw, f.broken_quaternion)
        msg.twist.twist.linear.x = float('nan') if f.nan else scene.LINEAR_SPEED
        msg.twist.twist.angular.z = scene.ANGULAR_SPEED
        return msg


class ImuPublisher(StreamPublisher):
    def msg_class(self):
        return Imu

    def build(self, t, frame_id, index):
        f = self.faults
        _, _, yaw = scene.robot_pose(t)
        n = self.rng.normal(0.0, 1.0, 6)
        msg = Imu()
        msg.orientation = _quaternion(yaw, f.broken_quaternion)
        msg.angular_velocity.x = 0.002 * n[0]
        msg.angular_velocity.y = 0.002 * n[1]
        msg.angular_velocity.z = scene.ANGULAR_SPEED + 0.002 * n[2]
        # specific force: gravity up, centripetal acceleration towards the circle's centre (+y)
        msg.linear_acceleration.x = 0.02 * n[3]
        msg.linear_acceleration.y = scene.LINEAR_SPEED * scene.ANGULAR_SPEED + 0.02 * n[4]
        msg.linear_acceleration.z = scene.GRAVITY + 0.02 * n[5]
        if f.nan:
            msg.angular_velocity.z = float('nan')
            msg.linear_acceleration.z = float('nan')
        return msg


# standing pose (rad; hands 0..1 open)
_POSE = {'HeadYaw': 0.0, 'HeadPitch': -0.2, 'HipRoll': 0.0, 'HipPitch': -0.03, 'KneePitch': 0.0,
         'LShoulderPitch': 1.56, 'LShoulderRoll': 0.14, 'LElbowYaw': -1.22, 'LElbowRoll': -0.52,
         'LWristYaw': -0.86, 'LHand': 0.6, 'RShoulderPitch': 1.56, 'RShoulderRoll': -0.14,
         'RElbowYaw': 1.22, 'RElbowRoll': 0.52, 'RWristYaw': 0.86, 'RHand': 0.6}
_OUT_OF_RANGE = {'HeadYaw': 4.0, 'KneePitch': -3.0, 'LHand': 1.8}     # beyond Pepper's limits
_WHEEL_RADIUS, _WHEEL_BASE = 0.07, 0.2


class JointStatePublisher(StreamPublisher):
    def __init__(self, *a, **kw):
        super().__init__(*a, **kw)
        n = len(_POSE)
        self.amp = 0.02 + 0.08 * self.rng.random(n)
        self.freq = 0.1 + 0.3 * self.rng.random(n)
        self.phase = 2 * math.pi * self.rng.random(n)
        self.pose = np.array([_POSE[j] for j in JOINT_NAMES if j in _POSE])

    def msg_class(self):
        return JointState

    def build(self, t, frame_id, index):
        f = self.faults
        w = 2 * math.pi * self.freq
        pos = self.pose + self.amp * np.sin(w * t + self.phase)
        vel = self.amp * w * np.cos(w * t + self.phase)
        eff = 0.05 * np.sin(w * t + self.phase + 1.0) + 0.01
        wheel_v = np.array([(scene.LINEAR_SPEED - scene.ANGULAR_SPEED * _WHEEL_BASE),
                            -(scene.LINEAR_SPEED + scene.ANGULAR_SPEED * _WHEEL_BASE),
                            scene.ANGULAR_SPEED * _WHEEL_BASE]) / _WHEEL_RADIUS
        positions = np.concatenate([pos, np.mod(wheel_v * t + math.pi, 2 * math.pi) - math.pi])
        velocities = np.concatenate([vel, wheel_v])
        efforts = np.concatenate([eff, [0.3, 0.3, 0.2]])
        names = list(JOINT_NAMES)
        if f.nan:
            for j in ('HeadPitch', 'LElbowRoll'):
                positions[names.index(j)] = np.nan
        if f.out_of_range:
            for j, v in _OUT_OF_RANGE.items():
                positions[names.index(j)] = v
        msg = JointState()
        msg.name = names
        msg.position = positions.tolist()
        msg.velocity = velocities.tolist()
        msg.effort = efforts.tolist()
        return msg


# ---------------------------------------------------------------- microphones (direct mode)

class AudioPublisher(StreamPublisher):
    """AudioCustomMsg from an AudioSource, 4096 samples per channel per message, real time."""

    def __init__(self, spec, faults, clock, stop, rate_factor=1.0, seed=0, source=None):
        super().__init__(spec, faults, clock, stop, rate_factor, seed)
        self.source = source

    def msg_class(self):
        from pepper_interface_tests.msg import AudioCustomMsg
        return AudioCustomMsg

    def always_tick(self, t):
        self.block = self.source.read(AUDIO_BUFFER)

    def build(self, t, frame_id, index):
        b = self.block
        cls = self.msg_class()
        return cls(rearLeft=b[:, 0].tolist(), rearRight=b[:, 1].tolist(),
                   frontLeft=b[:, 2].tolist(), frontRight=b[:, 3].tolist())


KINDS = {'camera': ImagePublisher, 'depth': ImagePublisher, 'stereo': ImagePublisher,
         'laser': LaserPublisher, 'sonar': SonarPublisher, 'odometry': OdometryPublisher,
         'imu': ImuPublisher, 'joints': JointStatePublisher, 'audio': AudioPublisher}
