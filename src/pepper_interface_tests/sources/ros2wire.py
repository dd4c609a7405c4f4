"""ROS 1 messages onto a ROS 2 graph: the one conversion the rclpy side publishes with.

Everything above the seam builds ROS 1 (genpy) messages, on either ROS. On ROS 2 a message is
serialized as ROS 1 wire bytes, turned into CDR by rosbags' ros1_to_cdr (the inverse of what
sources/ros2types.Converter does for what is read: Header loses seq, time becomes
builtin_interfaces/Time with the same two words) and published raw by an rclpy publisher of
the ROS 2 type of the same name ('sensor_msgs/Range' -> sensor_msgs/msg/Range), so a C++
subscriber (naoqi_driver2's /cmd_vel, /speech) receives an ordinary message.
"""
import collections
import functools
import io
import os
import threading
from typing import Any, Deque, Dict, Optional

# what this process published last on each topic it also listens to (/diagnostics): a ROS 2
# subscription callback does not say who sent a message, so sources/live2.py drops a message
# byte-equal to one of these, as sources/live.py drops its own node's on ROS 1. Cyclone DDS
# hands a raw subscription the serialized message padded with zeros to a multiple of 4 bytes
# (a 10-byte std_msgs/String arrives as 12 bytes, its encapsulation header unchanged): the
# padding is not part of the comparison
OWN_KEEP = 8
CDR_ALIGN = 4
_own: Dict[str, Deque[bytes]] = {}
_own_lock = threading.Lock()


def is_own(topic: str, raw: bytes) -> bool:
    """True when `raw` is one of the last OWN_KEEP messages this process published on `topic`,
    padded or not (CDR_ALIGN)."""
    if topic not in _own:       # every message of every topic passes here: most are no own topic
        return False
    with _own_lock:
        kept = list(_own[topic])
    return any(_same(raw, mine) for mine in kept)


def _same(raw: bytes, mine: bytes) -> bool:
    """`raw` is `mine`, or `mine` followed by the zeros that pad it to a multiple of CDR_ALIGN."""
    extra = len(raw) - len(mine)
    return 0 <= extra < CDR_ALIGN and raw[:len(mine)] == mine and not any(raw[len(mine):])


def ros2_type(ros1_type: str) -> str:
    """'sensor_msgs/Range' -> 'sensor_msgs/msg/Range'; this package's copies of naoqi_bridge_msgs
    types go out under naoqi_bridge_msgs, as naoqi_driver2 declares them."""
    pkg, name = ros1_type.split('/')
    return '%s/msg/%s' % (pkg, name)


@functools.lru_cache(maxsize=None)
def typestore(msg_dir: str, distro: Optional[str] = None) -> Any:
    """rosbags' typestore with the standard types of `distro` (Humble's when unknown) and this
    package's msg/ types (ros2types.package_msg_types)."""
    from rosbags.typesys import Stores, get_typestore

    from . import ros2types
    name = ros2types.DISTROS.get((distro or '').strip().lower(), ros2types.DISTROS[ros2types.DEFAULT_DISTRO])
    store = get_typestore(getattr(Stores, name, Stores.ROS2_HUMBLE))
    own = {k: v for k, v in ros2types.package_msg_types(msg_dir).items() if k not in store.fielddefs}
    store.register(own)
    return store


def to_cdr(msg: Any, store: Any) -> bytes:
    """One genpy message as the CDR bytes of its ROS 2 type."""
    buff = io.BytesIO()
    msg.serialize(buff)
    return bytes(store.ros1_to_cdr(buff.getvalue(), ros2_type(msg._type)))


def msg_class(ros2_type: str) -> Any:
    """The rclpy (rosidl) class of 'pkg/msg/Name'; ImportError naming what to install."""
    import importlib
    parts = ros2_type.split('/')
    if len(parts) != 3:
        raise ImportError('%s is not a message type' % ros2_type)
    try:
        module = importlib.import_module('%s.%s' % (parts[0], parts[1]))
        cls = getattr(module, parts[2])
    except (ImportError, AttributeError):
        raise ImportError('the ROS 2 message package %s is not installed (source its workspace)'
                          % parts[0]) from None
    if not hasattr(cls, 'get_fields_and_field_types'):    # a ROS 1 (genpy) package came first
        raise ImportError('%s is ROS 1\'s on this Python path, not ROS 2\'s (source the ROS 2 '
                          'setup file after any ROS 1 one)' % ros2_type)
    return cls


def default_msg_dir() -> str:
    from ..plan.settings import package_dir
    return os.path.join(package_dir(), 'msg')


class RawPublisher:
    """An rclpy publisher that takes genpy messages (rospy.Publisher's publish,
    get_num_connections and unregister)."""

    def __init__(self, node: Any, topic: str, ros1_type: str, qos: Any = 10,
                 msg_dir: Optional[str] = None, remember: bool = False,
                 destroy: Optional[Any] = None) -> None:
        """`destroy(publisher)`: how unregister() destroys it (live2.Ros2Graph.destroy: on the
        spinning thread); the node's destroy_publisher when not given."""
        self.node = node
        self.destroy = destroy
        self.topic = self.name = topic
        self.remember = remember
        self.store = typestore(msg_dir or default_msg_dir(), os.environ.get('ROS_DISTRO') or None)
        self.type_name = ros1_type
        self.pub = node.create_publisher(msg_class(ros2_type(ros1_type)), topic, qos)

    def publish(self, msg: Any) -> None:
        raw = to_cdr(msg, self.store)
        if self.remember:
            with _own_lock:
                _own.setdefault(self.topic, collections.deque(maxlen=OWN_KEEP)).append(raw)
        self.pub.publish(raw)

    def get_num_connections(self) -> int:
        return self.pub.get_subscription_count()

    def unregister(self, linger: float = 0.5) -> None:
        """Destroyed once every subscriber acknowledged what was sent (a reliable topic, at most
        `linger` s): a stop published just before the end is delivered, not dropped with the
        writer."""
        try:
            from rclpy.duration import Duration
            self.pub.wait_for_all_acked(Duration(nanoseconds=int(linger * 1e9)))
        except Exception:  # noqa: BLE001  (best effort, or the context is gone)
            pass
        if self.destroy is not None:
            self.destroy(self.pub)
            return
        try:
            self.node.destroy_publisher(self.pub)
        except Exception:  # noqa: BLE001  (the context is already gone)
            pass
