"""The robot's transform tree as tf2 keeps it: a `tf2_ros.Buffer` fed from /tf and /tf_static
(on ROS 2, ROS 2's own tf2: geometry2's tf2_py BufferCore, see _ros2_tf2_core).

This is the package's only module that imports tf2 (tf2_ros and its compiled tf2_py): a Python
whose tf2 is built elsewhere replaces this one module. Every question the checks ask of the tree
goes through `TfBuffer`, so the answers are tf2's own, the ones every consumer of /tf (RViz,
navigation, a perception node) gets: tf2 interpolates between stamps, refuses to extrapolate,
and names unconnected trees (geometry2 tf2/src/buffer_core.cpp canTransform/lookupTransform).

Memory is bounded by the buffer's cache time: tf2 keeps, per frame, the transforms of the last
`cache_time` seconds of stamps (buffer_core.cpp: TimeCache::pruneList drops what is older than
the newest stamp minus the cache time), so a long recording costs no more than a short one.
"""
import importlib
import math
import os
import re
from typing import Any, Dict, List, Optional, Sequence, Tuple

import genpy

tf2_ros: Any = None
tf2_core: Any = None        # ROS 2: tf2_py's BufferCore (see _ros2_tf2_core)


def _ros2_tf2_core() -> Any:
    """ROS 2's own tf2 for Python: geometry2's tf2_py BufferCore, the one every Humble install
    has (ros-humble-tf2-py, which tf2_ros_py depends on). The ament index says where it is
    installed, and it is imported from there even when another tf2_py comes first on the path
    (ROS 1's, Debian's python3-tf2, when a ROS 1 path is ahead of ROS 2's)."""
    import sys

    from ament_index_python.packages import PackageNotFoundError, get_package_prefix
    try:
        prefix = os.path.realpath(get_package_prefix('tf2_py'))
    except PackageNotFoundError as exc:
        raise ImportError("ROS 2's tf2_py is not installed (%s)" % exc) from exc
    ours = [d for d in sys.path if d and os.path.realpath(d).startswith(prefix + os.sep)
            and os.path.isfile(os.path.join(d, 'tf2_py', '__init__.py'))]
    if not ours:
        raise ImportError("ROS 2's tf2_py in %s is not on this Python's path (source its setup.bash)" % prefix)
    sys.path.insert(0, ours[0])
    try:
        module = importlib.import_module('tf2_py')
    finally:
        sys.path.remove(ours[0])
    where = os.path.realpath(getattr(module, '__file__', '') or '')
    if not where.startswith(prefix + os.sep):       # another tf2_py was imported before this
        raise ImportError('the tf2_py imported in this process is %s, not ROS 2\'s in %s' % (where, prefix))
    # the classes tf2_py checks a transform's parts against: those its own import found
    from geometry_msgs.msg import Quaternion, Vector3
    _ros2_geometry[:] = [Vector3, Quaternion]
    return module.BufferCore


_ros2_geometry: List[Any] = []      # ROS 2's geometry_msgs Vector3 and Quaternion (_ros2_tf2_core)


class _Nanoseconds:
    """A time or duration as ROS 2's tf2_py reads one: an object with `nanoseconds` (geometry2
    tf2_py/src/tf2_py.cpp, rostime_converter and rosduration_converter)."""

    __slots__ = ('nanoseconds',)

    def __init__(self, nanoseconds: int) -> None:
        self.nanoseconds = nanoseconds


class _Header:
    __slots__ = ('stamp', 'frame_id')

    def __init__(self, stamp: _Nanoseconds, frame_id: str) -> None:
        self.stamp, self.frame_id = stamp, frame_id


class _Transform:
    __slots__ = ('translation', 'rotation')

    def __init__(self, translation: Any, rotation: Any) -> None:
        self.translation, self.rotation = translation, rotation


class _Stamped:
    """A genpy TransformStamped in the form ROS 2's tf2_py reads (tf2_py.cpp setTransform: the
    attributes header.stamp, header.frame_id, child_frame_id, transform.translation and
    transform.rotation; the stamp with `nanoseconds`, which a genpy Time lacks; the translation
    must be a geometry_msgs Vector3 of ROS 2, checkTranslationType refuses any other object, and
    the rotation a Quaternion, or checkRotationType warns on every call)."""

    __slots__ = ('header', 'child_frame_id', 'transform')

    def __init__(self, t: Any) -> None:
        self.header = _Header(_Nanoseconds(_nsec(t.header.stamp.to_sec())), t.header.frame_id)
        self.child_frame_id = t.child_frame_id
        p, q = t.transform.translation, t.transform.rotation
        self.transform = _Transform(_ros2_geometry[0](x=float(p.x), y=float(p.y), z=float(p.z)),
                                    _ros2_geometry[1](x=float(q.x), y=float(q.y), z=float(q.z), w=float(q.w)))


def _nsec(seconds: float) -> int:
    """Seconds as the nanoseconds tf2 holds on ROS 1: ROS 1's tf2_py takes every time through
    its float seconds (tf2_py.cpp rostime_converter: to_sec(), then ros::Time::fromSec, which
    rounds the fraction to the nanosecond), so stamps and lookups are both on that grid (about
    240 ns apart at today's epoch). The same grid on ROS 2 gives the same answers, a lookup at a
    message's own stamp included."""
    sec = math.floor(seconds)
    nsec = int(math.floor((seconds - sec) * 1e9 + 0.5))
    return int(sec) * 1000000000 + nsec


if os.environ.get('ROS_VERSION', '').strip() == '2':
    try:
        tf2_core = _ros2_tf2_core()
        TF2_MISSING = ''
    except ImportError as exc:      # geometry2's tf2_py, in every ROS 2 base install
        TF2_MISSING = ('ROS 2\'s tf2_py cannot be imported (%s): no sensor\'s frame and no tree '
                       'was judged; fix: install it (Humble: sudo apt install ros-humble-tf2-py, '
                       'in ros-humble-ros-base) and source its setup.bash' % exc)
    except Exception as exc:  # noqa: BLE001  (the tree is one row: it never stops a run)
        TF2_MISSING = ('tf2 could not be set up on ROS 2 (%s: %s): no sensor\'s frame and no tree '
                       'was judged' % (type(exc).__name__, exc))
else:
    try:
        tf2_ros = importlib.import_module('tf2_ros')
        TF2_MISSING = ''
    except ImportError as exc:          # tf2_ros imports the compiled tf2_py, built for one Python
        # what the tf row says instead of judging the tree (sensors/tf.py, sensors/tree.py): on
        # Noetic rosdep installs ros-noetic-tf2-ros for the system's Python 3.8; Debian's
        # python3-tf2 is built for its python3 alone (docs/platforms.md)
        TF2_MISSING = ('tf2_ros cannot be imported on this Python (%s): no sensor\'s frame and no tree '
                       'was judged; fix: install tf2_ros for this Python (Noetic: ros-noetic-tf2-ros, '
                       'which rosdep installs; Debian: python3-tf2-ros, for /usr/bin/python3)' % exc)

# tf2's default: BufferCore::DEFAULT_CACHE_TIME, 10 s (tf2/include/tf2/buffer_core.h)
CACHE_TIME = 10.0

# "Lookup would require extrapolation 0.300000000s into the future." (buffer_core.cpp,
# createExtrapolationException1..3); older tf2 wording says "at time X, but only time Y is
# in the buffer", from which the gap is the difference
_EXTRAPOLATION = re.compile(r'extrapolation ([0-9.]+)s? into the (future|past)')
_ONLY_TIME = re.compile(r'at time ([0-9.]+), but only time ([0-9.]+)')
# ROS 2's tf2 (humble tf2/src/cache.cpp, createExtrapolationException2/3): "Lookup would require
# extrapolation into the future.  Requested time X but the latest data is at time Y"
_REQUESTED = re.compile(r'Requested time ([0-9.]+) but the (?:latest|earliest) data is at time ([0-9.]+)')

Pose = Tuple[Tuple[float, float, float], Tuple[float, float, float, float]]


class Lookup:
    """tf2's answer to "can `frame` be transformed to the target at `stamp`?"."""

    __slots__ = ('ok', 'error', 'kind', 'gap')

    def __init__(self, ok: bool, error: str = '') -> None:
        self.ok = ok
        self.error = error
        # '' (ok) | 'extrapolation' (the chain exists, not at this stamp) | 'missing' (a frame
        # tf2 has never heard of) | 'unconnected' (two trees)
        self.kind = '' if ok else classify(error)
        # extrapolation: seconds beyond the data, + into the future, - into the past
        self.gap = extrapolation_gap(error) if self.kind == 'extrapolation' else None


def classify(error: str) -> str:
    text = error.lower()
    if 'extrapolation' in text:
        return 'extrapolation'
    if 'does not exist' in text or 'frame does not exist' in text:
        return 'missing'
    return 'unconnected'


def extrapolation_gap(error: str) -> Optional[float]:
    """Seconds by which a lookup would extrapolate: positive into the future, negative into
    the past; None when tf2's text gives no number."""
    m = _EXTRAPOLATION.search(error)
    if m:
        return float(m.group(1)) * (1.0 if m.group(2) == 'future' else -1.0)
    m = _ONLY_TIME.search(error) or _REQUESTED.search(error)
    if m:
        return float(m.group(1)) - float(m.group(2))
    return None


class TfBuffer:
    """A tf2 buffer of `cache_time` seconds; thread-safe as tf2's BufferCore is (one mutex)."""

    def __init__(self, cache_time: float = CACHE_TIME) -> None:
        self._ros2 = tf2_core is not None
        if self._ros2:        # ROS 2: tf2's BufferCore, the same methods
            self._buffer = tf2_core(_Nanoseconds(_nsec(cache_time)))
        else:       # debug=False: no ~tf2_frames service (a bag run has no master)
            self._buffer = tf2_ros.Buffer(cache_time=genpy.Duration.from_sec(cache_time), debug=False)
        self.cache_time = cache_time

    def add(self, transforms: Sequence[Any], static: bool, authority: str) -> int:
        """A TFMessage's transforms (geometry_msgs/TransformStamped); returns how many tf2
        refused (tf2 rejects NaN, empty or self-parented frames and says why on its log)."""
        refused = 0
        put = self._buffer.set_transform_static if static else self._buffer.set_transform
        for t in transforms:
            try:
                put(_Stamped(t) if self._ros2 else t, authority)
            except Exception:
                refused += 1
        return refused

    def lookup(self, frame: str, target: str, stamp: float) -> Lookup:
        """Can `frame` be transformed into `target` at `stamp` (seconds)?"""
        at = _Nanoseconds(_nsec(stamp)) if self._ros2 else genpy.Time.from_sec(stamp)
        ok, error = self._buffer.can_transform_core(target, frame, at)
        return Lookup(bool(ok), error or '')

    def latest(self, frame: str, target: str) -> Optional[float]:
        """The newest stamp at which the whole chain from `frame` to `target` is known (tf2's
        getLatestCommonTime; 0.0: static all along, any time), None when there is no chain."""
        try:
            t = self._buffer.get_latest_common_time(target, frame)
        except Exception:
            return None
        if hasattr(t, 'nanoseconds'):       # ROS 2: an rclpy Time
            t = genpy.Time(0, t.nanoseconds)
        return float(t.to_sec())

    def pose(self, target: str, frame: str, stamp: float) -> Optional[Pose]:
        """`frame`'s pose in `target` at `stamp`: ((x, y, z), (qx, qy, qz, qw)), or None."""
        at = _Nanoseconds(_nsec(stamp)) if self._ros2 else genpy.Time.from_sec(stamp)
        try:
            t = self._buffer.lookup_transform_core(target, frame, at)
        except Exception:
            return None
        p, q = t.transform.translation, t.transform.rotation
        return (p.x, p.y, p.z), (q.x, q.y, q.z, q.w)

    def frames(self) -> List[str]:
        """Every frame tf2 knows."""
        return [str(f) for f in self._buffer._getFrameStrings()]

    def parents(self) -> Dict[str, str]:
        """child -> parent, as tf2 holds them now (its own YAML dump of the tree)."""
        import yaml
        data = yaml.safe_load(self._buffer.all_frames_as_yaml()) or {}
        return {str(child): str(info.get('parent', ''))
                for child, info in data.items() if isinstance(info, dict)}


def yaw_of(q: Sequence[float]) -> float:
    """The rotation about z of a quaternion (x, y, z, w)."""
    x, y, z, w = q
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
