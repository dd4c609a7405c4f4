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
from typing import Any, Callable, Dict, List, Optional, Tuple

from .sources.handling import timed
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
        graph = _graph()
        return RawPublisher(graph.node, topic, type_name, _qos(queue_size or 10, latch), destroy=graph.destroy)
    import warnings

    import rospy
    with warnings.catch_warnings():   # rospy warns about queue_size None: the caller chose it
        warnings.simplefilter('ignore', SyntaxWarning)
        return rospy.Publisher(topic, cls or msg(type_name), queue_size=queue_size, latch=latch)


class _Subscription:
    """An rclpy subscription handing genpy messages to `callback` (transient-local: `latched`)."""

    def __init__(self, topic: str, type_name: str, callback: Callable[[Any], None], queue_size: int,
                 cls: Any = None, latched: bool = False) -> None:
        from .plan.settings import package_dir
        from .sources import ros2types
        from .sources.ros2wire import msg_class, ros2_type
        self.graph = _graph()
        self.topic = topic
        ros2 = ros2_type(type_name)
        converter = ros2types.Converter([_Conn(topic, ros2, None)], os.path.join(package_dir(), 'msg'),
                                        os.environ.get('ROS_DISTRO') or None)
        cls = cls or msg(type_name)

        self.closed = False

        def on_raw(raw: bytes) -> None:
            if self.closed:
                return
            m = cls()
            try:
                m.deserialize(converter.to_ros1(raw, ros2))
            except Exception:  # noqa: BLE001  (a message of another layout: not ours to take)
                return
            callback(m)
        self.sub = self.graph.node.create_subscription(msg_class(ros2), topic, timed(on_raw),
                                                       _qos(queue_size, latched), raw=True)

    def get_num_connections(self) -> int:
        """Publishers of the topic other than this node (rospy's count of connections)."""
        try:
            return len(self.graph.publishers(self.topic))
        except Exception:  # noqa: BLE001  (the context is already gone)
            return 0

    def unregister(self) -> None:
        self.closed = True
        self.graph.destroy(self.sub)       # on the spinning thread (Ros2Graph.destroy)


def subscriber(topic: str, type_name: str, callback: Callable[[Any], None], queue_size: int = 10,
               cls: Any = None, latched: bool = False) -> Any:
    """A subscription handing genpy messages (of `cls` when given, else of msg(type_name)) to
    `callback`; unregister() ends it. `latched`: on ROS 2 transient-local, to get what a
    transient-local publisher sent before (ROS 1 subscribers get a latched topic's last message
    anyway)."""
    if ros_version() == 2:
        return _Subscription(topic, type_name, callback, queue_size, cls, latched)
    import rospy
    return rospy.Subscriber(topic, cls or msg(type_name), timed(callback), queue_size=queue_size)


def _log(level: str, text: str, *args: Any) -> None:
    if ros_version() == 2:
        graph = current()
        message = text % args if args else text
        if graph is None:
            import sys
            sys.stderr.write('[%s] %s\n' % (level.upper(), message))
            return
        logger = graph.node.get_logger()
        # one call site per severity: rclpy refuses a call site whose severity changes
        if level == 'info':
            logger.info(message)
        elif level == 'warn':
            logger.warning(message)
        else:
            logger.error(message)
        return
    import rospy
    getattr(rospy, 'logerr' if level == 'error' else 'log' + level)(text, *args)   # rospy.logerr


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


def subscriber_nodes(topic: str) -> List[str]:
    """The nodes other than this one subscribed to `topic` ([] when the graph cannot tell)."""
    try:
        if ros_version() == 2:
            graph = _graph()
            from .sources.live2 import node_label
            return sorted(node_label(i) for i in graph.node.get_subscriptions_info_by_topic(topic)
                          if node_label(i) != graph.name)
        import rosgraph
        import rospy
        me = rospy.get_name()
        _, subs, _ = rosgraph.Master(me).getSystemState()
        return sorted(n for t, nodes in subs if t == topic for n in nodes if n != me)
    except Exception:  # noqa: BLE001  (the master may be gone)
        return []


def published_topics() -> Optional[List[Tuple[str, str]]]:
    """[(topic, type)] of every topic with a publisher, or None when the graph cannot tell."""
    try:
        if ros_version() == 2:
            from .sources.ros2types import ros1_name
            return [(t, ros1_name(types[0])) for t, types in _graph().topic_types().items() if types]
        import rosgraph
        import rospy
        return [tuple(x) for x in rosgraph.Master(rospy.get_name()).getPublishedTopics('')]
    except Exception:  # noqa: BLE001  (the master may be gone)
        return None


class _AnySubscription:
    """ROS 2: a raw subscription to whatever type the graph advertises for `topic` (looked up
    every 0.25 s until a publisher appears), each message handed on as ROS 1 bytes."""

    def __init__(self, topic: str, callback: Callable[[str, bytes, Dict[str, Any]], None], queue_size: int) -> None:
        import threading
        self.graph = _graph()
        self.topic, self.callback, self.queue_size = topic, callback, queue_size
        self.sub: Any = None
        self.closed = threading.Event()
        self._thread = threading.Thread(target=self._find, daemon=True, name='any-' + topic)
        self._thread.start()

    def _find(self) -> None:
        from .plan.settings import package_dir
        from .sources import ros2types
        from .sources.ros2wire import is_own, msg_class
        while not self.closed.is_set():
            types = self.graph.topic_types().get(self.topic) if self.graph.ok else None
            if types:
                break
            self.closed.wait(0.25)
        else:
            return
        ros2 = types[0]
        try:
            cls = msg_class(ros2)
        except ImportError:
            return
        converter = ros2types.Converter([_Conn(self.topic, ros2, None)], os.path.join(package_dir(), 'msg'),
                                        os.environ.get('ROS_DISTRO') or None)
        header = dict(converter.header(ros2))
        topic = self.topic

        def on_raw(raw: bytes) -> None:
            if not self.closed.is_set() and not is_own(topic, raw):
                self.callback(header['type'], converter.to_ros1(raw, ros2), header)
        if not self.closed.is_set():
            self.sub = self.graph.node.create_subscription(cls, topic, timed(on_raw),
                                                           _qos_any(self.graph, topic, self.queue_size), raw=True)

    def unregister(self) -> None:
        self.closed.set()
        if self.sub is not None:
            self.graph.destroy(self.sub)   # on the spinning thread (Ros2Graph.destroy)


def _qos_any(graph: Any, topic: str, depth: int) -> Any:
    """Reliable when every publisher of `topic` is, else best effort (sources/live2.py)."""
    from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
    pubs = graph.publishers(topic)
    reliable = bool(pubs) and all(p.qos_profile.reliability == ReliabilityPolicy.RELIABLE for p in pubs)
    return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=max(1, depth),
                      reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
                      durability=DurabilityPolicy.VOLATILE)


def any_subscriber(topic: str, callback: Callable[[str, bytes, Dict[str, Any]], None], queue_size: int = 10,
                   buff_size: int = 65536) -> Any:
    """A subscription to `topic` whatever type it carries: callback(type, ROS 1 bytes, connection
    header) per message (rospy.AnyMsg on ROS 1; this node's own messages are left out on both)."""
    if ros_version() == 2:
        return _AnySubscription(topic, callback, queue_size)
    import rospy
    own = rospy.get_name()

    def on_any(msg: Any) -> None:
        conn = msg._connection_header
        if conn.get('callerid') != own:
            callback(conn.get('type', '?'), msg._buff, conn)
    return rospy.Subscriber(topic, rospy.AnyMsg, timed(on_any), queue_size=queue_size, buff_size=buff_size)
