"""Can this sensor's data be placed on the robot? Its messages' `frame_id` looked up in the run's
transform tree (sensors/tree.py, tf2's own buffer) into `base_footprint` at the messages' own
stamps: what RViz, navigation or a perception node does with every message (tf2
canTransform/lookupTransform), so a sensor that streams in a frame /tf cannot reach is broken
for all of them. A generic rule of every sensor whose messages carry a header with a frame:
sensors/window.py feeds it beside the stream check and merges its judgement.

Rules (docs/tf.md; the driver's tree: sensors/tree.py):
- target: `base_footprint`, the frame naoqi_driver's laser and base IMU are in
  (src/converters/laser.cpp:213, src/converters/imu.cpp:45) and the root of a mobile base's
  footprint (REP 120);
- a message waits until tf2's latest common time along its chain is at or past its stamp (the
  driver publishes /tf at 50 Hz, a camera's picture may be newer than the latest tree), at most
  WAIT seconds of arrival (UNLINKED seconds for a frame with no chain yet: a tree being
  assembled); one message per SPACING seconds of stamps is looked up (20 lookups a second at
  most per sensor: the tree changes slowly against that);
- a message stamped before the run's first /tf is not judged (nothing was listening then), nor
  one still waiting when the window ends with no /tf newer than it (the tree has not caught up
  yet: a /tf that stopped is the tf row's finding);
- a run without any /tf judges no frame here: the tf row says so, once;
- FAIL: not one looked-up stamp could be placed. The reason names the first missing link (the
  highest frame reached walking up from the sensor's frame: "/tf has nothing above Head"),
  the likely cause and the fix;
- WARN: some stamps could not be placed: how many, and by how much tf2 would have had to
  extrapolate (a part of the chain published late or at a lower rate).
"""
from collections import deque
from typing import TYPE_CHECKING, Deque, List, Optional, Tuple

from ..results import FramePlacement
from ..sources.tf_buffer import Lookup
from .base import Judgement, fmt

if TYPE_CHECKING:
    from .tree import Tree

TARGET = 'base_footprint'
WAIT = 5.0          # s of arrival a message waits for /tf before it is looked up anyway
UNLINKED = 1.0      # s a message whose frame has no chain to the target waits for one
SPACING = 0.05      # s of stamps between two looked-up messages
# fewer frames than this in the whole tree: naoqi_driver without its robot description
# (joint_state.cpp:59-63 leaves only odom -> base_link)
BARE_TREE = 3


class FramePlacer:
    """One sensor's frame, looked up in the run's tree; owned by the sensor's window."""

    def __init__(self, tree: Optional['Tree'], target: str = TARGET) -> None:
        self.tree = tree
        self.target = target
        self._pending: Deque[Tuple[float, float, str]] = deque(maxlen=400)
        self._last_stamp: Optional[float] = None
        self.frame_ids: List[str] = []
        self.judged = 0
        self.placed = 0
        self.failed_kinds: List[str] = []       # the kinds of failure seen (missing, unconnected, extrapolation)
        self.first_error = ''
        self.first_failed_frame = ''
        self.worst_gap: Optional[float] = None
        self.placed_frame = ''              # a frame that was placed (for the chain)

    def add(self, frame_id: str, stamp: float, t_recv: float) -> None:
        """One message's header (called under the window's lock)."""
        if self.tree is None or not frame_id or self.tree.record.first_stamp is None:
            return      # before the run's first /tf: not judged
        frame_id = frame_id.lstrip('/')
        if frame_id not in self.frame_ids and len(self.frame_ids) < 8:
            self.frame_ids.append(frame_id)
        if self._last_stamp is not None and abs(stamp - self._last_stamp) < SPACING:
            return
        self._last_stamp = stamp
        self._pending.append((t_recv, stamp, frame_id))
        self.resolve(t_recv)

    def resolve(self, now: Optional[float], closing: bool = False) -> None:
        """Look up every waiting message the tree has caught up with (tf2's latest common time
        of its chain is at or past its stamp), or that waited long enough: WAIT s, or UNLINKED
        s for a frame with no chain to the target yet. Closing: the rest are looked up when
        unlinked (a missing link stays missing), dropped when the tree lags them."""
        if self.tree is None:
            return
        record = self.tree.record
        while self._pending:
            t_recv, stamp, frame = self._pending[0]
            first = record.first_stamp
            if first is None or stamp < first:
                if closing or first is not None:
                    self._pending.popleft()     # before the run's first /tf: not judged
                    continue
                return
            latest = record.buffer.latest(frame, self.target)
            waited = None if now is None else now - t_recv
            if latest is None:
                ready = closing or (waited is not None and waited >= UNLINKED)
            else:
                ready = latest == 0.0 or stamp <= latest or (waited is not None and waited >= WAIT)
                if closing and not ready:
                    self._pending.popleft()     # the tree has not caught up: not judged
                    continue
            if not ready:
                return
            self._pending.popleft()
            self._look(frame, stamp)

    def _look(self, frame: str, stamp: float) -> None:
        assert self.tree is not None
        record = self.tree.record
        answer = record.buffer.lookup(frame, self.target, stamp)
        if answer.ok and frame not in record.known:     # tf2 places a frame in itself, known or not
            answer = Lookup(False, 'frame %s does not exist in /tf' % frame)
        self.judged += 1
        if answer.ok:
            self.placed += 1
            self.placed_frame = frame
            return
        if answer.kind not in self.failed_kinds:
            self.failed_kinds.append(answer.kind)
        if not self.first_error:
            self.first_error, self.first_failed_frame = answer.error, frame
        if answer.gap is not None and (self.worst_gap is None or abs(answer.gap) > abs(self.worst_gap)):
            self.worst_gap = answer.gap

    # --- at the end of the window --------------------------------------------------------------
    def close(self) -> None:
        self.resolve(None, closing=True)

    def placement(self) -> Optional[FramePlacement]:
        """What the JSON says of the sensor's frame (None: not judged)."""
        if self.tree is None or not self.frame_ids or self.tree.record.messages == 0:
            return None
        frame = self.placed_frame or self.first_failed_frame or self.frame_ids[0]
        record = self.tree.record
        top, walk = record.top_of(frame)
        never = self.placed == 0 and self.judged > 0
        chain = walk if never else record.path(frame, self.target)
        return FramePlacement(frame_id=frame, target=self.target, judged=self.judged,
                              placed=self.placed, chain=chain, missing_above=top if never else '',
                              worst_gap_s=None if self.worst_gap is None else round(self.worst_gap, 3))

    def judgement(self) -> Judgement:
        if self.tree is None or not self.frame_ids or self.judged == 0 or self.placed == self.judged:
            return Judgement([], [])
        frame = self.first_failed_frame
        if self.placed == 0:
            return Judgement([self._unplaceable(frame)], [])
        share = '%d of %d looked-up stamps' % (self.judged - self.placed, self.judged)
        gap = ''
        if self.worst_gap is not None:
            gap = ': tf2 would have had to extrapolate up to %s s into the %s' % (
                fmt(abs(self.worst_gap), 3), 'future' if self.worst_gap > 0 else 'past')
        return Judgement([], ['%s could not be placed in %s at %s%s (%s); a part of the chain is '
                              'published late or less often than the sensor: consumers drop these '
                              'messages' % (frame, self.target, share, gap, self.first_error.strip())])

    def _unplaceable(self, frame: str) -> str:
        assert self.tree is not None
        record = self.tree.record
        frames = record.frames()
        if self.failed_kinds == ['extrapolation']:
            gap = fmt(abs(self.worst_gap), 3) if self.worst_gap is not None else '?'
            return ('%s could not be placed in %s at any of its %d looked-up stamps: /tf has the '
                    'chain but not at these times (tf2 would have had to extrapolate %s s into the '
                    '%s); likely cause: the robot\'s clock and this computer\'s disagree, or /tf lags '
                    'the sensor; fix: synchronise the clocks (chrony/NTP) and see the tf row'
                    % (frame, self.target, self.judged, gap,
                       'future' if (self.worst_gap or 0) > 0 else 'past'))
        if frame not in frames:
            where = '/tf has no frame %s at all' % frame
        else:
            top, _ = record.top_of(frame)
            where = '/tf has nothing above %s' % top
        if self.target not in frames:
            where += ' (nor any %s)' % self.target
        bare = len(frames) < BARE_TREE + 1
        cause = ('naoqi_driver could not load its robot description (share/urdf/pepper.urdf: without '
                 'it /tf carries only odom -> base_link)' if bare else
                 'a joint of the chain is missing from the joint states the tree is built from, or '
                 'a second state publisher with another robot description replaces part of the tree')
        fix = ('install naoqi_driver with its share/urdf (catkin install, or rosrun from the '
               'workspace) and restart it' if bare else
               'see the tf row for the tree\'s roots and second publishers; rosrun tf2_tools '
               'view_frames.py shows the tree')
        return '%s has no path to %s: %s; likely cause: %s; fix: %s' % (
            frame, self.target, where, cause, fix)
