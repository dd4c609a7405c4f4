"""A ROS 1 bag's messages read from one mapping of the file, in rosbag's order, each camera frame
a view into it.

rosbag (ros_comm 1.15-1.16, rosbag/bag.py `_BagReader200.seek_and_read_message_data_record`)
opens the bag and reads its index well (connections, chunk headers, the index entries, their
time order: `Bag._get_entries`); reading the messages it reads each chunk into new memory, wraps
it in a BytesIO, parses every record header into a dict and copies the data once more. Here
rosbag's index and order are kept and only the record under each index entry is read, from the
mapped file: a minute of four cameras (2.1 GB) cost sensorTest 0.5-0.7 s of CPU less
(docs/benchmark.md).

The record (the ROS bag format 2.0, wiki.ros.org/Bags/Format/2.0, "Message data" op=0x02 and
"Connection" op=0x07): uint32 header length, the header's fields (each uint32 length then
`name=value`: op, conn (uint32), time (uint32 secs, uint32 nsecs)), uint32 data length, the
data. An index entry's offset counts from the start of its chunk's data; connection records
before a message are skipped, as rosbag skips them.

What is handed over: camera frames (sensor_msgs/Image, the only large messages) as a memoryview
of the mapping or of the decompressed chunk, everything else as bytes, as rosbag gives it.
Compressed chunks (bz2, lz4) are decompressed by the same modules as rosbag's, the last one
kept. Memory and a cut file: mapped_file.py (every page before the chunk being read is
unmapped; the file's size is checked before each chunk). An encrypted bag, or a rosbag whose
reader is not this one, is read by rosbag as before (reader() returns None).
test/sources/test_bag_chunks.py compares the two on bags rosbag writes (none, bz2, lz4 chunks).
"""
import struct
from typing import Any, Dict, Iterator, List, Optional, Tuple

from .mapped_file import MappedFile

_U32 = struct.Struct('<I')
_TIME = struct.Struct('<II')
OP_MSG_DATA, OP_CONNECTION = 2, 7
LARGE = ('sensor_msgs/Image',)       # handed over as views: the rest is copied, as rosbag does


def reader(bag: Any) -> Optional['MappedBag']:
    """A MappedBag for an opened rosbag.Bag, or None where rosbag must read it itself."""
    try:
        from rosbag import bag as rosbag_bag
    except ImportError:
        return None
    if (type(getattr(bag, '_reader', None)).__name__ != '_BagReader200'
            or type(getattr(bag, '_encryptor', None)) is not getattr(rosbag_bag, '_ROSBagNoEncryptor', None)
            or not isinstance(getattr(bag, '_chunk_headers', None), dict)):
        return None
    return MappedBag(bag)


class MappedBag:
    """read() in rosbag's order: (time ns, connection info, data, message class)."""

    def __init__(self, bag: Any) -> None:
        self.bag = bag
        self.file = MappedFile(bag._file.fileno())
        self.chunk_pos: Optional[int] = None
        self.chunk: Any = None          # the current chunk's data: a view of the map or new bytes

    def read(self, topics: List[str], start_time: Any, end_time: Any) -> Iterator[Tuple[int, Any, Any, Any]]:
        from rosbag.bag import _get_message_type
        connections = self.bag._get_connections(topics, None)
        classes: Dict[int, Any] = {}
        for entry in self.bag._get_entries(connections, start_time, end_time):
            if entry.chunk_pos != self.chunk_pos:
                self._load(entry.chunk_pos)
            conn, ns, data = self._record(entry.offset)
            info = self.bag._connections[conn]
            cls = classes.get(conn)
            if cls is None:
                cls = classes[conn] = _get_message_type(info)
            yield ns, info, data if info.datatype in LARGE else bytes(data), cls

    def _load(self, chunk_pos: int) -> None:
        from rosbag.bag import ROSBagException
        header = self.bag._chunk_headers.get(chunk_pos)
        if header is None:
            raise ROSBagException('no chunk at position %d' % chunk_pos)
        start = header.data_pos
        self.chunk = None
        data = self.file.span(start, start + header.compressed_size)
        if data is None:
            raise ROSBagException('the bag ends inside the chunk at position %d' % chunk_pos)
        if header.compression != 'none':
            data = memoryview(_decompress(header.compression, data))
            if len(data) != header.uncompressed_size:
                raise ROSBagException('the chunk at position %d decompresses to %d bytes, not %d'
                                      % (chunk_pos, len(data), header.uncompressed_size))
        self.chunk, self.chunk_pos = data, chunk_pos

    def _record(self, pos: int) -> Tuple[int, int, memoryview]:
        """(connection id, time ns, data) of the message record at `pos` in the chunk, its header
        read by rosbag's own functions (the same fields, checks and errors as its reader)."""
        from rosbag.bag import (
            ROSBagFormatException,
            _build_header_from_str,
            _read_field,
            _read_uint8_field,
            _read_uint32_field,
        )
        chunk = self.chunk
        while True:
            if pos + 4 > len(chunk):
                raise ROSBagFormatException('record past the end of its chunk')
            (length,) = _U32.unpack_from(chunk, pos)
            header = _build_header_from_str(bytes(chunk[pos + 4:pos + 4 + length]), None)
            at = pos + 4 + length
            if at + 4 > len(chunk):
                raise ROSBagFormatException('record past the end of its chunk')
            (size,) = _U32.unpack_from(chunk, at)
            if at + 4 + size > len(chunk):
                raise ROSBagFormatException('record data past the end of its chunk')
            op = _read_uint8_field(header, 'op')
            if op == OP_CONNECTION:
                pos = at + 4 + size
                continue
            if op != OP_MSG_DATA:
                raise ROSBagFormatException('Expecting OP_MSG_DATA, got %d' % op)
            secs, nsecs = _read_field(header, 'time', _TIME.unpack)
            return (_read_uint32_field(header, 'conn'), secs * 1000000000 + nsecs,
                    chunk[at + 4:at + 4 + size])


def _decompress(compression: str, data: memoryview) -> bytes:
    from rosbag.bag import ROSBagException
    if compression == 'bz2':
        import bz2
        return bz2.decompress(data)
    if compression == 'lz4':
        try:
            import roslz4
        except ImportError:
            raise ROSBagException('unsupported compression type: lz4 (roslz4 is not installed)') from None
        return roslz4.decompress(bytes(data))
    raise ROSBagException('unsupported compression type: %s' % compression)
