"""The commands the motion check sends, on naoqi_driver's own topics
(ros-naoqi/naoqi_driver src/naoqi_driver.cpp:933-938, registerDefaultSubscriber):

- /move_base_simple/goal, geometry_msgs/PoseStamped in base_footprint: ALMotion.moveTo(x, y,
  yaw), relative to where the robot stands and bounded (src/subscribers/moveto.cpp:104-121). A
  bounded command is what makes the check safe: if sensorTest dies mid-turn the robot still
  stops where it was told. Only in-place turns are sent (x = y = 0).
- /joint_angles, naoqi_bridge_msgs/JointAnglesWithSpeed (this package's copy, same md5sum:
  msg/JointAnglesWithSpeed.msg): ALMotion.setAngles(names, angles, speed) with relative 0
  (src/subscribers/teleop.cpp:55-65). Only HeadYaw is commanded.
- /cmd_vel, geometry_msgs/Twist: ALMotion.move(vx, vy, vth), which keeps going until told
  otherwise (teleop.cpp:44-53); used ONLY to stop: a zero twist, which also cancels a moveTo
  under way (ALMotion: a new move task replaces the running one).

Every publisher is synchronous (queue_size None): publish() returns once the message is written
to each subscriber's connection, so a stop sent just before the end (Ctrl-C, SIGTERM) is on the
wire before the publishers are unregistered; rospy's queued publishing would drop it. On ROS 2
(rosapi.py) the publishers are reliable and unregistering waits until every subscriber has
acknowledged what was sent (rclpy wait_for_all_acked, at most 0.5 s). After `close()` nothing
is ever sent again (every send checks it under the lock).
"""
import math
import threading
import time
from typing import Callable, List, Tuple

from .. import rosapi

JOINT_ANGLES = 'naoqi_bridge_msgs/JointAnglesWithSpeed'

GOAL_TOPIC = '/move_base_simple/goal'
JOINT_TOPIC = '/joint_angles'
STOP_TOPIC = '/cmd_vel'


class Commands:
    """The three publishers; `sent` lists what went out: (time, topic, text)."""

    def __init__(self, clock: Callable[[], float] = time.monotonic) -> None:
        self.clock = clock
        self.lock = threading.Lock()
        self.closed = False
        self.sent: List[Tuple[float, str, str]] = []
        if rosapi.version() == 2:
            self.angles_class = rosapi.msg(JOINT_ANGLES)
        else:   # this package's copy (same md5sum as naoqi_bridge_msgs', which may not be installed)
            from ..msg import JointAnglesWithSpeed
            self.angles_class = JointAnglesWithSpeed
        self.pose_class = rosapi.msg('geometry_msgs/PoseStamped')
        self.twist_class = rosapi.msg('geometry_msgs/Twist')
        self.goal = rosapi.publisher(GOAL_TOPIC, 'geometry_msgs/PoseStamped', queue_size=None)
        self.joints = rosapi.publisher(JOINT_TOPIC, self.angles_class._type, queue_size=None,
                                       cls=self.angles_class)
        self.twist = rosapi.publisher(STOP_TOPIC, 'geometry_msgs/Twist', queue_size=None)

    def receivers(self) -> int:
        """How many of the three topics have a subscriber (naoqi_driver: all three)."""
        return sum(1 for p in (self.goal, self.joints, self.twist) if p.get_num_connections() > 0)

    def missing(self) -> List[str]:
        return [p.name for p in (self.goal, self.joints, self.twist) if p.get_num_connections() == 0]

    def _send(self, pub, msg, text: str) -> bool:
        with self.lock:
            if self.closed:
                return False
            pub.publish(msg)
            self.sent.append((self.clock(), pub.name, text))
            return True

    def turn(self, yaw: float) -> bool:
        """A bounded turn in place by `yaw` rad (counter-clockwise positive)."""
        msg = self.pose_class()
        msg.header.stamp = rosapi.now()
        msg.header.frame_id = 'base_footprint'     # moveto.cpp:104: relative to the robot
        msg.pose.orientation.z = math.sin(yaw / 2.0)
        msg.pose.orientation.w = math.cos(yaw / 2.0)
        return self._send(self.goal, msg, 'turn %+.2f rad' % yaw)

    def head(self, yaw: float, speed: float) -> bool:
        """HeadYaw to `yaw` rad (absolute) at `speed` (fraction of its maximum speed)."""
        msg = self.angles_class()
        msg.header.stamp = rosapi.now()
        msg.joint_names = ['HeadYaw']
        msg.joint_angles = [yaw]
        msg.speed = speed
        msg.relative = 0
        return self._send(self.joints, msg, 'HeadYaw %+.2f rad' % yaw)

    def stop(self) -> bool:
        """A zero twist: the base stops at once (ALMotion.move(0, 0, 0))."""
        return self._send(self.twist, self.twist_class(), 'stop')

    def close(self) -> None:
        """Nothing is sent after this (the publishers are unregistered)."""
        with self.lock:
            self.closed = True
        for p in (self.goal, self.joints, self.twist):
            try:
                p.unregister()
            except Exception:  # the master may be gone: nothing more to undo
                pass
