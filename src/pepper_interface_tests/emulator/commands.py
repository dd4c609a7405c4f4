"""The motion commands naoqi_driver takes, subscribed exactly as the driver subscribes them, and
handed to the body (body.py) as the driver hands them to ALMotion.

`Driver::registerDefaultSubscriber` (ros-naoqi/naoqi_driver src/naoqi_driver.cpp:933-940)
registers TeleopSubscriber on "/cmd_vel" and "/joint_angles" and MovetoSubscriber on
"/move_base_simple/goal": absolute names, so the node's namespace does not apply; queue 10
(teleop.cpp:38-39, moveto.cpp:45). naoqi_driver2 (src/naoqi_driver.cpp:996-997) and the
CSSR4Africa fork (src/naoqi_driver.cpp:931-932) register the same three.

- /cmd_vel geometry_msgs/Twist -> move(linear.x, linear.y, angular.z) (teleop.cpp:44-53)
- /joint_angles naoqi_bridge_msgs/JointAnglesWithSpeed -> setAngles(joint_names,
  joint_angles, speed), or changeAngles when relative != 0 (teleop.cpp:55-65)
- /move_base_simple/goal geometry_msgs/PoseStamped (moveto.cpp:49-129): frame
  "base_footprint" -> moveTo(x, y, yaw of the orientation), a NaN yaw becoming 0 (:104-121);
  frame "odom" -> the pose transformed into base_footprint first (:51-103); any other frame
  is refused with a printed line (:123-128).

The driver's calls are asynchronous and print what they do; a call ALMotion refuses leaves
nothing on ROS. The emulator says each command and each refusal on /rosout.
"""
import math
from typing import Any, Callable, List

from .. import rosapi
from ..sources.naoqi_msgs import joint_angles_class
from .body import Body, CommandError

TOPICS = {'cmd_vel': '/cmd_vel', 'joint_angles': '/joint_angles', 'goal': '/move_base_simple/goal'}


def quaternion_yaw(q: object) -> float:
    """The driver's getYaw (src/helpers/transform_helpers.hpp:33-39): tf2::Matrix3x3 of the
    quaternion (scaled by 2 / |q|^2, so an unnormalised one works), getEulerYPR's yaw
    atan2(m10, m00). A zero quaternion gives NaN, which the driver turns into 0."""
    x, y, z, w = (float(getattr(q, k)) for k in 'xyzw')
    d = x * x + y * y + z * z + w * w
    if not d > 0:
        return float('nan')
    s = 2.0 / d
    return math.atan2(s * (x * y + w * z), 1.0 - s * (y * y + z * z))


class CommandSubscribers:
    """The three subscribers of one emulator run, feeding one body."""

    def __init__(self, body: Body, now: Callable[[], float], resting: bool, base_blocked: bool) -> None:
        self.body, self.now = body, now
        self.why_base = 'the robot is resting (stiffness 0)' if resting else \
            'the base may not move (power hatch open or collision protection)' if base_blocked else ''
        self.why_joints = 'the robot is resting (stiffness 0)' if resting else ''
        angles = joint_angles_class()
        self.subs: List[Any] = [
            rosapi.subscriber(TOPICS['cmd_vel'], 'geometry_msgs/Twist', self.on_cmd_vel, queue_size=10),
            rosapi.subscriber(TOPICS['joint_angles'], angles._type, self.on_joint_angles, queue_size=10,
                              cls=angles),
            rosapi.subscriber(TOPICS['goal'], 'geometry_msgs/PoseStamped', self.on_goal, queue_size=10)]
        body.expected = self.expected

    def expected(self) -> bool:
        """A publisher is connected to one of the command topics: commands are coming."""
        return any(s.get_num_connections() > 0 for s in self.subs)

    def _refused(self, what: str, why: str) -> None:
        rosapi.logwarn('pepperEmulator: %s ignored: %s', what, why)

    def on_cmd_vel(self, msg: Any) -> None:
        what = 'move(%.3f, %.3f, %.3f)' % (msg.linear.x, msg.linear.y, msg.angular.z)
        try:
            ok = self.body.move(self.now(), msg.linear.x, msg.linear.y, msg.angular.z)
        except CommandError as e:
            rosapi.logwarn('pepperEmulator: /cmd_vel: %s', e)
            return
        if ok:
            rosapi.loginfo('pepperEmulator: %s', what)
        else:
            self._refused(what, self.why_base)

    def on_joint_angles(self, msg: Any) -> None:
        names = list(msg.joint_names)
        angles = [float(a) for a in msg.joint_angles]
        speed, relative = float(msg.speed), bool(msg.relative)
        what = '%s(%s, %s, %.2f)' % ('changeAngles' if relative else 'setAngles', names,
                                     ['%.3f' % a for a in angles], speed)
        try:
            ok = self.body.set_angles(self.now(), names, angles, speed, relative)
        except CommandError as e:
            rosapi.logwarn('pepperEmulator: /joint_angles: %s refused: %s', what, e)
            return
        if ok:
            rosapi.loginfo('pepperEmulator: %s', what)
        else:
            self._refused(what, self.why_joints)

    def on_goal(self, msg: Any) -> None:
        frame = msg.header.frame_id
        if frame not in ('base_footprint', 'odom'):
            # moveto.cpp:123-128: printed, nothing moves
            rosapi.logwarn('pepperEmulator: /move_base_simple/goal: cannot reach a position '
                          'expressed in the "%s" frame (base_footprint or odom)', frame)
            return
        yaw = quaternion_yaw(msg.pose.orientation)
        if math.isnan(yaw):
            yaw = 0.0               # moveto.cpp:111-114
        p = msg.pose.position
        what = 'moveTo(%.3f, %.3f, %.3f) in %s' % (p.x, p.y, yaw, frame)
        try:
            ok = self.body.move_to(self.now(), p.x, p.y, yaw, frame)
        except CommandError as e:
            rosapi.logwarn('pepperEmulator: /move_base_simple/goal: %s', e)
            return
        if ok:
            rosapi.loginfo('pepperEmulator: %s', what)
        else:
            self._refused(what, self.why_base)

    def close(self) -> None:
        self.body.expected = None
        for s in self.subs:
            s.unregister()
