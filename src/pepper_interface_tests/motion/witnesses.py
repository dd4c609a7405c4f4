"""The motion check's witnesses: the sensors that see the robot move, subscribed for the check's
window whether or not they are selected (their topics from the topics file: RunContext.topics),
recorded into a record.Recording.

Each subscription takes any type (rosapi.any_subscriber: rospy.AnyMsg, or rclpy's raw), decoded
here with the message class of its type (so a naoqi_bridge_msgs/Bumper from the robot and this
package's copy, same md5sum, both decode).
Camera frames are kept small (about 80 pixels wide, grey) and at most about 10 per second.
"""
import math
import time
from typing import Any, Callable, Dict, List, Optional

import numpy as np

from .. import rosapi
from ..genmsgs import Bumper, DiagnosticArray, Image, Imu, JointState, LaserScan, Odometry, Range
from ..media import encodings
from ..plan import declaration
from ..stats import StampPlacer
from . import estimate
from .record import Recording, Scan

# witness role -> the sensor whose topic it listens to (plan/catalog.py names); the head's
# cameras are the declaration's (plan/declaration.py: the 'pepper' camera group), colour first
HEAD_CAMERAS = declaration.sensors_of('camera', camera='pepper') + declaration.sensors_of('depth', camera='pepper')
ROLES = ('jointState', 'odometry', 'imu', 'laser', 'frontSonar', 'backSonar', 'bumper',
         'robotHealth') + HEAD_CAMERAS
FRAME_PERIOD = 0.09    # s between two kept frames of one camera (naoqi_driver's 10 fps: each)
FRONT_SECTOR = 0.2     # rad either side of straight ahead: the laser's front sector
# Witnesses whose header stamp is the sample's time, on the driver's host, taken right after
# the values were fetched from NAOqi: joint states (converters/joint_state.cpp:90 getAngles,
# :94 ros::Time::now(), :99 the stamp), odometry (odom.cpp:56 getPosition, :58 now, :80),
# the IMU (imu.cpp:93 getListData, :103-104 now) and the head's cameras (camera.cpp: the stamp
# right after getImageRemote, :273, NAOqi's own image time left commented out, :289-291).
# (naoqi_driver ros-naoqi/naoqi_driver aed1b87.) A message handled late (a busy PC: messages
# waiting in this process or in the driver's publisher; then a burst) is placed when its stamp
# says it was sampled, not when it was handled: a turn's last samples handled after the step
# ended were left out of it, and a burst's gyro samples, integrated over their handling times,
# gave a wrong angle (issue 41).
STAMPED = ('jointState', 'odometry', 'imu') + HEAD_CAMERAS
# A stamp places its message only if it is on this computer's wall clock give or take this
# many seconds; within that, a clock offset between the driver's host and this one is taken
# out (stats.StampPlacer), so a driver on the robot whose clock is 3 s behind places as well as
# one on this PC
MAX_LATE = 10.0


class Recorder:
    """Decoded witness messages into a Recording: `handle(role, msg, t)` under its lock. Live, the
    Witnesses below subscribe; from a bag, motion/recorded.py feeds the same handlers."""

    live = False    # the witnesses subscribed live (not a recording read back)

    def __init__(self, recording: Recording) -> None:
        self.rec = recording
        self.placers = {role: StampPlacer(MAX_LATE) for role in STAMPED}
        self.handlers: Dict[str, Any] = {
            'jointState': (JointState, self._joints), 'odometry': (Odometry, self._odom),
            'imu': (Imu, self._imu), 'laser': (LaserScan, self._laser),
            'frontSonar': (Range, self._sonar), 'backSonar': (Range, self._sonar),
            'bumper': (Bumper, self._bumper), 'robotHealth': (DiagnosticArray, self._health)}
        for cam in HEAD_CAMERAS:
            self.handlers[cam] = (Image, self._frame)

    def handle(self, role: str, msg: Any, t: float) -> None:
        with self.rec.lock:
            self.rec.count(role)
            header = getattr(msg, 'header', None)
            if header is not None and header.stamp.to_sec() > 0:
                now = time.time()
                self.rec.stamps[role] = (header.stamp.to_sec(), now)
                if self.live and role in STAMPED:
                    placer = self.placers[role]
                    t = placer.place(t, now - header.stamp.to_sec())
                    self.rec.behind = max(self.rec.behind, placer.behind)
            self.handlers[role][1](role, msg, t)

    # each handler runs under the recording's lock
    def _joints(self, role: str, msg: Any, t: float) -> None:
        self.rec.joints.append((t, dict(zip(msg.name, msg.position))))

    def _odom(self, role: str, msg: Any, t: float) -> None:
        q = msg.pose.pose.orientation
        self.rec.odom_yaw.append((t, estimate.yaw_of(q.x, q.y, q.z, q.w)))
        p = msg.pose.pose.position
        self.rec.odom_xy.append((t, p.x, p.y))

    def _imu(self, role: str, msg: Any, t: float) -> None:
        w = msg.angular_velocity
        self.rec.gyro.append((t, w.x, w.y, w.z))

    def _laser(self, role: str, msg: Any, t: float) -> None:
        r = estimate.valid_ranges(msg.ranges, msg.range_min)
        self.rec.scans.append(Scan(t, r, msg.angle_increment))
        angles = msg.angle_min + msg.angle_increment * np.arange(len(r))
        ok = np.isfinite(r)
        if ok.any():
            i = int(np.nanargmin(r))
            self.rec.laser_nearest = (t, float(r[i]), float(angles[i]))
        front = ok & (np.abs(angles) <= FRONT_SECTOR)
        self.rec.laser_front = (t, float(np.min(r[front]))) if front.any() else None

    def _sonar(self, role: str, msg: Any, t: float) -> None:
        if math.isfinite(msg.range):
            self.rec.sonar[role] = (t, msg.range)

    def _bumper(self, role: str, msg: Any, t: float) -> None:
        self.rec.bumpers[msg.bumper] = msg.state == 1

    def _health(self, role: str, msg: Any, t: float) -> None:
        for s in msg.status:
            # naoqi_driver's per-joint statuses: src/converters/diagnostics.cpp:159-193
            if s.name.startswith('naoqi_driver_joints:') and s.hardware_id and s.name != 'naoqi_driver_joints:Status':
                for kv in s.values:
                    if kv.key == 'Stiffness':
                        try:
                            self.rec.stiffness[s.hardware_id] = float(kv.value)
                        except ValueError:
                            pass
            if s.level >= 2 and s.name.startswith('naoqi_driver'):
                self.rec.health_error = '%s: %s' % (s.name, s.message)

    def _frame(self, role: str, msg: Any, t: float) -> None:
        frames = self.rec.frames.setdefault(role, [])
        if frames and t - frames[-1][0] < FRAME_PERIOD:
            return
        try:
            img: np.ndarray
            enc = encodings.lookup(msg.encoding)
            if enc is not None and enc.dtype == 'u2':     # depth in mm, an infrared image
                img = np.frombuffer(msg.data, dtype=np.uint16)[:msg.height * msg.width]
                img = img.reshape(msg.height, msg.width)
            else:
                img = np.frombuffer(msg.data, dtype=np.uint8)[:msg.height * msg.step]
                img = img.reshape(msg.height, msg.step)
                channels = msg.step // msg.width if msg.width else 0
                if channels in (2, 3, 4):     # yuv422, rgb8/bgr8, rgba8: one grey value per pixel
                    img = img[:, :msg.width * channels].reshape(msg.height, msg.width, channels)
        except ValueError:
            return
        frames.append((t, estimate.small_grey(img)))


class Witnesses(Recorder):
    """Live: one subscription per witness role whose topic the run knows."""

    def __init__(self, topics: Dict[str, str], recording: Recording,
                 clock: Callable[[], float] = time.monotonic) -> None:
        super().__init__(recording)
        self.live = True
        self.clock = clock
        self.topics = {role: topics[role] for role in ROLES if topics.get(role)}
        self.subs: List[Any] = []
        self.closed = False
        for role, topic in self.topics.items():
            cls = self.handlers[role][0]
            self.subs.append(rosapi.any_subscriber(topic, self._decoder(role, cls), queue_size=5,
                                                   buff_size=1 << 22))

    def _decoder(self, role: str, cls: Any) -> Callable[[str, bytes, Dict[str, Any]], None]:
        def decode(_type: str, buff: bytes, _conn: Dict[str, Any]) -> None:
            self._decode(buff, role, cls)
        return decode

    def _decode(self, buff: bytes, role: str, cls: Any) -> None:
        if self.closed:
            return
        try:
            msg = cls().deserialize(buff)
        except Exception:   # another type on the topic: that sensor's own row says so
            return
        self.handle(role, msg, self.clock())

    def close(self) -> None:
        self.closed = True
        for s in self.subs:
            try:
                s.unregister()
            except Exception:  # the master may be gone
                pass


def heard_of(rec: Recording, role: str) -> Optional[int]:
    with rec.lock:
        return rec.heard.get(role)
