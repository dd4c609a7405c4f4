"""The driver's /tf added to a recording of naoqi_driver that lacks it, derived from the
recording's own /joint_states and odometry as the driver computes it (urdf_tree.py: the tree
of its share/urdf/pepper.urdf at each joint state's positions, joint_state.cpp:113-151; the
joint state's stamp and record time, one TFMessage per joint state, joint_state.cpp:94-99 and
src/publishers/joint_state.cpp:33-42; `odom -> base_link` from the odometry's pose
interpolated at that stamp, the pose the driver reads from the same ALMotion call,
joint_state.cpp:162-185 and odom.cpp:56-93). The connection names the joint states' node.

`drop`: (parent, child) pairs left out of every message (a recording with a broken tree);
`hold`: joints frozen in the tree (a tree that does not follow the head)."""
import bisect
import math
from typing import Any, Iterable, List, Optional, Tuple

from .urdf_tree import Transform, driver_tree, quat_axis

TF_TOPIC = '/tf'


def _odom_at(poses: List[Tuple[float, float, float, float]], stamp: float) -> Optional[Tuple[float, float, float]]:
    if not poses:
        return None
    stamps = [p[0] for p in poses]
    i = bisect.bisect_left(stamps, stamp)
    if i <= 0:
        return poses[0][1:]
    if i >= len(poses):
        return poses[-1][1:]
    (t0, x0, y0, a0), (t1, x1, y1, a1) = poses[i - 1], poses[i]
    k = (stamp - t0) / (t1 - t0) if t1 > t0 else 0.0
    da = math.atan2(math.sin(a1 - a0), math.cos(a1 - a0))
    return x0 + k * (x1 - x0), y0 + k * (y1 - y0), a0 + k * da


def add_tf(src: str, dst: str, joints: str = '/joint_states', odom: str = '/naoqi_driver/odom',
           drop: Iterable[Tuple[str, str]] = (), hold: Iterable[str] = ()) -> int:
    """Copy recording `src` to `dst` with /tf added (any /tf in `src` left out); returns the
    TFMessages written. `hold`: joints whose transform keeps their first position (a tree that
    does not follow the joint states)."""
    import rosbag
    from tf2_msgs.msg import TFMessage

    from .tf_publisher import tf_message
    dropped = set(drop)
    held: dict = {j: None for j in hold}
    poses = []
    with rosbag.Bag(src) as bag:
        for _, m, _ in bag.read_messages(topics=[odom]):
            q = m.pose.pose.orientation
            yaw = math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))
            poses.append((m.header.stamp.to_sec(), m.pose.pose.position.x, m.pose.pose.position.y, yaw))
    poses.sort()
    written = 0
    with rosbag.Bag(src) as bag, rosbag.Bag(dst, 'w', compression='bz2') as out:
        for topic, m, t, conn in bag.read_messages(raw=True, return_connection_header=True):
            if topic == TF_TOPIC:
                continue
            out.write(topic, m, t, raw=True, connection_header=conn)
            if topic != joints:
                continue
            msg = _decode(m)
            stamp = msg.header.stamp
            positions = dict(zip(msg.name, msg.position))
            for j in held:
                if held[j] is None:
                    held[j] = positions.get(j)
                if held[j] is not None:
                    positions[j] = held[j]
            tree: List[Transform] = driver_tree(positions)
            pose = _odom_at(poses, stamp.to_sec())
            if pose is not None:
                tree.append(('odom', 'base_link', (pose[0], pose[1], 0.0), quat_axis((0.0, 0.0, 1.0), pose[2])))
            tf = tf_message([x for x in tree if (x[0], x[1]) not in dropped], stamp)
            caller = conn.get('callerid', b'/naoqi_driver')
            header = {'callerid': caller.decode() if isinstance(caller, bytes) else caller, 'topic': TF_TOPIC,
                      'type': 'tf2_msgs/TFMessage', 'md5sum': TFMessage._md5sum,
                      'message_definition': TFMessage._full_text}
            out.write(TF_TOPIC, tf, t, connection_header=header)
            written += 1
    return written


def _decode(raw: Any) -> Any:
    _type, data, _md5, _pos, cls = raw
    return cls().deserialize(data)
