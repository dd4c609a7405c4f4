"""mcap_chunks: the messages of an MCAP file read chunk by chunk (one mapping of the file, each
message a view into it) must be exactly rosbags' own reading of the same file, in the same order
and with the same filters, for the files rosbags and the mcap library write (uncompressed, zstd
and lz4 chunks with checksums, per-message zstd, two files in one folder); a damaged chunk and a
file cut short while it is read are rosbags' ReaderError, never a crash; a view held while the
rest is read keeps its bytes.

Real files written by the real writers; the comparison is against rosbags' reader on the same
file, opened a second time without install()."""
import os
import subprocess
import sys

import numpy as np
import pytest

import fake_pepper as fake
import ros2_recordings as rr
from rosbags_support import OLD_ROSBAGS, reads_ros2

pytestmark = pytest.mark.skipif(OLD_ROSBAGS, reason=reads_ros2.kwargs['reason'])


def _messages():
    """(topic, ROS 2 type, log time ns, CDR bytes): the synthetic recording, and 30 frames of
    noise (so that chunks hold a few frames each and compression keeps them large)."""
    ts = rr._typestore()
    out = []
    for r in rr.records():
        name = rr._ros2_type(r.msg)
        out.append((rr.TOPICS[r.sensor][1], name, rr.record_ns(r),
                    bytes(ts.ros1_to_cdr(fake.serialized(r.msg), name))))
    rng = np.random.default_rng(7)
    for i in range(30):
        m = fake.image(rng.integers(0, 255, (120, 160, 3), dtype=np.uint8), 'rgb8', frame_id='cam')
        t = rr.T0 + 0.1 * i + 0.05
        m.header.stamp = rr.genpy.Time.from_sec(t)
        out.append(('/camera/bottom/image_raw', 'sensor_msgs/msg/Image', int(t * 1e9),
                    bytes(ts.ros1_to_cdr(fake.serialized(m), 'sensor_msgs/msg/Image'))))
    return sorted(out, key=lambda m: m[2])


def write_mcap(path, compression, chunk_size=40000, chunked=True):
    """One .mcap file by the mcap library (chunk checksums on, as ros2 bag record writes them).
    The messages are written topic by topic within each 0.3 s, not in time order: a chunk's
    messages are then out of order, as a recorder's threads can leave them (an unindexed file
    in time order: rosbags refuses one that is not)."""
    from mcap.writer import CompressionType, Writer
    ts = rr._typestore()
    with open(str(path), 'wb') as f:
        w = Writer(f, chunk_size=chunk_size, compression=getattr(CompressionType, compression),
                   use_chunking=chunked, enable_crcs=True)
        w.start(profile='ros2', library='test')
        schemas, channels = {}, {}
        block = 300000000 if chunked else 1
        for topic, name, ns, raw in sorted(_messages(), key=lambda m: (m[2] // block, m[0])):
            if name not in schemas:
                text = ts.generate_msgdef(name, ros_version=2)[0]
                schemas[name] = w.register_schema(name, 'ros2msg', text.encode())
            if topic not in channels:
                channels[topic] = w.register_channel(topic, 'cdr', schemas[name])
            w.add_message(channels[topic], log_time=ns, data=raw, publish_time=ns)
        w.finish()
    return str(path)


def _recs_by_rosbags(path, storage_compression=None, split=False):
    recs = list(rr.records())
    if split:
        return rr.write_split(path, recs, 'mcap')
    return rr.write_rosbags(path, recs, 'mcap', compression=storage_compression)


FILES = {
    'mcap-none': lambda p: write_mcap(str(p) + '.mcap', 'NONE'),
    'mcap-zstd': lambda p: write_mcap(str(p) + '.mcap', 'ZSTD'),
    'mcap-lz4': lambda p: write_mcap(str(p) + '.mcap', 'LZ4'),
    'rosbags': lambda p: _recs_by_rosbags(p),
    'rosbags-zstd-message': lambda p: _recs_by_rosbags(p, 'message'),
    'rosbags-zstd-file': lambda p: _recs_by_rosbags(p, 'file'),
    'rosbags-split': lambda p: _recs_by_rosbags(p, split=True),
}


def read(path, installed, topics=None, start=None, stop=None):
    from rosbags.rosbag2 import Reader

    from pepper_interface_tests.sources.mcap_chunks import install
    with Reader(path) as reader:
        n = install(reader) if installed else 0
        conns = [c for c in reader.connections if topics is None or c.topic in topics]
        return n, [(c.topic, c.msgtype, t, bytes(raw))
                   for c, t, raw in reader.messages(connections=conns, start=start, stop=stop)]


@pytest.mark.parametrize('form', sorted(FILES))
def test_same_messages_as_rosbags_reads(form, tmp_path):
    path = FILES[form](tmp_path / 'rec')
    n, ours = read(path, True)
    _, theirs = read(path, False)
    assert n >= 1                           # the chunks were read here, not by rosbags
    assert len(ours) == len(theirs) > 100
    assert ours == theirs
    times = [m[2] for m in ours]
    # a window and a subset of the topics, as sensorTest's source asks
    start, stop = times[len(times) // 4], times[3 * len(times) // 4]
    topics = {'/camera/front/image_raw', '/joint_states', '/camera/bottom/image_raw'}
    _, ours = read(path, True, topics, start, stop)
    _, theirs = read(path, False, topics, start, stop)
    assert ours == theirs and 0 < len(ours) < len(times) // 2 + 50


def test_an_unindexed_file_is_left_to_rosbags(tmp_path):
    path = write_mcap(tmp_path / 'flat.mcap', 'NONE', chunked=False)
    n, ours = read(path, True)
    assert n == 0                            # rosbags scans a file without chunks itself
    assert ours == read(path, False)[1]


def _chunk_payload_offset(path):
    from rosbags.rosbag2 import Reader
    with Reader(path) as reader:
        chunk = reader.storage.chunks[len(reader.storage.chunks) // 2]
        return chunk.chunk_start_offset + 9 + 40 + len(chunk.compression) + 100


def test_a_damaged_chunk_is_rosbags_checksum_error(tmp_path):
    from rosbags.rosbag2 import ReaderError
    path = write_mcap(tmp_path / 'rec.mcap', 'NONE')
    at = _chunk_payload_offset(path)
    with open(path, 'r+b') as f:
        f.seek(at)
        byte = f.read(1)
        f.seek(at)
        f.write(bytes([byte[0] ^ 0xFF]))
    for installed in (True, False):
        with pytest.raises(ReaderError, match='checksum'):
            read(path, installed)


CUT_WHILE_READING = r'''
import os, sys
from rosbags.rosbag2 import Reader, ReaderError
from pepper_interface_tests.sources.mcap_chunks import install
path = sys.argv[1]
with Reader(path) as reader:
    assert install(reader) == 1
    n = 0
    try:
        for conn, t, raw in reader.messages():
            n += 1
            if n == 5:
                os.truncate(path, os.path.getsize(path) // 2)
            bytes(raw)
    except ReaderError as e:
        print('ReaderError after %d: %s' % (n, e))
        sys.exit(3)
print('read', n)
'''


def test_a_file_cut_short_while_it_is_read_is_a_reader_error_not_a_crash(tmp_path):
    """The file is mapped: touching a page past a shortened end would be SIGBUS. Run as a
    process of its own so that such a crash shows as its exit code."""
    path = write_mcap(tmp_path / 'rec.mcap', 'NONE')
    p = subprocess.run([sys.executable, '-c', CUT_WHILE_READING, path], capture_output=True,
                       text=True, timeout=60)
    assert p.returncode == 3, (p.returncode, p.stdout, p.stderr)
    assert 'Truncated chunk' in p.stdout


def test_a_view_held_keeps_its_bytes_after_its_pages_are_released(tmp_path):
    """A chunk's pages are unmapped once it is read; a view kept (a frame waiting for the
    motion check) reads them again from the file."""
    from rosbags.rosbag2 import Reader

    from pepper_interface_tests.sources.mcap_chunks import install
    path = write_mcap(tmp_path / 'rec.mcap', 'NONE', chunk_size=20000)
    _, theirs = read(path, False)
    with Reader(path) as reader:
        install(reader)
        held = [raw for _c, _t, raw in reader.messages()]
        assert len(reader.storage.chunks) > 10
        assert [bytes(v) for v in held] == [m[3] for m in theirs]
    assert os.path.getsize(path) > 0
