"""The robot's transform tree as tf2 keeps it: a `tf2_ros.Buffer` fed from /tf and /tf_static
(on ROS 2, the same tf2 without rospy: tf2_py's BufferCore, see _ros2_tf2_core).

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
    """ROS 1's compiled tf2 (tf2_py, tf2's BufferCore) in a ROS 2 process. When first imported,
    tf2_py keeps the modules `rospy` (for the Time it returns) and `geometry_msgs.msg` (for the
    TransformStamped lookups return, and the Vector3 and Quaternion set_transform checks the
    parts against: geometry2 tf2_py/src/tf2_py.cpp, staticInit and transform_converter). In a
    ROS 2 environment those names are rclpy's and rosidl's, which it cannot fill; so for that
    one import they stand for genpy's Time and Duration and the genpy classes the tree decodes
    /tf with (messages.message_class), and ROS 2's own are put back right after. Nothing of
    rospy runs: tf2_ros.Buffer is BufferCore plus rospy's services and waits, not used here."""
    import struct
    import sys
    import types

    from .messages import message_class
    tfm = message_class('tf2_msgs/TFMessage')
    one = tfm()
    # one zero transform in ROS 1 bytes: its nested objects give the classes tf2_py checks
    one.deserialize(struct.pack('<IIIIII7d', 1, 0, 0, 0, 0, 0, *([0.0] * 7)))
    ts = one.transforms[0]
    geometry = types.ModuleType('geometry_msgs.msg')
    geometry.TransformStamped = type(ts)                      # type: ignore[attr-defined]
    geometry.Transform = type(ts.transform)                   # type: ignore[attr-defined]
    geometry.Vector3 = type(ts.transform.translation)         # type: ignore[attr-defined]
    geometry.Quaternion = type(ts.transform.rotation)         # type: ignore[attr-defined]
    clock = types.ModuleType('rospy')
    clock.Time, clock.Duration = genpy.Time, genpy.Duration   # type: ignore[attr-defined]
    names = ('rospy', 'geometry_msgs.msg')
    saved = {n: sys.modules.get(n) for n in names}
    sys.modules['rospy'], sys.modules['geometry_msgs.msg'] = clock, geometry
    try:
        return importlib.import_module('tf2_py').BufferCore
    finally:
        for n in names:
            if saved[n] is None:
                sys.modules.pop(n, None)
            else:
                sys.modules[n] = saved[n]   # type: ignore[assignment]


if os.environ.get('ROS_VERSION', '').strip() == '2':
    try:
        tf2_core = _ros2_tf2_core()
        TF2_MISSING = ''
    except ImportError as exc:      # tf2_py is ROS 1's, built for one Python (docs/ros2.md)
        TF2_MISSING = ('tf2_py cannot be imported on this Python (%s): no sensor\'s frame and no '
                       'tree was judged; fix: install ROS 1\'s tf2_py for this Python (Debian: '
                       'python3-tf2, for /usr/bin/python3)' % exc)
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
    m = _ONLY_TIME.search(error)
    if m:
        return float(m.group(1)) - float(m.group(2))
    return None


class TfBuffer:
    """A tf2 buffer of `cache_time` seconds; thread-safe as tf2's BufferCore is (one mutex)."""

    def __init__(self, cache_time: float = CACHE_TIME) -> None:
        if tf2_core is not None:        # ROS 2: the core alone, the same methods
            self._buffer = tf2_core(genpy.Duration.from_sec(cache_time))
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
                put(t, authority)
            except Exception:
                refused += 1
        return refused

    def lookup(self, frame: str, target: str, stamp: float) -> Lookup:
        """Can `frame` be transformed into `target` at `stamp` (seconds)?"""
        ok, error = self._buffer.can_transform_core(target, frame, genpy.Time.from_sec(stamp))
        return Lookup(bool(ok), error or '')

    def latest(self, frame: str, target: str) -> Optional[float]:
        """The newest stamp at which the whole chain from `frame` to `target` is known (tf2's
        getLatestCommonTime; 0.0: static all along, any time), None when there is no chain."""
        try:
            t = self._buffer.get_latest_common_time(target, frame)
        except Exception:
            return None
        return t.to_sec() if hasattr(t, 'to_sec') else float(t) * 1e-9

    def pose(self, target: str, frame: str, stamp: float) -> Optional[Pose]:
        """`frame`'s pose in `target` at `stamp`: ((x, y, z), (qx, qy, qz, qw)), or None."""
        try:
            t = self._buffer.lookup_transform_core(target, frame, genpy.Time.from_sec(stamp))
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
