"""The ROS 2 recording source: a rosbag2 folder (metadata.yaml with sqlite3 .db3 or .mcap files,
one or several, zstd-compressed per file or per message), or a single .mcap or .db3 file, read
with the pure-Python `rosbags` library: no ROS 2 installation is needed.

It is the ROS 1 bag source (bag.py) with another reader: the same record-time clock, the same
dense window, the same streaming. Each message is converted from CDR into ROS 1 wire bytes
(ros2types.Converter) and fed through the same Listener.feed_raw as a message out of a ROS 1 bag,
so the checks read the very same objects and the verdicts for the same data are the same.

Record time: rosbag2 stores the time the recorder received each message, in nanoseconds since
the epoch (or since the simulation's start on sim time), the same meaning as a ROS 1 bag's record
time; it is used as the receive time, exactly as for a ROS 1 bag. It stays an integer wherever
records are selected (the window's first and last record, the reader's start and stop), as in
bag.py: a float of seconds would hold it only to about 240 ns and could start after the first
record.

Streaming: rosbags reads a sqlite3 file with one ordered query (a cursor); an MCAP file is read
chunk by chunk (mcap_chunks.py: each chunk read once, its messages views into it); only the next
message is held here (the converter copies it into ROS 1 bytes). The record times are read once at the start for
the dense window, from the storage's index (ros2index.py: no message data is read), or, when it
has none, by one pass over the messages (the data dropped at once).
"""
import os
import re
import sys
from typing import Any, Dict, Iterator, List, Optional, Tuple

from ..plan.textfile import ConfigError
from .bag import NS, BagSource, Record

# The rosbags API read here is 0.10's (the Typestore's `fielddefs`, 0.9's `FIELDDEFS`), and 0.10
# is the first release for Python 3.10+ only; 0.9.23, the last for Python 3.8 (Ubuntu 20.04's),
# also reads no rosbag2 metadata version 9 (ROS 2 Jazzy's: "Rosbag2 version 9 not supported").
ROSBAGS_MIN = (0, 10)
FIX = ('check it is a ROS 2 recording (a folder with metadata.yaml and its .db3/.mcap files, or '
       'one .mcap or .db3 file) written completely (ros2 bag info; "ros2 bag reindex" rebuilds a '
       'missing metadata.yaml; "mcap recover IN.mcap -o OUT.mcap" an MCAP file whose recorder '
       'was killed)')


def rosbags_version() -> Tuple[int, ...]:
    """The installed rosbags' (major, minor, patch) from its distribution's metadata; () when
    it is not installed."""
    from importlib.metadata import PackageNotFoundError, version
    try:
        return tuple(int(p) for p in re.findall(r'\d+', version('rosbags'))[:3])
    except PackageNotFoundError:
        return ()


def check_rosbags(path: str, have: Optional[Tuple[int, ...]] = None) -> None:
    """ConfigError (exit 2: the run cannot start) in one sentence, with the fix, when the
    installed rosbags (`have`) is older than ROSBAGS_MIN."""
    have = rosbags_version() if have is None else have
    if have >= ROSBAGS_MIN:
        return
    raise ConfigError('reading a ROS 2 recording needs rosbags %s or later, which needs Python '
                      '3.10 or later (here: rosbags %s on Python %d.%d)'
                      % ('.'.join(map(str, ROSBAGS_MIN)), '.'.join(map(str, have)) or 'none',
                         sys.version_info[0], sys.version_info[1]), path,
                      fix='run sensorTest --bag on Python 3.10 or later with pip install '
                          'rosbags==0.11.9, or there convert the recording into a ROS 1 bag, '
                          'which this Python reads: rosbags-convert --src %s --dst recording.bag'
                          % path)


def _msg_dir() -> str:
    from ..plan.settings import package_dir
    return os.path.join(package_dir(), 'msg')


class Ros2BagSource(BagSource):
    """sensorTest --bag on a ROS 2 recording."""

    def _open(self, path: str) -> None:
        try:
            from rosbags.rosbag2 import Reader
        except ImportError:
            raise ConfigError('reading a ROS 2 recording needs the rosbags library, which is not '
                              'installed', path, fix='pip install rosbags==0.11.9 (Python 3.10 or '
                              'later; tools/setup.sh installs it)') from None
        check_rosbags(path)
        from . import ros2types
        if os.path.isdir(path) and not os.path.exists(os.path.join(path, 'metadata.yaml')):
            raise ConfigError('no metadata.yaml in this folder: not a rosbag2 recording', path,
                              fix='give --bag the recording folder that holds metadata.yaml, or one '
                                  'of its .mcap/.db3 files; "ros2 bag reindex %s" rebuilds it' % path)
        try:
            self.reader = Reader(path)
            self.reader.open()
        except Exception as e:  # noqa: BLE001  (ReaderError, sqlite3/MCAP errors, bad YAML)
            raise ConfigError('cannot open the ROS 2 recording: %s' % _why(e), path, fix=FIX) from None
        from .mcap_chunks import install
        install(self.reader)      # an MCAP file's chunks read once each, messages as views
        conns = list(self.reader.connections)
        try:
            distro = self.reader.ros_distro
        except Exception:  # noqa: BLE001  (older metadata without it)
            distro = None
        self.converter = ros2types.Converter(conns, _msg_dir(), distro)
        self.types = {c.topic: ros2types.ros1_name(c.msgtype) for c in conns}
        self._by_topic: Dict[str, List[Any]] = {}
        for c in conns:
            self._by_topic.setdefault(c.topic, []).append(c)
        self.problems = dict(self.converter.problems)
        for topic, why in sorted(self.problems.items()):
            self.notes.append('topic %s cannot be read: %s; fix: record with MCAP (it embeds every '
                              'definition) or add its .msg file to msg/' % (topic, why))
        self.read_error: Optional[str] = None

    def _record_times(self) -> Iterator[int]:
        from .ros2index import record_times
        indexed = record_times(self.reader)
        if indexed:
            yield from indexed
            return
        n = 0
        try:
            for _conn, ns, _raw in self.reader.messages():
                n += 1
                yield ns
        except Exception as e:  # noqa: BLE001  (a truncated file: keep what could be read)
            if n == 0:
                self.close()
                raise ConfigError('cannot read the ROS 2 recording: %s' % _why(e), self.path,
                                  fix=FIX) from None
            self.read_error = _why(e)
            self.notes.append('the recording ends early: reading stopped after %d messages (%s); '
                              'the checks judge what was read' % (n, self.read_error))
            return
        if n == 0:
            self.close()
            raise ConfigError('the ROS 2 recording holds no message', self.path,
                              fix='record again; check the topics with "ros2 bag info %s"' % self.path)

    def _records(self, after: Optional[float] = None) -> Iterator[Record]:
        conns = [c for topic in sorted(self.runs) for c in self._by_topic.get(topic, ())]
        if not conns:
            return
        start, end = self._start_ns(after), self.end_ns     # integer nanoseconds (bag.py)
        try:
            for conn, ns, raw in self.reader.messages(connections=conns, start=start, stop=end + 1):
                t = ns / NS
                if ns < start or ns > end or (after is not None and t <= after):
                    continue
                if conn.topic in self.problems:   # delivered undecodable: the sensor says so
                    yield t, conn.topic, self.types[conn.topic], b'', {'type': self.types[conn.topic]}
                    continue
                header = self.converter.header(conn.msgtype)
                yield t, conn.topic, header['type'], self.converter.for_checks(raw, conn.msgtype), header
        except Exception:  # noqa: BLE001  (a truncated file: the note made at the start says so)
            return

    def peek(self, topic: str, n: int = 1) -> List[Any]:
        """The first `n` messages of `topic`, decoded as the checks decode them ([] when the topic
        is missing or cannot be read)."""
        from . import messages
        out: List[Any] = []
        conns = self._by_topic.get(topic)
        if not conns or topic in self.problems:
            return out
        records = self.reader.messages(connections=conns)
        try:
            for conn, _ns, raw in records:
                header = self.converter.header(conn.msgtype)
                msg = messages.message_class(header['type'], header['message_definition'])()
                msg.deserialize(self.converter.to_ros1(raw, conn.msgtype))
                out.append(msg)
                if len(out) >= n:
                    break
        except Exception:  # noqa: BLE001  (an undecodable message: the check will say so)
            pass
        finally:
            records.close()
        return out

    def close(self) -> None:
        try:
            self.reader.close()
        except Exception:  # noqa: BLE001  (closing a reader that failed half-way)
            pass


def _why(e: Exception) -> str:
    text = str(e).strip().splitlines()[0] if str(e).strip() else ''
    return '%s%s' % (type(e).__name__, ': ' + text[:200] if text else '')


def open_recording(path: str) -> BagSource:
    """The source for `path`: a ROS 2 recording (a folder, its metadata.yaml, a .mcap or .db3
    file) or else a ROS 1 bag."""
    if os.path.basename(path) == 'metadata.yaml' and os.path.isfile(path):
        path = os.path.dirname(path) or '.'
    if os.path.isdir(path) or path.endswith(('.mcap', '.db3')):
        if not os.path.exists(path):
            raise ConfigError('recording not found', path, fix='give --bag an existing recording')
        return Ros2BagSource(path)
    magic = b''
    try:
        with open(path, 'rb') as f:
            magic = f.read(16)
    except OSError:
        pass      # missing or unreadable: the ROS 1 source names the problem
    if magic.startswith(b'\x89MCAP') or magic.startswith(b'SQLite format 3'):
        raise ConfigError('this is a ROS 2 %s file without its usual name' % (
            'MCAP' if magic.startswith(b'\x89MCAP') else 'sqlite3'), path,
            fix='rename it to end in .%s' % ('mcap' if magic.startswith(b'\x89MCAP') else 'db3'))
    return BagSource(path)

