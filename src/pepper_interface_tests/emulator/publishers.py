"""One publisher thread per sensor stream, on an absolute schedule, with faults applied.

Each `StreamPublisher` owns its rospy publisher(s), its renderer state and its counters; the
threads share the read-only world model (scene.py), the robot's body (body.py: one state under
a lock, which the motion commands change) and the stop event.
Ticks are scheduled at t0 + k / rate (monotonic clock), so rates do not drift; when a tick is
late by more than one period the missed slots are skipped rather than sent in a burst.
Like naoqi_driver, a stream is only rendered and published while it has a subscriber.
Under sim time (simulator profile) the scene runs on the simulated clock: a stream's nominal
rate is per simulated second, so it arrives at rate x real-time factor per wall second, and
every header stamp is the simulated time (the /clock the emulator publishes).
"""
import math
import threading
import time
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Tuple, Type

import genpy
import numpy as np

from .. import rosapi
from ..genmsgs import Image, Imu, JointState, LaserScan, Odometry, Quaternion, Range, String
from ..media import encodings
from . import camera_info, qos2, scene
from .body import Body, Snapshot
from .faults import HEALTHY, LASER_BOARDS, Faults
from .profiles import (
    AUDIO_RATE,
    JOINT_NAMES,
    JOINTS_WITHOUT_VELOCITY,
    LASER_ANGLE,
    LASER_BLIND_VALUE,
    LASER_INCREMENT,
    SIM_LASER_ANGLE,
    SIM_LASER_SLOTS,
    SensorSpec,
    laser_blind_mask,
)

if TYPE_CHECKING:
    from .audio_source import AudioSource
    from .network import Network


LOADED_CAMERA_HZ = 1.3
DARK_FACTOR = 0.12                 # a dark room: colour images at about an eighth of the light
BROKEN_QUATERNION_SCALE = 1.8


class Clock:
    """Seconds since the emulator started (the scene's time base), monotonic.

    Wall clock (rtf None): stamps are the node's now(), as naoqi_driver's ros::Time::now().
    Sim clock (rtf given): simulated seconds advance rtf times as fast as the wall clock and
    start at SIM_START, like Gazebo's; stamps are that simulated time."""

    SIM_START = 0.001

    def __init__(self, rtf: Optional[float] = None) -> None:
        self.t0 = time.monotonic()
        self.rtf = rtf
        self.sim = rtf is not None
        self.speed = rtf if rtf is not None else 1.0

    def now(self) -> float:
        return (time.monotonic() - self.t0) * self.speed + (self.SIM_START if self.sim else 0.0)

    def stamp(self) -> genpy.Time:
        return genpy.Time.from_sec(self.now()) if self.sim else rosapi.now()


class Schedule:
    """Ticks at t0 + k * period (monotonic clock): the time spent publishing does not slow the
    rate; a tick late by more than a period skips the missed slots instead of a burst."""

    def __init__(self, period: float, catch_up: bool = False) -> None:
        self.period = period
        self.t0 = time.monotonic()
        self.k = 0
        self.catch_up = catch_up     # a late tick sends the missed slots at once (held audio)

    def delay(self) -> float:
        """Seconds until the next tick is due (negative: late)."""
        return self.t0 + self.k * self.period - time.monotonic()

    def advance(self) -> None:
        self.k += 1
        late = -self.delay()
        if late > self.period and not self.catch_up:
            self.k += int(late / self.period)


class ClockPublisher(threading.Thread):
    """/clock (rosgraph_msgs/Clock) at CLOCK_HZ of wall time.

    Gazebo publishes /clock at every world update, i.e. every physics step (1 kHz of simulated
    time by default), throttled to ~pub_clock_frequency per simulated second only when that is set
    (gazebo_ros_pkgs gazebo_ros/src/gazebo_ros_api_plugin.cpp publishSimTime; empty_world.launch
    sets it only with use_clock_frequency:=true, pub_clock_frequency 100). The emulator ticks
    coarser, 100 times per wall second, so a subscriber's ROS time moves in steps of 10 ms x the
    real-time factor: fine enough for rates and windows, and light on a shared machine."""

    CLOCK_HZ = 100.0

    def __init__(self, clock: Clock, stop: threading.Event) -> None:
        super().__init__(name='pub-clock', daemon=True)
        self.clock, self.stop = clock, stop
        self.msg_class = rosapi.msg('rosgraph_msgs/Clock')
        self.pub = rosapi.publisher('/clock', 'rosgraph_msgs/Clock', queue_size=10)
        self.published = 0

    def run(self) -> None:
        ticks = Schedule(1.0 / self.CLOCK_HZ)
        ticks.advance()                           # the first tick one period after the start
        while not self.stop.wait(max(0.0, ticks.delay())):
            try:
                self.pub.publish(self.msg_class(clock=self.clock.stamp()))
                self.published += 1
            except Exception:
                if rosapi.is_shutdown() or self.stop.is_set():
                    break
            ticks.advance()

    def close(self) -> None:
        self.pub.unregister()


class StreamPublisher(threading.Thread):
    """Base class: scheduling, faults common to all sensors, publisher life cycle."""

    queue_size = 10
    # under the `network` condition: what was held is sent at once when the hold ends (audio
    # buffers: a stream), instead of fetched once, late (a frame, an ALMemory value)
    held_catch_up = False

    def __init__(self, spec: SensorSpec, faults: Optional[Faults], clock: 'Clock', stop: threading.Event,
                 rate_factor: float = 1.0, seed: int = 0, condition: str = 'normal') -> None:
        super().__init__(name='pub-' + spec.name, daemon=True)
        self.spec = spec
        self.faults = faults or HEALTHY
        self.clock = clock
        self.stop = stop
        self.condition = condition
        nominal = spec.rate
        self.jitter = 0.0
        if condition == 'loaded' and spec.is_image:
            # a busy robot: naoqi_driver's cameras drop to ~1.3 fps with irregular gaps
            # (measured in the D4.1 report, docs/reference pepper-sensors.md)
            nominal, self.jitter = LOADED_CAMERA_HZ, 0.4
        self.rate = nominal * rate_factor * self.faults.rate * clock.speed
        self.rng = np.random.default_rng(seed)
        self.published = 0
        self.dead = False
        self.error: Optional[str] = None
        self.first_wanted: Optional[float] = None    # scene time of the first tick with a subscriber
        self.stuck_msgs: Dict[int, genpy.Message] = {}   # output index -> the message republished by the fault stuck
        topics = [(spec.topic, spec.frame_id)] + list(spec.extra)
        msg_class: Any = String if self.faults.wrong_type else self.msg_class()
        # on ROS 2 the queue is the QoS depth a subscriber sees offered: naoqi_driver2's (qos2.py)
        depth = qos2.depth(spec.family) if rosapi.version() == 2 else self.queue_size
        self.outputs = [(rosapi.publisher(topic, msg_class._type, queue_size=depth, cls=msg_class),
                         frame) for topic, frame in topics]
        self.body: Optional[Body] = None     # the robot's body, shared (node.py); own one if unset
        # the `network` condition (network.py): what naoqi_driver fetches waits for its holds
        self.network: Optional[Network] = None
        self.first: Optional[Snapshot] = None    # the body at this stream's first message

    def snapshot(self, t: float) -> Snapshot:
        """The body at scene time t (and, once, kept as the stream's first: frozen faults)."""
        if self.body is None:
            self.body = Body(idle=self.condition != 'still')
        snap = self.body.snapshot(t)
        if self.first is None:
            self.first = snap
        return snap

    # -- to override
    def msg_class(self) -> type:
        raise NotImplementedError

    def build(self, t: float, frame_id: str, index: int) -> 'genpy.Message':
        """The message for output `index` (0 = main topic) at scene time t."""
        raise NotImplementedError

    def always_tick(self, t: float) -> None:
        """Work done on every tick, subscribed or not (the audio stream keeps flowing)."""

    # -- machinery
    def wanted(self) -> bool:
        return any(pub.get_num_connections() > 0 for pub, _ in self.outputs)

    def partial_on(self, t: float) -> bool:
        """True once a partial fault (stuck, frozen, black, silent_channel) is in force: at
        once, or with after=T from T s after the stream's first subscriber."""
        after = self.faults.after
        if after is None:
            return True
        return self.first_wanted is not None and t - self.first_wanted >= after

    def tick(self) -> None:
        t = self.clock.now()
        self.always_tick(t)
        if self.faults.silent or not self.wanted():
            return
        if self.first_wanted is None:
            self.first_wanted = t
        stuck = self.faults.stuck and self.partial_on(t)
        for index, (pub, frame) in enumerate(self.outputs):
            if self.faults.wrong_type:
                msg = String(data='emulator fault wrong_type: %s should be %s'
                             % (self.spec.name, self.spec.msg_type))
            else:
                if stuck and index in self.stuck_msgs:
                    msg = self.stuck_msgs[index]    # a driver republishing its last reading
                else:
                    msg = self.build(t, frame, index)
                    if stuck:
                        self.stuck_msgs[index] = msg
                if hasattr(msg, 'header'):      # the stamps keep moving, as naoqi_driver's
                    msg.header.stamp = self.clock.stamp()
                    if self.faults.clock_offset:    # a sensor on another clock
                        msg.header.stamp += genpy.Duration.from_sec(self.faults.clock_offset)
                    msg.header.frame_id = frame
            pub.publish(msg)
            self.sent(index, msg)
        self.published += 1

    def sent(self, index: int, msg: 'genpy.Message') -> None:
        """Output `index` has just published `msg` (the joint states hand it to the tree)."""

    def die(self) -> None:
        self.dead = True
        for pub, _ in self.outputs:
            pub.unregister()
        rosapi.loginfo('pepperEmulator: %s stopped after %.1f s (fault die_after)',
                      self.spec.topic, self.faults.die_after)

    def run(self) -> None:
        ticks = Schedule(1.0 / self.rate, catch_up=self.network is not None and self.held_catch_up)
        while not self.stop.is_set():
            delay = ticks.delay()
            if self.jitter:
                delay += self.jitter * ticks.period * (self.rng.random() - 0.5)
            if delay > 0 and self.stop.wait(delay):
                break
            held = self.network.wait(time.monotonic()) if self.network is not None else 0.0
            if held > 0 and self.stop.wait(held):     # the fetch waits for the network
                break
            if self.faults.die_after is not None and \
                    (time.monotonic() - ticks.t0) * self.clock.speed >= self.faults.die_after:
                self.die()
                return
            try:
                self.tick()
            except Exception as e:     # keep publishing; report each new kind of error once
                if rosapi.is_shutdown() or self.stop.is_set():
                    break
                if repr(e) != self.error:
                    self.error = repr(e)
                    rosapi.logerr('pepperEmulator: %s: %r', self.spec.topic, e)
            ticks.advance()

    def close(self) -> None:
        for pub, _ in self.outputs:
            if not self.dead:
                pub.unregister()


# ---------------------------------------------------------------- cameras

class ImagePublisher(StreamPublisher):
    queue_size = 2

    def __init__(self, spec: SensorSpec, faults: Optional[Faults], clock: 'Clock', stop: threading.Event,
                 rate_factor: float = 1.0, seed: int = 0, condition: str = 'normal') -> None:
        super().__init__(spec, faults, clock, stop, rate_factor, seed, condition)
        # the encoding's row (media/encodings.py): its bytes, and how a camera of it is drawn
        self.enc = encodings.ENCODINGS[spec.encoding]
        infrared = spec.family != 'depth' and self.enc.render == 'infrared'
        # a dark room: the colour cameras; depth and infrared light the scene themselves
        self.dark = condition == 'dark' and spec.family != 'depth' and not infrared
        self.renderer: Any
        if spec.family == 'depth':
            self.renderer = scene.DepthCamera(spec.width, spec.height, spec.hfov, seed=seed)
        elif infrared:
            self.renderer = scene.InfraredCamera(spec.width, spec.height, spec.hfov, view=spec.view)
        elif spec.view == 'stereo':
            self.renderer = scene.StereoCamera(spec.width, spec.height, spec.hfov)
        else:
            self.renderer = scene.ColourCamera(spec.width, spec.height, spec.hfov, view=spec.view)
        self.bpp = self.enc.bytes_per_pixel
        self.cached: Optional[bytes] = None
        # on ROS 2, naoqi_driver2's camera_info beside the image (camera_info.py)
        self.info = camera_info.sender_for(spec.topic, spec.view, spec.width, spec.height, spec.frame_id) \
            if rosapi.version() == 2 else None

    # wanted(): the image topic's subscribers alone, as naoqi_driver2 2.1.2 converts a camera
    # (src/publishers/camera.hpp:57-64 counts the image topic's subscribers, not image_transport's
    # camera publisher's): a camera_info subscriber alone gets nothing (the golden `audio`
    # recording's first take: 0 camera_info messages in 4 s)

    def sent(self, index: int, msg: 'genpy.Message') -> None:
        if index == 0 and self.info is not None and hasattr(msg, 'header'):
            self.info.send(msg.header.stamp)

    def close(self) -> None:
        super().close()
        if self.info is not None:
            self.info.close()

    def msg_class(self) -> type:
        return Image

    def pixels(self, t: float) -> bytes:
        f = self.faults
        if f.black and self.partial_on(t):
            if self.cached is None:
                self.cached = bytes(self.spec.height * self.spec.width * self.bpp)
            return self.cached
        if f.frozen and self.partial_on(t):
            if self.cached is None:
                self.cached = self.render(t).tobytes()
            return self.cached
        img = self.render(t)
        if self.dark:
            img = (img * DARK_FACTOR).astype(img.dtype)
        if f.dim is not None:       # a dusty lens lets less light through
            img = np.clip(img * f.dim, 0, encodings.full_scale(self.enc)).astype(img.dtype)
        if f.blur:                  # out of focus: each pixel the mean of its 5 x 5 neighbours
            img = _box_blur(img)
        if f.far_depth:         # every pixel ~20 m: beyond what the camera measures
            img = (20000 + img % 100).astype(img.dtype)
        elif f.flat_depth:      # one value everywhere, no noise, no floor
            img = np.full_like(img, 1500)
        return img.tobytes()

    def render(self, t: float) -> np.ndarray:
        """The picture from the head: the base's position, looking along base yaw + HeadYaw
        (every camera of the emulator sits in the head). not_following: the view of the first
        frame for ever, the picture otherwise live (a feed that does not follow the head)."""
        snap = self.snapshot(t)
        if self.faults.not_following:
            snap = self.first or snap
        view = (snap.x, snap.y, snap.view_yaw)
        if self.spec.family == 'depth':
            return self.renderer.render(t, view, self.body.circles() if self.body else ())
        return self.renderer.render(t, view=view)

    def build(self, t: float, frame_id: str, index: int) -> 'genpy.Message':
        s, f = self.spec, self.faults
        msg = Image()
        msg.height, msg.width = s.height, s.width
        msg.encoding = self.enc.mislabel if f.wrong_encoding else s.encoding
        msg.is_bigendian = 0
        msg.step = s.width * self.bpp
        if f.wrong_step:
            msg.step = s.width * self.bpp // 2
        msg.data = self.pixels(t)
        return msg


SCRATCHED_SHARE = 0.35     # laser:scratched: the share of a board's points lost in each scan


def _box_blur(img: np.ndarray, k: int = 5) -> np.ndarray:
    """A k x k box blur (separable, edge pixels repeated), the image's dtype kept."""
    out = img.astype(np.float32)
    pad = k // 2
    for axis in (0, 1):
        widths = [(0, 0)] * out.ndim
        widths[axis] = (pad, pad)
        padded = np.pad(out, widths, mode='edge')
        c = np.cumsum(padded, axis=axis, dtype=np.float32)
        c = np.concatenate([np.zeros_like(np.take(c, [0], axis=axis)), c], axis=axis)
        n = out.shape[axis]
        out = (np.take(c, range(k, k + n), axis=axis) - np.take(c, range(0, n), axis=axis)) / k
    return out.astype(img.dtype)


# ---------------------------------------------------------------- range sensors

class LaserPublisher(StreamPublisher):
    """naoqi_driver's 61-slot scan or the simulator's 488-slot /pepper/laser_2 (spec.layout).

    In Rest mode (~condition resting or robot:resting; naoqi_driver's layout only), its
    laser boards do not sample (yohatad/naoqi_driver2 src/converters/laser.hpp:72-75) and stock
    naoqi_driver reads the same last values from ALMemory at every tick and stamps them with the
    current time (ros-naoqi/naoqi_driver src/converters/laser.cpp:148, :154): the first scan's
    ranges are published for ever, with fresh stamps."""

    def __init__(self, spec: SensorSpec, faults: Optional[Faults], clock: 'Clock', stop: threading.Event,
                 rate_factor: float = 1.0, seed: int = 0, condition: str = 'normal') -> None:
        super().__init__(spec, faults, clock, stop, rate_factor, seed, condition)
        self.blind = np.asarray(laser_blind_mask())
        self.rested: Optional[List[float]] = None     # the boards' last values while resting

    def msg_class(self) -> type:
        return LaserScan

    def naoqi_ranges(self, t: float) -> Tuple[np.ndarray, float, float, float]:
        """laser.cpp:165-205: each measured slot is the raw distance of one device's point
        converted to base_footprint (scene.laser_ranges), never clipped to range_max; the blind
        slots keep -1.0 (reset(), :221)."""
        f = self.faults
        dead = LASER_BOARDS.index(f.dead_board) if f.dead_board else None
        snap = self.snapshot(t)
        pose, circles = (snap.x, snap.y, snap.yaw), self.body.circles() if self.body else ()
        ranges = scene.laser_ranges(t, self.blind, self.spec.noise, self.rng, dead, pose, circles)
        if f.scratched:       # a scratched window: a third of the board's points lost, each scan
            # a lost point reads x = y = 0 in ALMemory, as a stopped board's (laser.cpp:170-171)
            board = LASER_BOARDS.index(f.scratched)
            lost = scene.laser_ranges(t, self.blind, self.spec.noise, self.rng, board, pose, circles)
            slots = np.flatnonzero(~self.blind)[board * 15:(board + 1) * 15]
            hit = slots[self.rng.random(15) < SCRATCHED_SHARE]
            ranges[hit] = lost[hit]
        if f.nan_board:       # yohatad/naoqi_driver2: kUnknownRange in a stopped board's slots
            board = LASER_BOARDS.index(f.nan_board)
            ranges[np.flatnonzero(~self.blind)[board * 15:(board + 1) * 15]] = np.nan
        if f.all_blind:
            ranges[:] = LASER_BLIND_VALUE
        return ranges, -LASER_ANGLE, LASER_ANGLE, LASER_INCREMENT

    def gazebo_ranges(self, t: float) -> Tuple[np.ndarray, float, float, float]:
        """laser_publisher.py:293-395, 424-497: the 45 points of three 15-ray lasers, in
        base_footprint, each written into the slot of its own angle; every other slot NaN."""
        s = self.spec
        increment = 2 * SIM_LASER_ANGLE / SIM_LASER_SLOTS
        ranges = np.full(SIM_LASER_SLOTS, np.nan, dtype=np.float32)
        if not self.faults.no_returns:
            snap = self.snapshot(t)
            dist, angle = scene.gazebo_laser_points(t, s.noise, self.rng, (snap.x, snap.y, snap.yaw),
                                                    self.body.circles() if self.body else ())
            ok = ~np.isnan(angle)       # a ray with no hit: no point (laser_publisher.py:464-477)
            idx = np.clip(((angle[ok] + SIM_LASER_ANGLE) / increment).astype(int), 0,
                          SIM_LASER_SLOTS - 1)
            ranges[idx] = dist[ok]
        if self.faults.all_blind:
            ranges[:] = np.nan
        return ranges, -SIM_LASER_ANGLE, SIM_LASER_ANGLE, increment

    def build(self, t: float, frame_id: str, index: int) -> 'genpy.Message':
        s, f = self.spec, self.faults
        if s.layout == 'gazebo':
            ranges, a_min, a_max, inc = self.gazebo_ranges(t)
            valid = ~np.isnan(ranges)
        else:
            ranges, a_min, a_max, inc = self.naoqi_ranges(t)
            valid = ~self.blind
        if f.nan:
            ranges[valid] = np.nan
        if f.out_of_range:
            idx = np.flatnonzero(valid)
            ranges[idx[0::2]] = -5.0
            ranges[idx[1::2]] = 0.0
        if f.reversed:          # the beams stored left first: the scan turns the wrong way
            ranges = ranges[::-1].copy()
        msg = LaserScan()
        msg.angle_min, msg.angle_max = a_min, a_max
        msg.angle_increment = inc
        # naoqi_driver and laser_publisher.py leave time_increment and scan_time at 0
        msg.range_min, msg.range_max = s.range_min, s.range_max
        msg.ranges = ranges.tolist()
        if s.layout != 'gazebo' and self.snapshot(t).stiffness == 0.0:   # Rest mode (the body)
            if self.rested is None:
                self.rested = list(msg.ranges)
            msg.ranges = list(self.rested)
        return msg


class SonarPublisher(StreamPublisher):
    def msg_class(self) -> type:
        return Range

    def build(self, t: float, frame_id: str, index: int) -> 'genpy.Message':
        s, f = self.spec, self.faults
        msg = Range()
        msg.radiation_type = Range.ULTRASOUND
        msg.field_of_view = s.field_of_view
        msg.min_range, msg.max_range = s.range_min, s.range_max
        back = s.name == 'backSonar'
        snap = self.snapshot(t)
        pose = (snap.x, snap.y, snap.yaw)
        circles = self.body.circles() if self.body else ()
        gx, g0, g1 = scene.GLASS_PANE        # behind the start pose for the back sonar
        panes = (((-gx if back else gx), g0, g1),) if f.glass else ()
        if s.layout == 'gazebo':
            msg.range = scene.gazebo_sonar_range(t, back, s.range_max, s.noise, self.rng, pose, circles, panes)
        else:
            msg.range = scene.sonar_range(t, back, s.noise * (4 if f.noisy else 1), self.rng, pose, circles, panes)
        if f.nan:
            msg.range = float('nan')
        elif f.out_of_range:
            msg.range = -1.0 if self.published % 2 == 0 else 50.0
        return msg


# ---------------------------------------------------------------- body

def _quaternion(yaw: float, broken: bool) -> Any:
    x, y, z, w = scene.yaw_quaternion(yaw)
    k = BROKEN_QUATERNION_SCALE if broken else 1.0
    return Quaternion(x * k, y * k, z * k, w * k)


class OdometryPublisher(StreamPublisher):
    def msg_class(self) -> type:
        return Odometry

    def build(self, t: float, frame_id: str, index: int) -> 'genpy.Message':
        f = self.faults
        snap = self.snapshot(t)
        if f.frozen_pose:       # the pose of the first message, standing still, whatever the wheels do
            first = self.first or snap
            snap = Snapshot(snap.t, first.x, first.y, first.yaw, 0.0, 0.0, 0.0, 0.0, 0.0,
                            snap.joints, snap.joint_velocities, snap.wheels, snap.wheel_velocities,
                            snap.stiffness)
        # odom.cpp:56-93: getPosition("Torso", FRAME_WORLD) and getRobotVelocity (base frame)
        x, y, yaw = snap.x, snap.y, snap.yaw
        if f.pose_jump:     # an odometry that jumps 1 m every 2 s
            x += float(int(t / 2.0))
        if f.spike and self.published % 8 == 7:     # one pose in eight 25 m away, then back
            x += 25.0
        msg = Odometry()
        msg.child_frame_id = self.spec.child_frame_id
        msg.pose.pose.position.x = float('nan') if f.nan else x
        msg.pose.pose.position.y = y
        msg.pose.pose.orientation = _quaternion(yaw, f.broken_quaternion)
        msg.twist.twist.linear.x = float('nan') if f.nan else (0.4 if f.twist_mismatch else snap.vx)
        msg.twist.twist.linear.y = snap.vy
        msg.twist.twist.angular.z = snap.wz
        return msg


class ImuPublisher(StreamPublisher):
    def msg_class(self) -> type:
        return Imu

    def build(self, t: float, frame_id: str, index: int) -> 'genpy.Message':
        f = self.faults
        snap = self.snapshot(t)
        yaw = snap.yaw
        n = self.rng.normal(0.0, 1.0, 6)
        msg = Imu()
        # imu.cpp:106-126: orientation from AngleX/Y/Z, gyroscope, accelerometer (gravity
        # included: the robot stands, so +g on z), and covariance[0] = -1 ("unknown") for all three
        msg.orientation = _quaternion(yaw, f.broken_quaternion)
        msg.orientation_covariance[0] = -1.0
        msg.angular_velocity_covariance[0] = -1.0
        msg.linear_acceleration_covariance[0] = -1.0
        if f.nan_attitude:
            msg.orientation = Quaternion(float('nan'), float('nan'), float('nan'), float('nan'))
        msg.angular_velocity.x = 0.002 * n[0]
        msg.angular_velocity.y = 0.002 * n[1]
        msg.angular_velocity.z = snap.wz + 0.002 * n[2]
        # specific force in the base frame: gravity up, the base's acceleration and the
        # centripetal term of a turning drive (body.py)
        msg.linear_acceleration.x = snap.ax + 0.02 * n[3]
        msg.linear_acceleration.y = snap.ay + 0.02 * n[4]
        msg.linear_acceleration.z = scene.GRAVITY + 0.02 * n[5]
        if f.dead_accelerometer:
            msg.linear_acceleration.x = msg.linear_acceleration.y = msg.linear_acceleration.z = 0.0
        g, a = msg.angular_velocity, msg.linear_acceleration
        if f.dead_gyro:         # a gyrometer that reads nothing
            g.x = g.y = g.z = 0.0
        if f.gyro_inverted:     # the rates of the opposite sign: a turn left reads as a turn right
            g.x, g.y, g.z = -g.x, -g.y, -g.z
        if f.swapped_axes:      # x and z exchanged: a turn about z seen on x, gravity on x
            g.x, g.z = g.z, g.x
            a.x, a.z = a.z, a.x
        if f.gyro_overrange:
            msg.angular_velocity.z = 12.0 + 0.002 * n[2]
        if f.gyro_bias is not None:
            msg.angular_velocity.x += f.gyro_bias
        if f.nan:
            msg.angular_velocity.z = float('nan')
            msg.linear_acceleration.z = float('nan')
        return msg


_OUT_OF_RANGE = {'HeadYaw': 4.0, 'KneePitch': -3.0, 'LHand': 1.8}     # beyond Pepper's limits


class JointStatePublisher(StreamPublisher):
    """joint_state.cpp:87-137: getAngles("Body", useSensors=true), in getBodyNames("Body")'s
    order; the body's 17 joints and its three wheels (body.py). With `tree` set (the emulator's
    /tf, tf_publisher.py) each message also goes out as the tree at its positions and stamp,
    whoever listens, as the driver's loop does (joint_state.cpp:54-58, 199-202)."""

    tree: Any = None

    def wanted(self) -> bool:
        return self.tree is not None or super().wanted()

    def sent(self, index: int, msg: 'genpy.Message') -> None:
        if self.tree is not None and index == 0:
            self.tree.send(msg)

    def msg_class(self) -> type:
        return JointState

    def build(self, t: float, frame_id: str, index: int) -> 'genpy.Message':
        f = self.faults
        snap = self.snapshot(t)
        first = self.first or snap
        positions = np.array([snap.joints[j] if j in snap.joints else snap.wheels[j] for j in JOINT_NAMES])
        velocities = np.array([snap.joint_velocities[j] if j in snap.joint_velocities
                               else snap.wheel_velocities[j] for j in JOINT_NAMES])
        eff = 0.05 * np.sin(2 * math.pi * 0.2 * t + np.arange(len(JOINT_NAMES))) + 0.01
        efforts = np.where([j in snap.joints for j in JOINT_NAMES], eff, 0.3)
        if f.noisy:        # worn encoders: 0.002 rad of noise on every joint but the wheels
            arm = np.array([j in snap.joints for j in JOINT_NAMES])
            positions = positions + np.where(arm, self.rng.normal(0.0, 0.002, positions.shape), 0.0)
        names = list(JOINT_NAMES)
        if f.nan:
            for j in ('HeadPitch', 'LElbowRoll'):
                positions[names.index(j)] = np.nan
        if f.out_of_range:
            for j, v in _OUT_OF_RANGE.items():
                positions[names.index(j)] = v
        if f.joint_jump:    # within HeadYaw's limits, but 4 rad in 0.25 s: an encoder jumping
            positions[names.index('HeadYaw')] = 2.0 if int(t / 0.25) % 2 else -2.0
        if f.stuck_joint:   # an encoder that reads its first angle whatever the joint does
            i = names.index(f.stuck_joint)
            positions[i] = first.joints[f.stuck_joint] if f.stuck_joint in first.joints \
                else first.wheels[f.stuck_joint]
            velocities[i] = 0.0
        # joint_state.cpp:120-133: NaN velocity and effort where ALMemory has no value
        for j in (JOINTS_WITHOUT_VELOCITY if self.spec.layout != 'gazebo' else ()):
            velocities[names.index(j)] = np.nan
            efforts[names.index(j)] = np.nan
        msg = JointState()
        msg.name = names
        msg.position = positions.tolist()
        msg.velocity = velocities.tolist()
        msg.effort = efforts.tolist()
        return msg


# ---------------------------------------------------------------- microphones

class AudioPublisher(StreamPublisher):
    """AudioCustomMsg from an AudioSource (the CSSR fork's bridge: four int16 arrays of
    spec.width samples each, cssr4africa/naoqi_driver scripts/naoqiAudioPublisher.py:15-34)."""

    held_catch_up = True

    def __init__(self, spec: SensorSpec, faults: Optional[Faults], clock: 'Clock', stop: threading.Event,
                 rate_factor: float = 1.0, seed: int = 0, condition: str = 'normal',
                 source: Optional['AudioSource'] = None) -> None:
        if source is None:
            raise ValueError('%s: an AudioPublisher needs an AudioSource' % spec.name)
        super().__init__(spec, faults, clock, stop, rate_factor, seed, condition)
        self.source = source

    def msg_class(self) -> type:
        from pepper_interface_tests.msg import AudioCustomMsg
        return AudioCustomMsg

    def always_tick(self, t: float) -> None:
        self.block = self.source.read(self.spec.width)

    def data_block(self, t: float) -> np.ndarray:
        """This tick's samples (n, 4), with after=T's silent channels zeroed from T on, and a
        broken bridge's channels (sensors/channels.py): copied_channels puts rearLeft's samples
        in all four; planar_as_interleaved takes NAOqi's buffer as planar (rearLeft's n
        samples, then rearRight's ...) and reads it as interleaved, so channel c gets samples
        c, c+4, c+8 ... of one microphone (rearLeft in the first quarter of the buffer, rearRight
        in the next ...), as a bridge that ignores the buffer's layout would."""
        b = self.block
        f = self.faults
        if f.silent_channel and f.after is not None and self.partial_on(t):
            from .profiles import MIC_CHANNELS
            b = b.copy()
            for name in f.silent_channel:
                b[:, MIC_CHANNELS.index(name)] = 0
        if f.quiet_channel:         # a clogged grille: a quarter of the amplitude, 12 dB (at the
            # microphone, before any transport fault below)
            from .profiles import MIC_CHANNELS
            b = b.copy()
            for name in f.quiet_channel:
                b[:, MIC_CHANNELS.index(name)] //= 4
        if f.copied_channels:
            b = np.repeat(b[:, :1], b.shape[1], axis=1)
        if f.planar_as_interleaved:
            b = np.ascontiguousarray(b.T).reshape(-1, b.shape[1])
        return b

    def build(self, t: float, frame_id: str, index: int) -> 'genpy.Message':
        b = self.data_block(t)
        cls = self.msg_class()
        return cls(rearLeft=b[:, 0].tolist(), rearRight=b[:, 1].tolist(),
                   frontLeft=b[:, 2].tolist(), frontRight=b[:, 3].tolist())


class AudioBufferPublisher(AudioPublisher):
    """naoqi_bridge_msgs/AudioBuffer as stock naoqi_driver publishes it (src/event/audio.cpp:
    62-66 channelMap [3, 5, 0, 2] on Pepper; 107-113 ALAudioDevice at 48000 Hz, all channels,
    interleaved; 177-186 one message per NAOqi buffer, data = the buffer as it came)."""

    def msg_class(self) -> type:
        from ..sources.naoqi_msgs import audio_buffer_class
        return audio_buffer_class()

    def build(self, t: float, frame_id: str, index: int) -> 'genpy.Message':
        from ..sources.naoqi_msgs import PEPPER_CHANNEL_MAP
        msg = self.msg_class()()
        msg.frequency = AUDIO_RATE
        # channelMap is uint8[]: genpy serialises it from bytes
        msg.channelMap = bytes(PEPPER_CHANNEL_MAP)
        # the source's columns are rearLeft, rearRight, frontLeft, frontRight = codes 3, 5, 0, 2
        msg.data = self.data_block(t).reshape(-1).tolist()
        return msg


# one publisher per check family (sensors/families.py), as the driver publishes its stream
FAMILY_PUBLISHERS: Dict[str, Type[StreamPublisher]] = {
    'camera': ImagePublisher, 'depth': ImagePublisher, 'laser': LaserPublisher, 'range': SonarPublisher,
    'odometry': OdometryPublisher, 'imu': ImuPublisher, 'joints': JointStatePublisher,
    'audio': AudioPublisher}


def publisher_class(spec: SensorSpec) -> Type[StreamPublisher]:
    """The publisher of a stream: its family's, stock naoqi_driver's AudioBuffer apart."""
    if spec.family == 'audio' and spec.layout == 'audiobuffer':
        return AudioBufferPublisher
    return FAMILY_PUBLISHERS[spec.family]
