"""The ROS seam for what this package publishes and subscribes besides the sensor windows
(those go through sources/live.py or sources/live2.py): rospy on ROS 1, rclpy on ROS 2.

Above the seam every message is a ROS 1 (genpy) message built from a class `msg()` gives
(rospy's own on ROS 1; built from the definition on ROS 2, where a package of the same name is
ROS 2's). On ROS 2 a publisher turns it into CDR (sources/ros2wire.py) and a subscription turns
CDR back into it (sources/ros2types.Converter), on the rclpy node of the process
(sources/live2.Ros2Graph: sensorTest's, or the emulator's).

QoS on ROS 2: reliable, volatile, keep-last `queue_size` (what naoqi_driver2's subscribers
take: src/subscribers/teleop.cpp:38-46, speech.cpp:37, moveto.cpp:45 all use depth 10, the
default reliable profile); `latch` is transient-local, as a ROS 1 latched topic.
"""
import os
from collections import namedtuple
from typing import Any, Callable, Optional

from .sources.live2 import current, ros_version

_Conn = namedtuple('_Conn', 'topic msgtype msgdef')


def version() -> int:
    return ros_version()


def msg(type_name: str) -> Any:
    """The genpy class of 'pkg/Name' (either ROS)."""
    from .sources import messages
    return messages.message_class(type_name)


def _graph() -> Any:
    graph = current()
    if graph is None:
        raise RuntimeError('ROS 2: no rclpy node in this process yet (sources/live2.Ros2Graph)')
    return graph


def now() -> Any:
    """The node's current time as a genpy Time (rospy.Time on ROS 1)."""
    if ros_version() == 2:
        import genpy
        return genpy.Time.from_sec(_graph().now())
    import rospy
    return rospy.Time.now()


def _qos(depth: int, latch: bool) -> Any:
    from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
    return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=max(1, depth),
                      reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL if latch else DurabilityPolicy.VOLATILE)


def publisher(topic: str, type_name: str, queue_size: Optional[int] = 10, latch: bool = False,
              cls: Any = None) -> Any:
    """A publisher taking genpy messages: publish(msg), get_num_connections(), unregister(),
    name. ROS 1: rospy.Publisher (queue_size None: synchronous) of `cls` when given, else of
    msg(type_name)."""
    if ros_version() == 2:
        from .sources.ros2wire import RawPublisher
        return RawPublisher(_graph().node, topic, type_name, _qos(queue_size or 10, latch))
    import warnings

    import rospy
    with warnings.catch_warnings():   # rospy warns about queue_size None: the caller chose it
        warnings.simplefilter('ignore', SyntaxWarning)
        return rospy.Publisher(topic, cls or msg(type_name), queue_size=queue_size, latch=latch)


class _Subscription:
    """An rclpy subscription handing genpy messages to `callback`."""

    def __init__(self, topic: str, type_name: str, callback: Callable[[Any], None], queue_size: int,
                 cls: Any = None) -> None:
        from .plan.settings import package_dir
        from .sources import ros2types
        from .sources.ros2wire import msg_class, ros2_type
        self.graph = _graph()
        ros2 = ros2_type(type_name)
        converter = ros2types.Converter([_Conn(topic, ros2, None)], os.path.join(package_dir(), 'msg'),
                                        os.environ.get('ROS_DISTRO') or None)
        cls = cls or msg(type_name)

        def on_raw(raw: bytes) -> None:
            m = cls()
            try:
                m.deserialize(converter.to_ros1(raw, ros2))
            except Exception:  # noqa: BLE001  (a message of another layout: not ours to take)
                return
            callback(m)
        self.sub = self.graph.node.create_subscription(msg_class(ros2), topic, on_raw,
                                                       _qos(queue_size, False), raw=True)

    def unregister(self) -> None:
        try:
            self.graph.node.destroy_subscription(self.sub)
        except Exception:  # noqa: BLE001  (the context is already gone)
            pass


def subscriber(topic: str, type_name: str, callback: Callable[[Any], None], queue_size: int = 10,
               cls: Any = None) -> Any:
    """A subscription handing genpy messages (of `cls` when given, else of msg(type_name)) to
    `callback`; unregister() ends it."""
    if ros_version() == 2:
        return _Subscription(topic, type_name, callback, queue_size, cls)
    import rospy
    return rospy.Subscriber(topic, cls or msg(type_name), callback, queue_size=queue_size)


def _log(level: str, text: str, *args: Any) -> None:
    if ros_version() == 2:
        graph = current()
        message = text % args if args else text
        if graph is None:
            import sys
            sys.stderr.write('[%s] %s\n' % (level.upper(), message))
            return
        getattr(graph.node.get_logger(), 'warning' if level == 'warn' else level)(message)
        return
    import rospy
    getattr(rospy, 'log' + level)(text, *args)


def loginfo(text: str, *args: Any) -> None:
    _log('info', text, *args)


def logwarn(text: str, *args: Any) -> None:
    _log('warn', text, *args)


def logerr(text: str, *args: Any) -> None:
    _log('error', text, *args)


def is_shutdown() -> bool:
    if ros_version() == 2:
        graph = current()
        return graph is None or not graph.ok
    import rospy
    return rospy.is_shutdown()
