"""An MCAP file's messages read chunk by chunk from one mapping of the file, every message a
view into it: no copy until the converter writes the ROS 1 bytes (ros2types.Converter).

rosbags (0.11, rosbag2/storage_mcap.py `msgsrc`) opens the file and parses its summary (schemas,
channels, the chunk index) well; reading the messages, it reads a chunk, wraps it in a BytesIO,
and copies every record twice more (`read_sized`, then `recio.read()`). Reading a minute of four
cameras (2.1 GB) and copying each message once cost 1.2 s of CPU with rosbags, 0.56-0.60 s with
one read of each chunk into new memory (a page fault every 4 KB), 0.46 s mapped (measured on
2026-11-29, docs/benchmark.md). The index, the decompression (zstd, lz4) and the chunk's
checksum stay rosbags' own (`decompress`); only the loop over a chunk's records is done here.

Memory and a file cut while it is read: mapped_file.py (every page before the chunk being read
is unmapped; the file's size is checked before each chunk, and a chunk past it is rosbags'
ReaderError("Truncated chunk"), as a truncated file is for rosbags). Peak RSS reading the
minute's 12,652 messages 30 MB (rosbags' reading 42 MB), sensorTest on it 93 MB (130 MB with
rosbags' reading).

Layouts (the MCAP specification, mcap.dev/spec, "Chunk (op=0x06)" and "Message (op=0x05)"; every
record is an opcode byte and a uint64 length, little-endian):
  Chunk    uint64 message_start_time, message_end_time, uncompressed_size, uint32
           uncompressed_crc, string compression (uint32 length + bytes), uint64 records length,
           records: at offset 9 + 40 + len(compression) from the chunk's opcode
  Message  uint16 channel_id, uint32 sequence, uint64 log_time, publish_time, data: the data
           starts 31 bytes after the opcode

Order, as rosbags': a chunk's messages sorted by log time (stable), chunks merged by (log time,
chunk offset); a chunk is read when the merge reaches its first log time, so at most the chunks
whose times overlap are held. Anything else (an unindexed file, which rosbags scans; another
storage; a rosbags whose reader is not this one) keeps rosbags' own reading: install() changes
nothing there. test/sources/test_mcap_chunks.py compares the two on MCAP files written by
rosbags and by the mcap library (compressed chunks, checksums, several files, time windows).
"""
import heapq
import struct
from typing import Any, Collection, Dict, Iterator, List, Optional, Tuple

from .mapped_file import MappedFile

_MESSAGE = struct.Struct('<BQHIQ')        # opcode, record length, channel_id, sequence, log_time
_LENGTH = struct.Struct('<Q')
_CRC = struct.Struct('<I')
MESSAGE_OP, DATA_AT = 0x05, 31

Msg = Tuple[int, int, Any, Any]      # log time, chunk offset, connection, data (a memoryview)


def install(reader: Any) -> int:
    """Makes every indexed MCAP file of an opened rosbags Reader read its messages here (its
    `messages`, which rosbags' Reader and DirectoryReader call); returns how many files."""
    try:
        from rosbags.rosbag2.storage_mcap import McapReader
    except ImportError:
        return 0
    storage = getattr(reader, 'storage', None)
    storages = getattr(storage, 'storages', None)
    n = 0
    for one in (storages if storages is not None else [storage]):
        if type(one) is McapReader and getattr(one, 'chunks', None) and getattr(one, 'bio', None):
            one.messages = _Chunked(one)  # type: ignore[method-assign,assignment]  # what rosbags calls
            n += 1
    return n


class _Chunked:
    """McapReader.messages(connections, start, stop) for one opened file."""

    def __init__(self, storage: Any) -> None:
        self.storage = storage
        self.file: Optional[MappedFile] = None      # the file, mapped at the first chunk read

    def __call__(self, connections: Collection[Any], start: Optional[int] = None,
                 stop: Optional[int] = None) -> Iterator[Tuple[Any, int, Any]]:
        channels = {c.id: c for c in connections}
        sources = [self._chunk(c, channels, c.message_start_time if start is None else start,
                               c.message_end_time + 1 if stop is None else stop)
                   for c in self.storage.chunks
                   if (start is None or start < c.message_end_time + 1)
                   and (stop is None or c.message_start_time < stop)
                   and any(c.channel_count.get(cid, 0) for cid in channels)]
        for log_time, offset, connection, data in heapq.merge(*sources, key=_order):
            if offset:
                yield connection, log_time, data

    def _chunk(self, chunk: Any, channels: Dict[int, Any], start: int, stop: int) -> Iterator[Msg]:
        """First a marker at the chunk's start time (offset 0, skipped), then its messages."""
        yield chunk.message_start_time, 0, None, None
        records = self._records(chunk)
        out: List[Msg] = []
        pos, end, at = 0, len(records), chunk.chunk_start_offset
        while pos < end:
            if pos + 9 > end:
                raise _error('Truncated record in the chunk at offset %d.' % at)
            if records[pos] == MESSAGE_OP:
                if pos + DATA_AT > end:
                    raise _error('Truncated message record in the chunk at offset %d.' % at)
                _op, size, channel, _seq, log_time = _MESSAGE.unpack_from(records, pos)
                if size < 22:
                    raise _error('Invalid message record length %d.' % size)
                if start <= log_time < stop and channel in channels:
                    out.append((log_time, at, channels[channel], records[pos + DATA_AT:pos + 9 + size]))
            else:
                (size,) = _LENGTH.unpack_from(records, pos + 1)
            pos += 9 + size
        if pos != end:
            raise _error('Truncated record in the chunk at offset %d.' % at)
        out.sort(key=_time)
        del records
        yield from out

    def _records(self, chunk: Any) -> memoryview:
        """The chunk's records, decompressed and checked against its checksum by rosbags."""
        from rosbags.rosbag2.storage_mcap import decompress
        if self.file is None:
            self.file = MappedFile(self.storage.bio.fileno())
        head, at = 9 + 40 + len(chunk.compression), chunk.chunk_start_offset
        view: Any = self.file.span(at, at + head + chunk.compressed_size)
        if view is None:
            raise _error('Truncated chunk at offset %d.' % at)
        (crc,) = _CRC.unpack_from(view, 9 + 24)
        (length,) = _LENGTH.unpack_from(view, head - 8)
        if length != chunk.compressed_size:
            raise _error('Chunk at offset %d: %d bytes of records where its index says %d.'
                         % (at, length, chunk.compressed_size))
        return memoryview(decompress(view[head:], chunk.compression, chunk.uncompressed_size, crc))


def _order(msg: Msg) -> Tuple[int, int]:
    return msg[0], msg[1]


def _time(msg: Msg) -> int:
    return msg[0]


def _error(text: str) -> Exception:
    from rosbags.rosbag2 import ReaderError
    return ReaderError(text)
