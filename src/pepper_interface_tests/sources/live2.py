"""The live data source on ROS 2: rclpy subscriptions in raw (CDR) form feeding sensor windows.

The same windows and checks as on ROS 1 (sources/live.py) read the same ROS 1 wire bytes: each
CDR message is converted as a ROS 2 recording's are (ros2types.Converter: one copy for images,
TF and audio, rosbags' conversion for the rest), so nothing above this seam knows which ROS
carried it.

* Types: a ROS 2 subscription needs its type. It is the type the graph advertises for the topic,
  looked up when the window starts and again every POLL s until a publisher appears (a driver
  started after sensorTest is found, as rospy's subscriptions find it on ROS 1).
* QoS: what naoqi_driver2 publishes with is reliable, volatile, keep-last 10 (its
  src/publishers/basic.hpp:72, joint_state.cpp:46; the sonars keep-last 1, sonar.cpp:53; the
  cameras image_transport's default profile, camera.cpp:51). A reliable subscription would not
  match a best-effort publisher (Gazebo's sensor plugins publish best effort), so the
  subscription takes the reliability of the topic's publishers: reliable when every publisher
  is, else best effort. Durability is volatile, which matches volatile and transient-local
  publishers alike, unless every publisher is transient-local (a StaticTransformBroadcaster's
  /tf_static, tf2_ros static_transform_broadcaster.h StaticBroadcasterQoS): then the
  subscription is too, to get what they published before it (ROS 1's latched topics). Depth is
  the window's queue.
* Publishers: the graph's publisher names (`get_publishers_info_by_topic`), this node left out.
  A ROS 2 subscription callback does not say which publisher sent a message (Humble's rclpy has
  no message info), so the windows' connection header names the topic's publisher (callerid)
  only when it has one, and this node's own /diagnostics are told by their bytes
  (sources/ros2wire.is_own).
* The graph has no master: nothing to lose but this process's own context, which a signal
  or rclpy's shutdown ends ("the ROS 2 context was shut down").
* sensorTest's own lag: every callback is wrapped in sources/handling.begin/finish, as on
  ROS 1, and the Handling goes to the window's feed_raw (sensors/lag.py). rclpy's executor runs
  every topic's callbacks on its one spinning thread, so a message also waits for the other
  topics' callbacks: the wait is counted on that thread.
"""
import os
import sys
import threading
import time
from collections import namedtuple
from typing import Any, Dict, List, Optional, Set

from . import Graph, Listener, SourceLost, TopicInfo, handling

POLL = 0.25          # s between looks at the graph for a topic's type and publishers
DESTROY_WAIT = 0.1   # s the spinning thread waits for work before it destroys what it was given
NODE_NAME = 'sensorTest'

_Conn = namedtuple('_Conn', 'topic msgtype msgdef')


def ros_version() -> int:
    """2 when the environment is a ROS 2 one (ROS_VERSION=2, as every ROS 2 setup file sets),
    else 1."""
    return 2 if os.environ.get('ROS_VERSION', '').strip() == '2' else 1


_current: Optional['Ros2Graph'] = None


def current() -> Optional['Ros2Graph']:
    """The graph of this sensorTest run on ROS 2 (None on ROS 1 or before it started)."""
    return _current


class Ros2Graph:
    """One rclpy context and node for sensorTest, spun in a thread of its own."""

    def __init__(self, name: str = NODE_NAME, args: Optional[List[str]] = None,
                 parameters: bool = False) -> None:
        """`parameters`: the node takes every parameter given to it (`--ros-args -p name:=value`
        or `--params-file FILE`), to be read with parameter()."""
        import rclpy
        from rclpy.executors import SingleThreadedExecutor
        self.context = rclpy.Context()
        rclpy.init(args=args, context=self.context)
        self.node = rclpy.create_node(name, context=self.context, start_parameter_services=False,
                                      allow_undeclared_parameters=parameters,
                                      automatically_declare_parameters_from_overrides=parameters)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self._doomed: List[Any] = []        # subscriptions and publishers to destroy (destroy())
        self._doomed_lock = threading.Lock()
        self._stopping = threading.Event()
        self._thread = threading.Thread(target=self._spin, daemon=True, name='rclpy-spin')
        self._thread.start()
        global _current
        _current = self

    def _spin(self) -> None:
        """Spin until the context ends, destroying what destroy() was given between two waits.
        An error in a callback ends rclpy's spin(), and with it every subscription of the run:
        here it is said once per kind of error, and the spinning goes on."""
        said: Set[str] = set()
        while self.context.ok() and not self._stopping.is_set():
            try:
                self.executor.spin_once(timeout_sec=DESTROY_WAIT)
            except Exception as exc:  # noqa: BLE001
                if not self.context.ok():
                    break       # the context shut down under it (a signal, the end of the run)
                what = '%s: %s' % (type(exc).__name__, exc)
                if what not in said:
                    said.add(what)
                    import traceback
                    sys.stderr.write('sensorTest: a ROS 2 callback failed (%s); listening goes on\n%s'
                                     % (what, traceback.format_exc()))
            self._destroy_doomed()

    def destroy(self, entity: Any) -> None:
        """Destroy a subscription or publisher of this node on the spinning thread, within
        DESTROY_WAIT s. Destroyed from another thread while the executor waits, Humble's rclpy
        raises InvalidHandle in the wait ("cannot use Destroyable because destruction was
        requested": the entity's QoS event handlers are in the wait set), which ends spin()
        and every other subscription with it."""
        if threading.current_thread() is self._thread or not self._thread.is_alive():
            self._destroy_now(entity)
            return
        with self._doomed_lock:
            self._doomed.append(entity)

    def _destroy_doomed(self) -> None:
        with self._doomed_lock:
            doomed, self._doomed = self._doomed, []
        for entity in doomed:
            self._destroy_now(entity)

    def _destroy_now(self, entity: Any) -> None:
        from rclpy.subscription import Subscription
        try:
            if isinstance(entity, Subscription):
                self.node.destroy_subscription(entity)
            else:
                self.node.destroy_publisher(entity)
        except Exception:  # noqa: BLE001  (the context is already gone)
            pass

    @property
    def name(self) -> str:
        return self.node.get_fully_qualified_name()

    @property
    def ok(self) -> bool:
        return self.context.ok()

    def parameter(self, name: str) -> Any:
        """The value of the node's parameter `name`; None when it was not given."""
        if not self.node.has_parameter(name):
            return None
        return self.node.get_parameter(name).value

    def now(self) -> float:
        return self.node.get_clock().now().nanoseconds / 1e9

    def topic_types(self) -> Dict[str, List[str]]:
        return {topic: list(types) for topic, types in self.node.get_topic_names_and_types()}

    def publishers(self, topic: str) -> List[Any]:
        """The publishers of `topic` other than this node (TopicEndpointInfo)."""
        me = self.name
        out = []
        for info in self.node.get_publishers_info_by_topic(topic):
            ns = info.node_namespace.rstrip('/')
            if '%s/%s' % (ns, info.node_name) != me:
                out.append(info)
        return out

    def shutdown(self) -> None:
        """Stop the spinning thread and wait for it (at most a second): a thread still inside
        rclpy's wait when the process exits aborts it ("terminate called without an active
        exception", exit -6 in place of the run's code). Then the executor, node and context."""
        self._stopping.set()
        if self._thread is not threading.current_thread():
            self._thread.join(1.0)
        try:
            self.executor.shutdown(timeout_sec=0.5)
            self.node.destroy_node()
        except Exception:  # noqa: BLE001  (already shut down by a signal)
            pass
        try:
            self.context.try_shutdown()
        except Exception:  # noqa: BLE001
            pass


def node_label(info: Any) -> str:
    ns = info.node_namespace.rstrip('/')
    return '%s/%s' % (ns, info.node_name)


class Ros2LiveSource:
    """Subscribes a window (Listener) to its topic for the length of its window, on ROS 2."""
    live = True

    def __init__(self, graph: Ros2Graph, msg_dir: str) -> None:
        self.graph = graph
        self.msg_dir = msg_dir
        self.distro = os.environ.get('ROS_DISTRO') or None
        self.subs: Dict[Listener, Any] = {}
        self.attached: Dict[Listener, List[bool]] = {}   # a window's flag its callback reads
        self.pending: Dict[Listener, float] = {}     # windows whose topic has no type yet
        self._last_conn: Dict[Listener, float] = {}

    @property
    def graph_words(self) -> Optional[Graph]:
        """A ROS 2 graph has no master: a driver is out of reach in another DDS domain, on
        another middleware, or behind ROS_LOCALHOST_ONLY (Humble's; ROS_AUTOMATIC_DISCOVERY_RANGE
        from Iron on)."""
        return Graph('in ROS 2 DDS domain %s' % (os.environ.get('ROS_DOMAIN_ID') or '0'),
                     ' (%s)' % (os.environ.get('RMW_IMPLEMENTATION') or 'the default middleware'),
                     'another ROS_DOMAIN_ID',
                     'ROS_DOMAIN_ID, RMW_IMPLEMENTATION or ROS_LOCALHOST_ONLY differs from the driver\'s')

    def _check(self) -> None:
        if not self.graph.ok:
            raise SourceLost('the ROS 2 context was shut down')

    def attach(self, run: Listener) -> None:
        self._check()
        if not run.listens:
            return
        self.pending[run] = 0.0
        self._subscribe(run, time.monotonic())

    def _subscribe(self, run: Listener, now: float) -> None:
        """Subscribe once the topic's type is known (else try again in POLL s)."""
        if now - self.pending.get(run, 0.0) < POLL and self.pending.get(run):
            return
        self.pending[run] = now
        types = self.graph.topic_types().get(run.topic)
        if not types:
            return
        msgtype = types[0]
        from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

        from . import ros2types
        from .ros2wire import is_own, msg_class
        pubs = self.graph.publishers(run.topic)
        reliable = bool(pubs) and all(p.qos_profile.reliability == ReliabilityPolicy.RELIABLE for p in pubs)
        latched = bool(pubs) and all(p.qos_profile.durability == DurabilityPolicy.TRANSIENT_LOCAL for p in pubs)
        qos = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=max(1, run.queue_size),
                         reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL if latched else DurabilityPolicy.VOLATILE)
        try:
            cls = msg_class(msgtype)
        except ImportError:
            cls = None
        converter = ros2types.Converter([_Conn(run.topic, msgtype, None)], self.msg_dir, self.distro)
        if cls is None or run.topic in converter.problems:
            # a type this process cannot subscribe to: the window hears nothing and the advertised
            # type (lookup) tells the check what was there
            del self.pending[run]
            return
        header = dict(converter.header(msgtype))
        ros1_type = header['type']
        if len(pubs) == 1:
            header['callerid'] = node_label(pubs[0])

        topic = run.topic
        attached = self.attached.setdefault(run, [True])

        def callback(raw: bytes, run: Listener = run) -> None:
            if not attached[0] or is_own(topic, raw):    # detached, or this node's /diagnostics
                return
            with handling.measured() as own:     # how late this process handles it (sources/handling.py)
                run.feed_raw(ros1_type, converter.to_ros1(raw, msgtype), own.t0, self.graph.now(), header, own)

        self.subs[run] = self.graph.node.create_subscription(cls, run.topic, callback, qos, raw=True)
        del self.pending[run]

    def detach(self, run: Listener) -> None:
        self.pending.pop(run, None)
        self._last_conn.pop(run, None)
        self.attached.pop(run, [True])[0] = False      # nothing reaches the window from now on
        sub = self.subs.pop(run, None)
        if sub is not None:
            self.graph.destroy(sub)

    def poll(self, run: Listener, now: float) -> None:
        self._check()
        if run in self.pending:
            self._subscribe(run, time.monotonic())
        if now - self._last_conn.get(run, 0.0) >= POLL and run.listens:
            self._last_conn[run] = now
            run.observe_connections(len(self.graph.publishers(run.topic)), now)

    def published_topics(self) -> Optional[Set[str]]:
        try:
            return {t for t in self.graph.topic_types() if self.graph.publishers(t)}
        except Exception:  # noqa: BLE001  (the context shut down)
            return None

    def lookup(self, topic: str) -> Optional[TopicInfo]:
        from .ros2types import ros1_name
        try:
            types = self.graph.topic_types().get(topic)
            pubs = self.graph.publishers(topic)
        except Exception:  # noqa: BLE001  (the context shut down)
            return None
        return (ros1_name(types[0]) if types else None), sorted(node_label(p) for p in pubs)

    @staticmethod
    def sleep(dt: float) -> None:
        time.sleep(dt)
