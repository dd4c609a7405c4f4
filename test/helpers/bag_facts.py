"""The facts of a bag's topics that a driver's format fixes: type, md5, frame ids, and per type
the layout (image encoding and size, laser geometry and blind slots, covariance markers, joint
names and NaN columns, sonar geometry, a camera's calibration, diagnostics' status names) and
the rate. Used to hold the emulator's streams against the real naoqi_driver's golden recordings."""
import math


def _nan_columns(values):
    return tuple(i for i, v in enumerate(values) if isinstance(v, float) and math.isnan(v))


def message_facts(msg_type, m):
    """The layout facts of one message (values that do not change from message to message)."""
    if msg_type == 'sensor_msgs/Image':
        return dict(encoding=m.encoding, width=m.width, height=m.height, step=m.step,
                    is_bigendian=m.is_bigendian, data_len=len(m.data))
    if msg_type == 'sensor_msgs/LaserScan':
        return dict(slots=len(m.ranges), angle_min=round(m.angle_min, 4), angle_max=round(m.angle_max, 4),
                    angle_increment=round(m.angle_increment, 5), range_min=round(m.range_min, 3),
                    range_max=round(m.range_max, 3),
                    minus_one=tuple(i for i, r in enumerate(m.ranges) if r == -1.0),
                    intensities=len(m.intensities))
    if msg_type == 'sensor_msgs/Range':
        return dict(radiation_type=m.radiation_type, field_of_view=round(m.field_of_view, 4),
                    min_range=round(m.min_range, 3), max_range=round(m.max_range, 3))
    if msg_type == 'sensor_msgs/Imu':
        return dict(orientation_covariance=tuple(m.orientation_covariance),
                    angular_velocity_covariance=tuple(m.angular_velocity_covariance),
                    linear_acceleration_covariance=tuple(m.linear_acceleration_covariance))
    if msg_type == 'sensor_msgs/JointState':
        return dict(names=tuple(m.name), positions=len(m.position), velocities=len(m.velocity),
                    efforts=len(m.effort), nan_velocity=_nan_columns(m.velocity),
                    nan_effort=_nan_columns(m.effort))
    if msg_type == 'nav_msgs/Odometry':
        return dict(child_frame_id=m.child_frame_id,
                    pose_covariance_nonzero=any(m.pose.covariance),
                    twist_covariance_nonzero=any(m.twist.covariance))
    if msg_type.endswith('/AudioBuffer') or msg_type.endswith('/AudioCustomMsg'):
        return dict(frequency=getattr(m, 'frequency', None), channel_map=tuple(getattr(m, 'channelMap', ())),
                    data_len=len(m.data))
    if msg_type == 'sensor_msgs/CameraInfo':    # the calibration (ROS 2's lower-case names: ros2_facts)
        return dict(width=m.width, height=m.height, distortion_model=m.distortion_model,
                    D=tuple(m.D), K=tuple(m.K), R=tuple(m.R), P=tuple(m.P))
    if msg_type == 'diagnostic_msgs/DiagnosticArray':
        return dict(status_names=tuple(sorted(s.name for s in m.status)))
    return {}


def bag_facts(path):
    """{topic: {'type', 'md5', 'frames', 'count', 'rate', 'facts'}} of a bag."""
    import rosbag  # here, not above: ros2_facts uses message_facts on ROS 2, without rospy
    out = {}
    with rosbag.Bag(path) as bag:
        info = bag.get_type_and_topic_info().topics
        conns = {c.topic: c for c in bag._get_connections()}
        for topic, ti in info.items():
            times, frames, facts = [], set(), None
            for _, m, t in bag.read_messages([topic]):
                times.append(t.to_sec())
                header = getattr(m, 'header', None)
                if header is not None:
                    frames.add(header.frame_id)
                if facts is None:
                    facts = message_facts(ti.msg_type, m)
            span = times[-1] - times[0] if len(times) > 1 else 0.0
            out[topic] = dict(type=ti.msg_type, md5=conns[topic].md5sum, frames=frames,
                              count=len(times), rate=(len(times) - 1) / span if span > 0 else None,
                              facts=facts or {})
    return out
