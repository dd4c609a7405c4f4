"""The robot's transform tree (the `tf` row): /tf itself, judged over the whole run from the
tree's record (sensors/tree.py: what naoqi_driver publishes there, with its lines).

Its window listens to /tf for the generic rules (sensors/stream.py: arrival within --wait, the
rate band; /tf is a shared topic, several publishers are normal). Its own rules, on what the
run's tree witness saw from the start of the run to the end of this window (docs/tf.md):
- one tree: a loop of parents fails, naming its frames; a second root is a warning naming it
  (nothing publishes its parent: the sensors whose frames hang under it fail on their own rows,
  by name, sensors/frames.py);
- `root` (naoqi_driver: odom, joint_state.cpp:176) and `frames` (base_link, base_footprint)
  must be in the tree: naoqi_driver without its robot description publishes odom -> base_link
  alone (joint_state.cpp:59-63), so base_footprint is missing;
- a child frame published by two nodes with different transforms fails, naming the frame and
  the nodes (a second robot_state_publisher next to naoqi_driver, with another description);
  the same transform from two nodes is a warning;
- stamps: the newest stamp of a message more than `future` s ahead of its arrival fails (tf2
  refuses to look up past its newest data: every consumer waits, then gives up); more than
  `stale` s behind fails (the driver stamps the tree just before it publishes,
  joint_state.cpp:94 and :199-202: tens of milliseconds). Judged on the freshest tenth of the
  latest messages (tree.FRESHEST: an offset shifts every message, a busy PC or WiFi delays
  some); stamps old in the median only are a warning that names the late delivery;
- `odom -> base_link` at an odometry message's stamp is its pose (odom.cpp:56-93 and
  joint_state.cpp:162-185 read the same ALMotion pose): more than `odom_tolerance` apart fails;
- `torso -> Neck` turns about z by /joint_states' HeadYaw at its stamp (joint_state.cpp:113-150,
  pepper.urdf joint HeadYaw): more than `head_tolerance` apart fails. With --move the head
  turns, so this holds the chain to the measured yaw while it moves.
"""
import os
import struct
from typing import TYPE_CHECKING, Any, List, Optional

from ..sources import messages
from ..sources.tf_buffer import TF2_MISSING
from .base import Check, fmt
from .lag import BUSY_LOAD_PER_CORE, load_now
from .tree import FRESHEST
from .values.tf import TfLink, TfValues

if TYPE_CHECKING:
    import genpy

    from ..plan.expectations import TfExpect
    from ..plan.settings import SensorPlan
    from .base import RunContext

LINKS_SHOWN = 120       # links kept for the report's drawing (naoqi_driver: 84)


def _this_pc() -> str:
    """This PC's load, when it is above its cores (sensors/lag.py's rule for a busy PC)."""
    busy = os.getloadavg()[0] > BUSY_LOAD_PER_CORE * (os.cpu_count() or 1)
    return 'this PC%s (%s)' % (' busy' if busy else '', load_now())


class _Count:
    """A TFMessage after the first, as the tf row's window needs it: how many transforms."""

    __slots__ = ('n',)

    def __init__(self, n: int) -> None:
        self.n = n


class TfCheck(Check):
    family = 'tf'
    expect: 'TfExpect'

    def __init__(self, plan: 'SensorPlan', ctx: 'RunContext') -> None:
        super().__init__(plan, ctx)
        self.found: Optional[TfValues] = None
        self.transforms = 0
        self._cls = messages.message_class(plan.sensor.msg_type)

    def decode(self, buff: bytes) -> Any:
        """The first message in full (its fields for the outputs); after it only the number of
        transforms, read from the array's length (the first uint32 of a serialized TFMessage):
        the run's tree witness decodes every message already (sensors/tree.py)."""
        if self.first_fields is None:
            return self._cls().deserialize(buff)
        return _Count(struct.unpack_from('<I', buff, 0)[0] if len(buff) >= 4 else 0)

    def fields(self, msg: 'genpy.Message') -> List[Any]:
        first = msg.transforms[0] if msg.transforms else None
        out: List[Any] = [('Transforms', len(msg.transforms))]
        if first is not None:
            out += [('First parent', first.header.frame_id), ('First child', first.child_frame_id),
                    ('First stamp', '%d.%09d' % (first.header.stamp.secs, first.header.stamp.nsecs))]
        return out

    def on_message(self, msg: 'genpy.Message', t: float) -> None:
        self.transforms += msg.n if isinstance(msg, _Count) else len(msg.transforms)

    def finish(self) -> None:
        tree = self.ctx.services.tree
        if tree is None and TF2_MISSING:
            self.warn(TF2_MISSING)
            return
        if tree is None:
            self.notes.append('the run kept no transform tree: only the stream rules were applied')
            return
        tree.settle()
        record = tree.record
        if record.messages == 0:
            return          # the stream rules say that nothing came
        e = self.expect
        parents = record.parent_map()
        frames = set(parents) | set(parents.values())
        roots, loops = record.roots(), record.loops()
        for loop in loops:
            self.fail('the tree has a loop: %s; tf2 cannot walk it: two publishers disagree on '
                      'which frame is the parent' % ' -> '.join(loop))
        expected_root = e.root
        if expected_root and expected_root not in frames:
            self.fail('%s is not in the tree (%s)%s' % (expected_root, ', '.join(roots) or 'no root',
                                                        self._bare(frames)))
        others = [r for r in roots if r != expected_root and not self._above(r, expected_root, parents)]
        for r in others:
            under = sorted(c for c in parents if self._top(c, parents) == r)
            self.warn('a second tree with its root %s (%d frame%s: %s): nothing publishes %s\'s '
                      'parent; the sensors in these frames fail on their own rows'
                      % (r, len(under), '' if len(under) == 1 else 's', ', '.join(under[:6])
                         + (', ...' if len(under) > 6 else ''), r))
        for frame in e.frames:
            if frame not in frames:
                self.fail('%s is not in the tree%s' % (frame, self._bare(frames)))
        second = []
        for child, nodes, differ in record.conflicts():
            second.append('%s (%s)' % (child, ', '.join(nodes)))
            text = ('%s is published by %d nodes (%s)' % (child, len(nodes), ', '.join(nodes)))
            if differ:
                self.fail(text + ' with different transforms: the tree flips between them; likely '
                          'a second robot_state_publisher next to naoqi_driver (which publishes the '
                          'whole tree itself); fix: stop the second publisher')
            else:
                self.warn(text + ' with the same transform')
        # judged on the freshest tenth of the latest messages (tree.FRESHEST), not the worst
        # single one nor the median: a clock ahead or behind, or a driver stamping old data,
        # shifts every message; a loaded machine or a bursty network delays some (0.73 s once in
        # 475 on a loaded 2-core host; seconds of sensorTest's own backlog beside a build), and
        # what came while sensorTest kept up shows the stamps as they are
        lag, fresh = record.typical_lag(), record.lag_quantile(FRESHEST)
        if fresh is not None and -fresh > e.future:
            self.fail('/tf stamps %s s in the future (the freshest tenth; median %s s, up to %s s; more '
                      'than %s s ahead of their arrival): tf2 has no data for the present until then; '
                      'likely cause: the clock of the driver\'s computer runs ahead of this one; fix: '
                      'synchronise the clocks (chrony/NTP)'
                      % (fmt(-fresh, 3), fmt(-(lag or 0.0), 3), fmt(record.max_ahead or 0.0, 3), fmt(e.future, 3)))
        if fresh is not None and fresh > e.stale:
            self.fail('/tf stamps %s s old when they arrive (even the freshest tenth; median %s s, up to %s s; '
                      'more than %s s): every lookup of a fresh sensor message waits that long or fails with '
                      '"extrapolation into the future"; likely cause: an overloaded driver or a clock behind '
                      'this one; fix: see the driver\'s load and synchronise the clocks'
                      % (fmt(fresh, 3), fmt(lag or 0.0, 3), fmt(record.max_behind or 0.0, 3), fmt(e.stale, 3)))
        elif lag is not None and fresh is not None and lag > e.stale:
            self.warn('/tf came late in bursts: its stamps %s s old when they arrive (median; up to %s s; '
                      'more than %s s) while the freshest tenth were %s s old: the stamps are right and the '
                      'delivery was held up (%s or a bursty network between the driver and this PC); '
                      'tf lookups waited meanwhile' % (fmt(lag, 3), fmt(record.max_behind or 0.0, 3),
                                                       fmt(e.stale, 3), fmt(fresh, 3), _this_pc()))
        odom, head = tree.odom, tree.head
        if odom is not None and odom.worst is not None and odom.worst > e.odom_tolerance:
            self.fail('%s -> %s differs from %s\'s pose by %s (at stamp %.3f; tolerance %s m with '
                      '0.3 m per rad): the tree and the odometry place the robot in two places'
                      % (odom.parent, odom.child, odom.topic, odom.worst_what, odom.worst_at or 0.0,
                         fmt(e.odom_tolerance, 3)))
        if head is not None and head.worst is not None and head.worst > e.head_tolerance:
            self.fail('torso -> Neck does not follow %s\'s HeadYaw: %s at stamp %.3f (tolerance %s '
                      'rad): the head cameras\' frames point elsewhere than the head'
                      % (head.topic, head.worst_what, head.worst_at or 0.0, fmt(e.head_tolerance, 3)))
        if head is not None and head.compared and head.moved > 0.05:
            self.notes.append('the head turned %.2f rad in the run; torso -> Neck followed HeadYaw '
                              'within %s rad' % (head.moved, fmt(head.worst, 3)))
        self.found = TfValues(
            messages=record.messages + record.thinned, static_messages=record.static_messages,
            pairs=record.count_pairs(), roots=roots, loops=loops, publishers=sorted(record.nodes),
            second_publishers=second,
            max_ahead_s=None if record.max_ahead is None else round(record.max_ahead, 4),
            max_behind_s=None if record.max_behind is None else round(record.max_behind, 4),
            odom_compared=odom.compared if odom is not None else 0,
            odom_worst=None if odom is None or odom.worst is None else round(odom.worst, 4),
            head_compared=head.compared if head is not None else 0,
            head_worst_rad=None if head is None or head.worst is None else round(head.worst, 4),
            head_moved_rad=None if head is None or not head.compared else round(head.moved, 4),
            links=[TfLink(c, p) for c, p in list(parents.items())[:LINKS_SHOWN]])

    @staticmethod
    def _top(frame: str, parents: Any) -> str:
        walk = [frame]
        while walk[-1] in parents and parents[walk[-1]] not in walk:
            walk.append(parents[walk[-1]])
        return walk[-1]

    def _above(self, root: str, frame: Optional[str], parents: Any) -> bool:
        """`root` is the root above `frame` (a map -> odom above the driver's tree is fine)."""
        return bool(frame) and self._top(frame or '', parents) == root

    @staticmethod
    def _bare(frames: Any) -> str:
        if len(frames) <= 3:
            return ('; the tree has %d frame%s only: naoqi_driver could not load its robot '
                    'description (share/urdf/pepper.urdf) and publishes odom -> base_link alone; '
                    'fix: install naoqi_driver with its share/urdf and restart it'
                    % (len(frames), '' if len(frames) == 1 else 's'))
        return ''
