"""The bag data source: replays a recorded bag through the same sensor windows, with no master.

Time is the bag's record time: the runner's clock is a virtual clock that this source advances
by one tick per loop, feeding every message recorded up to that moment. Rates and delays are
therefore measured from the recorded times, exactly as they were on the robot.

Streaming: messages are read with rosbag's `read_messages` generator (in record-time order,
one chunk at a time) while the virtual clock advances, and only for the topics a running window
listens to; nothing but the next message is held. Memory is bounded by the windows' working set
(the checks' state, one bag chunk), not by the size of the bag.

The window: a bag is checked over its *dense* part, its longest run of records with no silence
longer than MAX_SILENCE between two of them (any topic). A record at a bogus time (t = 1 s in a
bag recorded at 1.7e9 s, a clock that jumped) would otherwise stretch the window to decades;
such records are left out and `notes` says which and when.

Record times stay integer nanoseconds wherever a record is selected (the dense window's first
and last record, the start and end handed to the reader): a float of seconds near 1.7e9 holds the
nanoseconds only to about 240 ns, so a start computed from it can land after the first record and
leave it out. Only the time handed to the windows (their rates and delays) is a float.
"""
import os
from typing import TYPE_CHECKING, Any, Dict, Iterator, List, Mapping, Optional, Sequence, Tuple

from ..plan.textfile import ConfigError
from . import Graph, Listener, TopicInfo, bag_chunks

if TYPE_CHECKING:
    from ..plan.settings import TestPlan

# a record as the runner is fed it: (record time, topic, type name, bytes, connection header)
Record = Tuple[float, str, str, bytes, Dict[str, Any]]
NS = 1000000000     # nanoseconds a second

# No sensor of Pepper publishes less than once a second (reference/pepper-sensors.md) and a
# sensor test records seconds to minutes: when no topic at all has a record for 5 minutes, the
# records on the other side of that silence are not part of the same recording.
MAX_SILENCE = 300.0


def dense_span(times: Sequence[Any], max_silence: float = MAX_SILENCE) -> Tuple[Any, Any, int, int]:
    """(begin, end, left out before, left out after) of the largest group of `times` (sorted;
    seconds, or integer nanoseconds with `max_silence` in nanoseconds: begin and end are then
    those integers) with no gap above `max_silence`; the first such group when two have the
    same size."""
    if not times:
        return 0.0, 0.0, 0, 0
    best, start = (0, 0), 0
    for i in range(1, len(times) + 1):
        if i == len(times) or times[i] - times[i - 1] > max_silence:
            if i - start > best[1] - best[0]:
                best = (start, i)
            start = i
    first, stop = best
    return times[first], times[stop - 1], first, len(times) - stop


def _when(t):
    import time
    if t > 1e8:
        return '%s UTC (t = %.6g s)' % (time.strftime('%Y-%m-%d %H:%M:%S', time.gmtime(t)), t)
    return 't = %.6g s' % t


class BagSource:
    live = False

    def __init__(self, path: str) -> None:
        self.path = path
        self.types: Dict[str, str] = {}      # topic -> ROS 1 type name ('sensor_msgs/LaserScan')
        self.notes: List[str] = []
        self._open(path)
        times = sorted(self._record_times())     # integer nanoseconds
        begin, end, before, after = dense_span(times, MAX_SILENCE * NS)
        self.begin_ns, self.end_ns = int(begin), int(end)
        self.begin, self.end = self.begin_ns / NS, self.end_ns / NS
        if before or after:
            odd = [t / NS for t in times if t < self.begin_ns or t > self.end_ns]
            self.notes.append(
                '%d record%s at odd times left out (%s%s); no record for more than %g s '
                'separates them from the %d records checked, from %s to %s (%.1f s)'
                % (len(odd), '' if len(odd) == 1 else 's', ', '.join(_when(t) for t in odd[:3]),
                   ', ...' if len(odd) > 3 else '', MAX_SILENCE, len(times) - len(odd),
                   _when(self.begin), _when(self.end), self.end - self.begin))
        self.now = self.begin
        self.runs: Dict[str, List[Listener]] = {}     # topic -> the windows listening to it
        self._reader: Optional[Iterator[Record]] = None   # the records, opened at the first tick
        self._pending: Optional[Record] = None            # the next record, read but not yet due
        # (type, md5sum, callerid) -> connection header fields
        self._conns: Dict[Tuple[str, str, Optional[str]], Dict[str, Any]] = {}

    def _open(self, path: str) -> None:
        """Open the ROS 1 bag at `path` and fill self.types."""
        import rosbag
        if not os.path.exists(path):
            raise ConfigError('bag file not found', path, fix='give --bag an existing .bag file')
        try:
            self.bag = rosbag.Bag(path)
        except Exception as e:  # ROSBagException, unindexed or foreign files
            raise ConfigError('cannot open the bag: %s' % e, path,
                              fix='check it is a ROS 1 bag (rosbag info %s); reindex with '
                                  '"rosbag reindex" if it was not closed' % path) from None
        info = self.bag.get_type_and_topic_info()
        self.types = {t: v.msg_type for t, v in info.topics.items()}

    def _record_times(self) -> Iterator[int]:
        """Record times of every message in integer nanoseconds, from the bag's index (already
        in memory: no data is read)."""
        for entries in self.bag._connection_indexes.values():
            for entry in entries:
                yield entry.time.secs * NS + entry.time.nsecs

    def _start_ns(self, after: Optional[float]) -> int:
        """The first record time to read: the window's first record, or for a reader opened
        again at `after` (the clock, a float) a little before it (the exact choice of what is
        later than `after` is made with the very comparison `sleep` delivers by)."""
        if after is None:
            return self.begin_ns
        return max(self.begin_ns, int(after * NS) - 1000)

    def _records(self, after: Optional[float] = None) -> Iterator[Record]:
        """(t, topic, type name, serialized bytes) in record-time order, within the dense span,
        for the topics of the windows attached so far (only records later than `after`)."""
        import genpy
        topics = sorted(self.runs)
        if not topics:
            return
        start, stop = self._start_ns(after), self.end_ns
        start_time, end_time = genpy.Time(start // NS, start % NS), genpy.Time(stop // NS, stop % NS)
        for ns, topic, type_name, data, conn in self._read(topics, start_time, end_time):
            t = ns / NS
            if start <= ns <= stop and (after is None or t > after):
                yield t, topic, type_name, data, conn

    def _read(self, topics: List[str], start_time: Any,
              end_time: Any) -> Iterator[Tuple[int, str, str, Any, Dict[str, Any]]]:
        """(record time ns, topic, type, data, connection) in rosbag's order: read in place
        (bag_chunks.py) where it can, else by rosbag."""
        mapped = bag_chunks.reader(self.bag)
        if mapped is not None:
            for ns, info, data, cls in mapped.read(topics, start_time, end_time):
                yield ns, info.topic, info.datatype, data, self._connection(
                    info.datatype, info.md5sum, cls, info.header)
            return
        for topic, raw, stamp, header in self.bag.read_messages(
                topics=topics, raw=True, start_time=start_time, end_time=end_time,
                return_connection_header=True):
            yield (stamp.secs * NS + stamp.nsecs, topic, raw[0], raw[1],
                   self._connection(raw[0], raw[2], raw[4], header))

    def _connection(self, type_name: str, md5sum: str, cls: Any, header: Optional[Dict[str, Any]] = None):
        """What a live connection header would say of a raw record (type, md5sum, definition,
        and the recorded node, callerid: the bag's connection record, which rosbag record copies
        from the publisher's header): `cls` is the class rosbag generated from the connection's
        definition, so a type whose package is not installed is still decoded. One dict per
        connection (the header dict rosbag returns is the connection's)."""
        caller = (header or {}).get('callerid')
        if isinstance(caller, bytes):
            caller = caller.decode('utf-8', 'replace')
        key = (type_name, md5sum, caller)
        conn = self._conns.get(key)
        if conn is None:
            conn = self._conns[key] = {'type': type_name, 'md5sum': md5sum,
                                       'message_definition': getattr(cls, '_full_text', None)}
            if caller:
                conn['callerid'] = caller
        return conn

    @property
    def length(self) -> float:
        return self.end - self.begin

    def clock(self) -> float:
        return self.now

    def attach(self, run: Listener) -> None:
        run.use_record_clock()    # rates on the bag's record times (stats.py)
        if self._reader is not None and run.topic not in self.runs:
            # a topic nobody listened to so far: read again from now, with it included
            self._reader = self._records(after=self.now)
            self._pending = None
        self.runs.setdefault(run.topic, []).append(run)

    def detach(self, run: Listener) -> None:
        runs = self.runs.get(run.topic, [])
        if run in runs:
            runs.remove(run)

    def poll(self, run: Listener, now: float) -> None:
        pass

    def published_topics(self) -> None:
        return None     # a bag has no publishers to ask about; the check on each topic says enough

    graph_words: Optional[Graph] = None

    def lookup(self, topic: str) -> TopicInfo:
        t = self.types.get(topic)
        return (t, ['the bag']) if t else (None, None)

    def sleep(self, dt: float) -> None:
        self.now += dt
        if self._reader is None:
            self._reader = self._records()
        while True:
            if self._pending is None:
                self._pending = next(self._reader, None)
                if self._pending is None:
                    return
            t, topic, type_name, data, conn = self._pending
            if t > self.now:
                return
            self._pending = None
            for run in self.runs.get(topic, ()):
                run.feed_raw(type_name, data, t, t, conn)

    def close(self) -> None:
        self.bag.close()


def platform_hint(plan: 'TestPlan', listened: Sequence[str], bag_types: Mapping[str, str],
                  other_plan: 'TestPlan') -> Optional[str]:
    """A bag checked with the wrong platform fails nearly every sensor as "not in the bag". When
    `listened` (the topics of `plan` the checks listen to) are missing from the bag and
    `other_plan` (the same files, the other platform) finds more of its topics there, the note
    that says so and names the option (a topic both share, /joint_states, does not decide);
    else None."""
    mine = set(listened)
    found = {t for t in mine if t in bag_types}
    theirs = sorted({s.topic for s in other_plan.sensors if s.topic is not None and s.topic in bag_types})
    if not mine or found == mine or len(theirs) <= len(found):
        return None
    return ('%d of the %d %s topics are in the bag, but %d of the %s topics are (%s%s): check it '
            'with --platform %s' % (len(found), len(mine), plan.platform, len(theirs),
                                    other_plan.platform, ', '.join(theirs[:3]),
                                    ', ...' if len(theirs) > 3 else '', other_plan.platform))
