"""The record times of a ROS 2 recording from its index, without reading a message's data.

The ROS 2 source needs every record time once, at the start, for the dense window (bag.py).
Reading the messages for that reads the whole recording twice (2 GB for a minute of Pepper's
cameras); the storage formats keep the times apart from the data:
  * sqlite3: the `messages` table's `timestamp` column (the table rosbags' own reader queries,
    rosbags/rosbag2/storage_sqlite3.py Sqlite3Reader.messages);
  * MCAP: the Message Index records written after each chunk, one per channel, each a list of
    (log_time, offset) pairs (the MCAP specification, "Message Index (op=0x07)"), found through
    the Chunk Index records of the summary that rosbags' reader has already read.
Anything else (an MCAP file without a summary, as a killed recorder leaves it) returns None and
the caller reads the messages instead.
"""
import struct
from typing import Any, List, Optional

_OP_MESSAGE_INDEX = 0x07
_OP_LEN = struct.Struct('<BQ')         # opcode, record length
_CHANNEL = struct.Struct('<HI')        # channel id, byte length of the (log_time, offset) pairs


def record_times(reader: Any) -> Optional[List[int]]:
    """Every record time (ns) of a rosbags rosbag2 Reader, unsorted; None when the index cannot
    give them (or reading it fails)."""
    storage = getattr(reader, 'storage', None)     # a folder's DirectoryReader, or one file's reader
    storages = getattr(storage, 'storages', None) or ([storage] if storage is not None else [])
    if not storages:
        return None
    times: List[int] = []
    try:
        for storage in storages:
            part = _sqlite3_times(storage) if hasattr(storage, 'dbconn') else _mcap_times(storage)
            if part is None:
                return None
            times.extend(part)
    except Exception:  # noqa: BLE001  (a damaged index: the messages themselves are read instead)
        return None
    return times


def _sqlite3_times(storage: Any) -> Optional[List[int]]:
    if storage.dbconn is None:
        return None
    return [t for (t,) in storage.dbconn.execute('SELECT timestamp FROM messages')]


def _mcap_times(storage: Any) -> Optional[List[int]]:
    chunks = getattr(storage, 'chunks', None)
    bio = getattr(storage, 'bio', None)
    if not chunks or bio is None:
        return None
    times: List[int] = []
    for chunk in chunks:
        bio.seek(chunk.chunk_start_offset + chunk.chunk_length)
        data = bio.read(chunk.message_index_length)
        if len(data) != chunk.message_index_length:
            return None
        pos = 0
        while pos < len(data):
            op, length = _OP_LEN.unpack_from(data, pos)
            pos += _OP_LEN.size
            if op == _OP_MESSAGE_INDEX:
                _channel, size = _CHANNEL.unpack_from(data, pos)
                start = pos + _CHANNEL.size
                pairs = struct.unpack_from('<%dQ' % (size // 8), data, start)
                times.extend(pairs[0::2])
            pos += length
    n = sum(sum(chunk.channel_count.values()) for chunk in chunks)
    return times if len(times) == n else None
