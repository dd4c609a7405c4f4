"""The robot's transform tree over the whole run: what /tf and /tf_static carried, kept in a tf2
buffer (sources/tf_buffer.py) that every sensor's frame is looked up in, and the record the `tf`
row judges (sensors/tf.py).

What naoqi_driver publishes (line numbers: ros-naoqi/naoqi_driver at aed1b87; docs/tf.md):
- `JointStateConverter` loads the robot description share/urdf/pepper.urdf
  (src/tools/robot_description.cpp:34-58, src/helpers/filesystem_helpers.hpp:113-124) and
  builds the URDF's tree (src/converters/joint_state.cpp:57-69); with every joint state it
  puts every joint's transform, moving (:207-236) and fixed (:239-265), stamped with the joint
  state's own stamp (:94, :150-151), plus `odom -> base_link` from ALMotion's torso pose
  (:162-185), in one TFMessage on /tf (src/publishers/joint_state.cpp:33-42). 83 joints + odom:
  84 parent-child pairs, at the joint states' rate (share/boot_config.json "joint_states": 50
  Hz); nothing on /tf_static.
- Without its robot description (the file not found), `reset()` returns before building the
  tree (joint_state.cpp:59-63): /tf then carries `odom -> base_link` alone.

The witness listens to /tf and /tf_static for the whole run (live: subscribers; a bag: its
recorded /tf, in record order), next to the sensors' windows, like the stiffness witness
(sensors/stiffness.py). Its record is bounded: per child frame its parents and its publishers
(with their latest transform), counts and extremes; the transforms themselves live in tf2's
buffer for its cache time only.
"""
import math
import struct
import threading
from collections import OrderedDict, deque
from typing import TYPE_CHECKING, Any, Deque, Dict, List, Optional, Set, Tuple

from ..sources.handling import Handling
from ..sources.tf_buffer import TF2_MISSING, Pose, TfBuffer, yaw_of
from ..sources.witness import TopicWitness
from .tf_layout import LayoutDecoder

if TYPE_CHECKING:
    from ..plan.model import TestPlan

TF_TYPE = 'tf2_msgs/TFMessage'
TF_SENSOR = 'tf'                 # the catalog's row of /tf
DEFAULT_TF = '/tf'
# Two transforms of one child frame from two nodes "differ" beyond these: a millimetre or a
# thousandth of a radian is far above float rounding and far below any real mounting error.
SAME_M = 1e-3
SAME_RAD = 1e-3
# A node's tree is read into the record (parents, publishers) once per this many seconds of
# stamps when its messages keep their size: the structure of a tree does not change at 50 Hz,
# and tf2's buffer gets every transform regardless
RECORD_EVERY = 0.5
# A node's /tf messages of one layout (their count of transforms and first parent and child)
# are decoded and put into tf2's buffer at most once per THIN_S s of stamps; the others are
# counted (the tf row's window counts every message) and not decoded. naoqi_driver sends its 84
# transforms at 50 Hz (joint_state.cpp), and decoding them and tf2's set_transform were the
# tree's whole cost (docs/tf.md, "Memory and cost"). Kept messages are at most THIN_S plus one
# period apart (0.06 s at 50 Hz: every third) and lookups between them interpolate: a joint
# whose speed changes by dv within one gap is off by at most dv * gap / 4, 0.011 rad for a head
# starting or stopping a 0.7 rad/s turn, about half of head_tolerance (0.02 rad); a base
# stopping from 0.55 m/s, 8 mm against odom_tolerance's 0.05 m.
THIN_S = 0.05
# The share of the latest messages, the least delayed, whose stamps the tf row judges for a
# clock offset or stale stamps (sensors/tf.py): a clock behind or ahead, or a driver stamping
# old data, shifts every message, these too; a backlog (this PC busy: messages waiting in
# sensorTest's queue; a bursty WiFi holding them) delays some and leaves those handled while
# sensorTest kept up fresh. A tenth: beside six busy loops sensorTest keeps up with /tf most of
# the time; the emulator's WiFi holds it 0.30-0.45 s in every 1.5-3.5 s (issue 41).
FRESHEST = 0.1
_U32 = struct.Struct('<I')
_STAMP = struct.Struct('<II')


class Link:
    """What the run saw of one child frame."""

    __slots__ = ('parents', 'publishers', 'count', 'static')

    def __init__(self) -> None:
        self.parents: Dict[str, int] = OrderedDict()      # parent -> transforms naming it
        self.publishers: Dict[str, Pose] = OrderedDict()  # node -> its latest transform
        self.count = 0
        self.static = False


class TreeRecord:
    """The bounded record of /tf and /tf_static over the run (thread-safe)."""

    def __init__(self, cache_time: float = 10.0) -> None:
        self.buffer = TfBuffer(cache_time)
        self._lock = threading.Lock()
        self.links: Dict[str, Link] = OrderedDict()
        self.messages = 0           # decoded into the buffer
        self.thinned = 0            # seen and not decoded (THIN_S)
        self.static_messages = 0
        self.transforms = 0
        self.refused = 0
        self.first_stamp: Optional[float] = None     # the earliest stamp of the first message
        self.newest_stamp: Optional[float] = None    # the newest stamp so far (non-static)
        # stamp - arrival (s) per message, the message's newest stamp: > 0 in the future
        self.max_ahead: Optional[float] = None
        self.max_behind: Optional[float] = None
        self.ahead_over: Dict[float, int] = {}        # threshold -> messages beyond it
        self.lags: Deque[float] = deque(maxlen=2000)  # arrival - newest stamp, the latest messages
        self.nodes: Set[str] = set()
        self.known: Set[str] = set()                  # every frame named so far
        self._recorded: Dict[Tuple[str, bool, int], float] = {}   # (node, static, size) -> stamp

    def add(self, msg: Any, static: bool, node: str, ros_now: float) -> None:
        transforms = msg.transforms
        refused = self.buffer.add(transforms, static, node)
        newest, earliest = _newest_earliest(transforms)
        with self._lock:
            self.nodes.add(node)
            self.messages += 1
            self.static_messages += int(static)
            self.transforms += len(transforms)
            self.refused += refused
            # the links (parents, publishers and their latest transforms) of a node's message
            # like its last one are read every RECORD_EVERY s of stamps, not every message
            key = (node, static, len(transforms))
            last = self._recorded.get(key)
            if static or last is None or newest is None or abs(newest - last) >= RECORD_EVERY:
                self._recorded[key] = newest if newest is not None else 0.0
                self._record_links(transforms, static, node)
            if newest is None or static:
                return      # a static transform holds at every time: its stamp is no lag
            if self.first_stamp is None:
                self.first_stamp = earliest
            self.newest_stamp = newest if self.newest_stamp is None else max(self.newest_stamp, newest)
            ahead = newest - ros_now
            self.lags.append(-ahead)
            self.max_ahead = ahead if self.max_ahead is None else max(self.max_ahead, ahead)
            self.max_behind = -ahead if self.max_behind is None else max(self.max_behind, -ahead)

    def count_thinned(self) -> None:
        with self._lock:
            self.thinned += 1

    def typical_lag(self) -> Optional[float]:
        """The median of arrival - newest stamp over the latest messages (s; < 0: in the
        future), or None before the first timed message."""
        return self.lag_quantile(0.5)

    def lag_quantile(self, q: float) -> Optional[float]:
        """The q-quantile of arrival - newest stamp over the latest messages (FRESHEST: the
        least delayed ones, which show the stamps' own offset), or None before the first."""
        with self._lock:
            lags = sorted(self.lags)
        return lags[min(len(lags) - 1, int(q * len(lags)))] if lags else None

    def _record_links(self, transforms: Any, static: bool, node: str) -> None:
        for t in transforms:
            child, parent = t.child_frame_id.lstrip('/'), t.header.frame_id.lstrip('/')
            self.known.add(child)
            self.known.add(parent)
            link = self.links.get(child)
            if link is None:
                link = self.links[child] = Link()
            link.count += 1
            link.static = link.static or static
            link.parents[parent] = link.parents.get(parent, 0) + 1
            p, q = t.transform.translation, t.transform.rotation
            link.publishers[node] = ((p.x, p.y, p.z), (q.x, q.y, q.z, q.w))

    # --- the tree ----------------------------------------------------------------------------
    def parent_map(self) -> Dict[str, str]:
        """child -> its most named parent."""
        with self._lock:
            return {c: max(link.parents, key=lambda p: link.parents[p]) for c, link in self.links.items()}

    def frames(self) -> Set[str]:
        pm = self.parent_map()
        return set(pm) | set(pm.values())

    def top_of(self, frame: str) -> Tuple[str, List[str]]:
        """The highest frame reached walking up from `frame` and the walk ([frame, ...,
        top]); a loop ends the walk where it closes."""
        pm = self.parent_map()
        walk = [frame]
        while walk[-1] in pm and pm[walk[-1]] not in walk:
            walk.append(pm[walk[-1]])
        return walk[-1], walk

    def path(self, frame: str, target: str) -> List[str]:
        """The frames from `frame` up to the lowest frame it shares with `target` and down to
        `target`, by the parents recorded ([] when the two are in different trees)."""
        _, up = self.top_of(frame)
        _, down = self.top_of(target)
        common = next((f for f in up if f in down), None)
        if common is None:
            return []
        return up[:up.index(common) + 1] + list(reversed(down[:down.index(common)]))

    def roots(self) -> List[str]:
        pm = self.parent_map()
        return sorted({p for p in pm.values() if p not in pm})

    def loops(self) -> List[List[str]]:
        """Each loop of parents, as the frames along it."""
        pm = self.parent_map()
        seen: Set[str] = set()
        out = []
        for start in pm:
            walk: List[str] = []
            f = start
            while f in pm and f not in walk and f not in seen:
                walk.append(f)
                f = pm[f]
            if f in walk:
                out.append(walk[walk.index(f):] + [f])
            seen.update(walk)
        return out

    def conflicts(self) -> List[Tuple[str, List[str], bool]]:
        """(child, its publishers, whether their latest transforms differ) for each child frame
        published by more than one node, or under more than one parent."""
        out = []
        with self._lock:
            for child, link in self.links.items():
                if len(link.publishers) > 1:
                    poses = list(link.publishers.values())
                    differ = any(_differ(poses[0], p) for p in poses[1:]) or len(link.parents) > 1
                    out.append((child, list(link.publishers), differ))
        return out

    def count_pairs(self) -> int:
        with self._lock:
            return len(self.links)


def _differ(a: Pose, b: Pose) -> bool:
    dist = math.sqrt(sum((x - y) ** 2 for x, y in zip(a[0], b[0])))
    dot = abs(sum(x * y for x, y in zip(a[1], b[1])))
    angle = 2.0 * math.acos(min(1.0, dot))
    return dist > SAME_M or angle > SAME_RAD


class TfTopic(TopicWitness):
    """A sources.Listener of /tf (or /tf_static) that feeds the run's TreeRecord, naming the
    node of each message (its connection's callerid: a live subscriber's header, a bag's
    connection record)."""

    queue_size = 200        # 50 messages a second from naoqi_driver alone
    buff_size = 1 << 20

    def __init__(self, record: TreeRecord, topic: str, static: bool) -> None:
        super().__init__(topic, TF_TYPE)      # another type: the tf row says so
        self.record = record
        self.static = static
        self._kept: Dict[Tuple[str, bytes], float] = {}     # layout -> stamp of its last kept message
        self._decoder = LayoutDecoder(TF_TYPE)      # kept messages of a known layout, in place

    def feed_raw(self, type_name: str, buff: bytes, t_recv: float, ros_now: float,
                 conn: Optional[Dict[str, Any]] = None, own: Optional[Handling] = None) -> None:
        """Every /tf_static message; a /tf message unless its layout's last kept message is less
        than THIN_S s of stamps older (read from the ROS 1 bytes before anything is decoded)."""
        if not self.static and type_name == self.type_name:
            peeked = _peek(buff)
            if peeked is not None:
                caller = (conn or {}).get('callerid') or '?'
                key = (str(caller), peeked[0])
                last = self._kept.get(key)
                if last is not None and 0.0 <= peeked[1] - last < THIN_S:
                    self.record.count_thinned()
                    return
                if len(self._kept) > 1000:      # bounded: layouts of a run are a handful
                    self._kept.clear()
                self._kept[key] = peeked[1]
                try:
                    msg = self._decoder.decode(key, buff)
                except Exception:   # a broken message: the tf row's to report, as any other
                    return
                self.take_full(msg, t_recv, ros_now, conn)
                return
        super().feed_raw(type_name, buff, t_recv, ros_now, conn, own)

    def take_full(self, msg: Any, t_recv: float, ros_now: float, conn: Optional[Dict[str, Any]]) -> None:
        caller = (conn or {}).get('callerid') or '?'
        node = caller.decode('utf-8', 'replace') if isinstance(caller, bytes) else str(caller)
        self.record.add(msg, self.static, node, ros_now)

    def use_record_clock(self) -> None:
        pass

    def observe_connections(self, n: int, now: float) -> None:
        pass


def _newest_earliest(transforms: Any) -> Tuple[Optional[float], Optional[float]]:
    """The newest and earliest stamp (s, as genpy's to_sec) of a message's transforms, ordered
    as genpy orders Times (by nanoseconds) without building a Time per comparison."""
    if not transforms:
        return None, None
    stamps = [t.header.stamp for t in transforms]
    ns = [s.secs * 1000000000 + s.nsecs for s in stamps]
    hi, lo = stamps[ns.index(max(ns))], stamps[ns.index(min(ns))]
    return float(hi.secs) + float(hi.nsecs) / 1e9, float(lo.secs) + float(lo.nsecs) / 1e9


def _peek(buff: bytes) -> Optional[Tuple[bytes, float]]:
    """(layout: the count of transforms and the first transform's parent and child, as bytes;
    the first transform's stamp in s) of a ROS 1 TFMessage, or None when it is empty or too
    short (then it is decoded as any other: a broken one is the tf row's to report)."""
    try:
        (n,) = _U32.unpack_from(buff, 0)
        if n == 0:
            return None
        secs, nsecs = _STAMP.unpack_from(buff, 8)
        (parent,) = _U32.unpack_from(buff, 16)
        (child,) = _U32.unpack_from(buff, 20 + parent)
        end = 24 + parent + child
        if end > len(buff):
            return None
        return bytes(buff[0:4]) + bytes(buff[16:end]), secs + nsecs * 1e-9
    except struct.error:
        return None


class Agreement(TopicWitness):
    """A witness of another topic whose value tf must agree with at the message's stamp:
    /naoqi_driver/odom's pose against `odom -> base_link`, /joint_states' HeadYaw against
    `torso -> Neck`'s turn about z. Each message waits until /tf has data past its stamp (the
    driver publishes both from one loop, joint_state.cpp:94-201), then is compared once; one
    message per THIN_S s of stamps is decoded and compared."""

    WAIT = 5.0      # s of arrival a message waits for /tf before it is compared anyway

    def __init__(self, record: TreeRecord, topic: str, type_name: str) -> None:
        super().__init__(topic, type_name)
        self.record = record
        self._pending: Deque[Tuple[float, float, Any]] = deque(maxlen=500)
        self._taken: Optional[float] = None      # the stamp of the last message decoded
        self._lock = threading.Lock()
        self.compared = 0
        self.unplaced = 0
        self.worst: Optional[float] = None
        self.worst_at: Optional[float] = None
        self.worst_what = ''

    def feed_raw(self, type_name: str, buff: bytes, t_recv: float, ros_now: float,
                 conn: Optional[Dict[str, Any]] = None, own: Optional[Handling] = None) -> None:
        if self.record.first_stamp is None or type_name != self.type_name:
            return      # before the run's first /tf nothing is compared: not even decoded
        # one message per THIN_S s of stamps (the header's, read before decoding): the tree is
        # kept at that pace too, and a tree that does not follow stays wrong for many of them
        try:
            secs, nsecs = _STAMP.unpack_from(buff, 4)
        except struct.error:
            secs, nsecs = 0, 0
        stamp = secs + nsecs * 1e-9
        if self._taken is not None and 0.0 <= stamp - self._taken < THIN_S:
            return
        self._taken = stamp
        super().feed_raw(type_name, buff, t_recv, ros_now, conn, own)

    def take(self, msg: Any, t_recv: float) -> None:
        value = self.value(msg)
        if value is None:
            return
        with self._lock:
            self._pending.append((t_recv, msg.header.stamp.to_sec(), value))
        self.resolve(t_recv)

    def resolve(self, now: Optional[float] = None) -> None:
        """Compare every waiting message /tf has caught up with (all of them: now None)."""
        while True:
            with self._lock:
                if not self._pending:
                    return
                t_recv, stamp, value = self._pending[0]
                latest = self.record.buffer.latest(*self.chain())
                ready = latest is not None and (latest == 0.0 or stamp <= latest)
                if not ready and now is not None and now - t_recv < self.WAIT:
                    return
                self._pending.popleft()
            first = self.record.first_stamp
            if first is None or stamp < first:
                continue        # before the run's first /tf: not judged
            self._compare(stamp, value)

    def _compare(self, stamp: float, value: Any) -> None:
        found = self.measure(stamp)
        if found is None:
            self.unplaced += 1
            return
        diff, what = self.difference(value, found)
        self.compared += 1
        if self.worst is None or diff > self.worst:
            self.worst, self.worst_at, self.worst_what = diff, stamp, what

    # --- for subclasses
    def chain(self) -> Tuple[str, str]:
        """(frame, target) of the transform compared."""
        raise NotImplementedError

    def value(self, msg: Any) -> Any:
        raise NotImplementedError

    def measure(self, stamp: float) -> Any:
        raise NotImplementedError

    def difference(self, value: Any, found: Any) -> Tuple[float, str]:
        raise NotImplementedError


class OdomAgreement(Agreement):
    """odom.cpp:56-93 and joint_state.cpp:162-185 read the same ALMotion pose
    (getPosition("Torso", FRAME_WORLD)): `odom -> base_link` at an odometry message's stamp is
    its pose. Difference: metres between the positions plus the yaw difference times 0.3 m
    (Pepper's half-width), one number a tolerance in metres bounds."""

    def __init__(self, record: TreeRecord, topic: str, parent: str = 'odom', child: str = 'base_link') -> None:
        super().__init__(record, topic, 'nav_msgs/Odometry')
        self.parent, self.child = parent, child

    def chain(self) -> Tuple[str, str]:
        return self.child, self.parent

    def value(self, msg: Any) -> Any:
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        self.parent = msg.header.frame_id or self.parent
        self.child = msg.child_frame_id or self.child
        return (p.x, p.y, yaw_of((q.x, q.y, q.z, q.w)))

    def measure(self, stamp: float) -> Any:
        pose = self.record.buffer.pose(self.parent, self.child, stamp)
        if pose is None:
            return None
        return (pose[0][0], pose[0][1], yaw_of(pose[1]))

    def difference(self, value: Any, found: Any) -> Tuple[float, str]:
        d = math.hypot(value[0] - found[0], value[1] - found[1])
        dyaw = abs(_wrap(value[2] - found[2]))
        return d + 0.3 * dyaw, '%.3f m and %.3f rad' % (d, dyaw)


class HeadAgreement(Agreement):
    """joint_state.cpp:113-150: each joint's transform is the URDF segment's pose at the joint
    state's own position, same stamp: `torso -> Neck` turns about z by HeadYaw (pepper.urdf,
    joint HeadYaw: parent torso, child Neck, axis 0 0 1)."""

    JOINT = 'HeadYaw'

    def __init__(self, record: TreeRecord, topic: str) -> None:
        super().__init__(record, topic, 'sensor_msgs/JointState')
        self.moved = 0.0        # the largest HeadYaw change seen (rad): did the head turn?
        self._first: Optional[float] = None

    def chain(self) -> Tuple[str, str]:
        return 'Neck', 'torso'

    def value(self, msg: Any) -> Any:
        try:
            yaw = float(msg.position[list(msg.name).index(self.JOINT)])
        except (ValueError, IndexError):
            return None
        if not math.isfinite(yaw):
            return None
        if self._first is None:
            self._first = yaw
        self.moved = max(self.moved, abs(yaw - self._first))
        return yaw

    def measure(self, stamp: float) -> Any:
        pose = self.record.buffer.pose('torso', 'Neck', stamp)
        return None if pose is None else yaw_of(pose[1])

    def difference(self, value: Any, found: Any) -> Tuple[float, str]:
        d = abs(_wrap(value - found))
        return d, 'HeadYaw %.3f rad, torso -> Neck turned %.3f rad' % (value, found)


def _wrap(a: float) -> float:
    return (a + math.pi) % (2.0 * math.pi) - math.pi


class Tree:
    """The run's tree and its witnesses, offered to the checks as ctx.services.tree."""

    def __init__(self, tf_topic: str, cache_time: float = 10.0) -> None:
        self.record = TreeRecord(cache_time)
        self.topic = tf_topic
        self.static_topic = tf_topic + '_static'
        self.odom: Optional[OdomAgreement] = None
        self.head: Optional[HeadAgreement] = None

    def listeners(self, topics: Dict[str, str]) -> List[Any]:
        out: List[Any] = [TfTopic(self.record, self.topic, False),
                          TfTopic(self.record, self.static_topic, True)]
        if topics.get('odometry'):
            self.odom = OdomAgreement(self.record, topics['odometry'])
            out.append(self.odom)
        if topics.get('jointState'):
            self.head = HeadAgreement(self.record, topics['jointState'])
            out.append(self.head)
        return out

    def settle(self) -> None:
        """Compare what the agreement witnesses still hold (the end of the run or the tf row)."""
        for w in (self.odom, self.head):
            if w is not None:
                w.resolve(None)


def tf_topic(plan: 'TestPlan', topics: Dict[str, str]) -> Optional[str]:
    """The run's /tf: the tf row's topic in the plan, else the topics file's, else /tf when
    the run checks any sensor (every driver publishes its tree there)."""
    for s in plan.sensors:
        if s.name == TF_SENSOR and s.topic:
            return s.topic
    return topics.get(TF_SENSOR) or DEFAULT_TF


def witnesses(plan: 'TestPlan', ctx: Any) -> List[Any]:
    """The tree's listeners for this run (the runner attaches them to the source before the
    first window), offered to the checks as ctx.services.tree (ctx: the run's
    sensors.base.RunContext, which names this module's Tree)."""
    topic = tf_topic(plan, dict(ctx.topics))
    if topic is None or TF2_MISSING:
        return []       # no tree: the tf row says why (sensors/tf.py)
    tree = Tree(topic)
    ctx.services.tree = tree
    return tree.listeners(dict(ctx.topics))
