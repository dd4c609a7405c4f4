"""/tf as the driver publishes it (emulator/urdf_tree.py: the frames, parents and origins of
naoqi_driver's share/urdf/pepper.urdf), and the tree's faults.

On the robot profiles the tree goes out with every joint state, from the same positions and
with the same stamp (joint_state.cpp:94-201): the joint state publisher hands each message it
publishes to `TfPublisher.send`. `odom -> base_link` is the body's pose at that moment
(joint_state.cpp:162-185: the torso's pose from ALMotion, the odometry's too). With no joint
state publisher the tree keeps its own 50 Hz schedule from the body's joints.

With --realsense the camera's own frames and its mount go out once on /tf_static
(REALSENSE_TREE). The simulator's layout follows robot_state_publisher and Gazebo (urdf_tree.py's docstring):
`odom -> base_footprint` and the moving joints on /tf, the fixed joints once, latched, on
/tf_static, the leg chain from base_footprint up.

Faults (sensor `tf`): no_description (only odom -> base_link, joint_state.cpp:59-63),
second_publisher (a second node, emulator/second_publisher.py, publishes Head ->
CameraTop_frame 1 cm off), stale (stamps 0.8 s behind), future_stamps (1.0 s ahead).
"""
import os
import subprocess
import sys
import threading
from typing import Any, Dict, List, Optional

import genpy

from .. import rosapi
from .publishers import StreamPublisher
from .urdf_tree import Transform, driver_tree, quat_axis, quat_rpy, simulator_tree

STALE_S = 0.8
FUTURE_S = 1.0
# The RealSense on the head (--realsense): realsense2_camera (ros1-legacy) publishes its own
# frames once on /tf_static (base_realsense_node.cpp publishStaticTransforms: camera_link ->
# camera_color_frame, the D435's colour imager 15 mm to the left, -> camera_color_optical_frame
# turned as every optical frame, z forward); the mount, Head -> camera_link, is the robot's own
# static transform (a static_transform_publisher in its launch): here 0.1 m in front of and
# 0.15 m above Head, a stand-in
REALSENSE_TREE: List[Transform] = [
    ('Head', 'camera_link', (0.1, 0.0, 0.15), (0.0, 0.0, 0.0, 1.0)),
    ('camera_link', 'camera_color_frame', (0.0, 0.015, 0.0), (0.0, 0.0, 0.0, 1.0)),
    ('camera_color_frame', 'camera_color_optical_frame', (0.0, 0.0, 0.0), quat_rpy(-1.5707963, 0.0, -1.5707963)),
]


def static_topic(spec: Any) -> Optional[str]:
    """The latched /tf_static this stream publishes besides /tf (the simulator's fixed joints,
    the RealSense's frames), or None."""
    if spec.family == TfPublisher.family and spec.layout in ('gazebo', 'realsense'):
        return spec.topic + '_static'
    return None


def tf_message(transforms: List[Transform], stamp: genpy.Time) -> Any:
    """A TFMessage of (parent, child, translation, rotation) transforms, all at `stamp`."""
    out = rosapi.msg('tf2_msgs/TFMessage')()
    stamped = rosapi.msg('geometry_msgs/TransformStamped')
    for parent, child, p, q in transforms:
        t = stamped()
        t.header.stamp = stamp
        t.header.frame_id = parent
        t.child_frame_id = child
        t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = p
        (t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z,
         t.transform.rotation.w) = q
        out.transforms.append(t)
    return out


class TfPublisher(StreamPublisher):
    """The tree on /tf (and, for the simulator, /tf_static)."""

    queue_size = 100
    family = 'tf'

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.driven = False         # set by the emulator when the joint states carry the tree
        self.gazebo = self.spec.layout == 'gazebo'
        self._lock = threading.Lock()
        self._static: Optional[Any] = None
        self._second: Optional[subprocess.Popen] = None
        fixed: List[Transform] = []
        if self.gazebo:
            fixed = [t for t in simulator_tree(driver_tree({})) if not self._moving(t)]
        elif self.spec.layout == 'realsense':
            fixed = list(REALSENSE_TREE)
        if fixed:
            self._static = rosapi.publisher(static_topic(self.spec) or '/tf_static', 'tf2_msgs/TFMessage', queue_size=1,
                                            latch=True)
            self._static.publish(tf_message(fixed, rosapi.now()))
        if self.faults.second_publisher:
            self._second = subprocess.Popen(
                [sys.executable, '-m', 'pepper_interface_tests.emulator.second_publisher', self.spec.topic],
                env=dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p)))

    @staticmethod
    def _moving(t: Transform) -> bool:
        from .urdf_tree import JOINTS
        return any(j.moving and {j.parent, j.child} == {t[0], t[1]} for j in JOINTS)

    def msg_class(self) -> type:
        return rosapi.msg('tf2_msgs/TFMessage')

    def run(self) -> None:
        if not self.driven:
            super().run()

    def wanted(self) -> bool:
        return True     # the driver publishes the tree whoever listens (joint_state.cpp:54-58)

    def build(self, t: float, frame_id: str, index: int) -> Any:
        snap = self.snapshot(t)
        positions = dict(snap.joints)
        positions.update(snap.wheels)
        return self.tree(positions, self.clock.stamp(), t)

    def send(self, joint_state: Any) -> None:
        """The tree of a joint state the joint publisher has just published."""
        if self.faults.silent or not hasattr(joint_state, 'position'):
            return
        positions = dict(zip(joint_state.name, joint_state.position))
        msg = self.tree(positions, joint_state.header.stamp, self.clock.now())
        with self._lock:
            for pub, _ in self.outputs:
                pub.publish(msg)
            self.published += 1

    def tree(self, positions: Dict[str, float], stamp: genpy.Time, t: float) -> Any:
        f = self.faults
        snap = self.snapshot(t)
        base = 'base_footprint' if self.gazebo else 'base_link'
        odom: Transform = ('odom', base, (snap.x, snap.y, 0.0), quat_axis((0.0, 0.0, 1.0), snap.yaw))
        below = driver_tree(positions, described=not f.no_description)
        if self.gazebo:
            below = [t for t in simulator_tree(below) if self._moving(t)]
        if f.stale:
            stamp = stamp - genpy.Duration.from_sec(STALE_S)
        if f.future_stamps:
            stamp = stamp + genpy.Duration.from_sec(FUTURE_S)
        return tf_message(below + [odom], stamp)

    def close(self) -> None:
        super().close()
        if self._static is not None:
            self._static.unregister()
        if self._second is not None:
            self._second.terminate()
            try:
                self._second.wait(5.0)
            except subprocess.TimeoutExpired:
                self._second.kill()
