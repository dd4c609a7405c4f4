"""bag_chunks: a ROS 1 bag's messages read from one mapping of the file must be exactly what
rosbag reads (the same records in the same order, the same connections and classes, with time
windows and topic subsets), for bags rosbag writes with uncompressed, bz2 and lz4 chunks; camera
frames come as views, the rest as bytes; a broken record is rosbag's format error and a bag cut
while it is read is rosbag's error, never a crash.

Real bags written by rosbag; the comparison is against rosbag's own read_messages on the same
file."""
import subprocess
import sys

import genpy
import pytest
import rosbag

import fake_pepper as fake
from pepper_interface_tests.sources import bag_chunks

NS = 1000000000
T0 = 1700000000.0


def write_bag(path, compression='none', chunk_threshold=20000, seconds=2.0):
    """Camera frames (with a recorded node), joint states, laser, audio: several connection
    records and many chunks."""
    with rosbag.Bag(str(path), 'w', compression=compression, chunk_threshold=chunk_threshold) as bag:
        for i in range(int(seconds * 10)):
            t = T0 + 0.1 * i
            frame = fake.camera_image(i, w=64, h=48, t=t)
            node = '/naoqi_driver'
            bag.write('/naoqi_driver/camera/front/image_raw', frame, genpy.Time.from_sec(t + 0.002),
                      connection_header={'callerid': node, 'type': frame._type, 'md5sum': frame._md5sum,
                                         'message_definition': frame._full_text, 'topic': 'x'})
            for k in range(5):
                j = fake.joints(i * 5 + k, t=t + 0.02 * k)
                bag.write('/joint_states', j, genpy.Time.from_sec(t + 0.02 * k + 0.001))
            bag.write('/naoqi_driver/laser', fake.laser(i, t=t), genpy.Time.from_sec(t + 0.003))
            bag.write('/naoqi_driver/audio', fake.audio_buffer(i), genpy.Time.from_sec(t + 0.004))
    return str(path)


def theirs(path, topics, start=None, end=None):
    with rosbag.Bag(path) as bag:
        return [(topic, raw[0], stamp.to_nsec(), raw[1], raw[2], raw[4], header.get('callerid'))
                for topic, raw, stamp, header in bag.read_messages(
                    topics=topics, raw=True, start_time=start, end_time=end, return_connection_header=True)]


def ours(path, topics, start=None, end=None):
    with rosbag.Bag(path) as bag:
        mapped = bag_chunks.reader(bag)
        assert mapped is not None
        out = []
        for ns, info, data, cls in mapped.read(topics, start, end):
            assert isinstance(data, memoryview if info.datatype == 'sensor_msgs/Image' else bytes)
            out.append((info.topic, info.datatype, ns, bytes(data), info.md5sum, cls,
                        info.header.get('callerid')))
        return out


TOPICS = ['/naoqi_driver/camera/front/image_raw', '/joint_states', '/naoqi_driver/laser',
          '/naoqi_driver/audio']


@pytest.mark.parametrize('compression', ['none', 'bz2', 'lz4'])
def test_same_records_as_rosbag_reads(compression, tmp_path):
    path = write_bag(tmp_path / 'pepper.bag', compression)
    with rosbag.Bag(path) as bag:
        assert len(bag._chunk_headers) > 5
    mine, rosbags_own = ours(path, TOPICS), theirs(path, TOPICS)
    assert len(mine) == len(rosbags_own) == 20 * 8
    assert mine == rosbags_own
    # a window and a subset of the topics, as BagSource asks
    start, end = genpy.Time.from_sec(T0 + 0.5), genpy.Time.from_sec(T0 + 1.2)
    subset = ['/naoqi_driver/camera/front/image_raw', '/joint_states']
    mine = ours(path, subset, start, end)
    assert mine == theirs(path, subset, start, end) and 0 < len(mine) < 60


def test_a_broken_record_is_rosbags_format_error(tmp_path):
    """The op field of a message record, changed: rosbag and this both refuse the record."""
    path = write_bag(tmp_path / 'pepper.bag')
    with rosbag.Bag(path) as bag:
        laser = next(c.id for c in bag._connections.values() if c.topic == '/naoqi_driver/laser')
        entry = bag._connection_indexes[laser][3]
        at = bag._chunk_headers[entry.chunk_pos].data_pos + entry.offset
    with open(path, 'rb') as f:
        f.seek(at)
        head = f.read(200)
    op = head.index(b'op=') + 3
    with open(path, 'r+b') as f:
        f.seek(at + op)
        f.write(b'\x05')
    for read in (ours, theirs):
        with pytest.raises(rosbag.ROSBagFormatException):
            read(path, ['/naoqi_driver/laser'])


CUT_WHILE_READING = r'''
import os, sys
import rosbag
from pepper_interface_tests.sources import bag_chunks
path = sys.argv[1]
n = 0
with rosbag.Bag(path) as bag:
    try:
        for ns, info, data, cls in bag_chunks.reader(bag).read(None, None, None):
            n += 1
            if n == 5:
                os.truncate(path, os.path.getsize(path) // 2)
            bytes(data)
    except rosbag.ROSBagException as e:
        print('ROSBagException after %d: %s' % (n, e))
        sys.exit(3)
print('read', n)
'''


def test_a_bag_cut_short_while_it_is_read_is_rosbags_error_not_a_crash(tmp_path):
    """The file is mapped: touching a page past a shortened end would be SIGBUS. Run as a
    process of its own so that such a crash shows as its exit code."""
    path = write_bag(tmp_path / 'pepper.bag')
    p = subprocess.run([sys.executable, '-c', CUT_WHILE_READING, path], capture_output=True,
                       text=True, timeout=60)
    assert p.returncode == 3, (p.returncode, p.stdout, p.stderr)
    assert 'ends inside the chunk' in p.stdout


def test_a_frame_held_keeps_its_bytes_after_its_pages_are_unmapped(tmp_path):
    path = write_bag(tmp_path / 'pepper.bag', chunk_threshold=5000, seconds=4.0)
    topic = ['/naoqi_driver/camera/front/image_raw']
    with rosbag.Bag(path) as bag:
        held = [data for _ns, _info, data, _cls in bag_chunks.reader(bag).read(topic, None, None)]
        assert len(bag._chunk_headers) > 20
        assert [bytes(v) for v in held] == [m[3] for m in theirs(path, topic)]
