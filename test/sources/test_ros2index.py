"""ros2index: the record times of a ROS 2 recording read from its index (sqlite3's timestamp
column, MCAP's message index records) are exactly those of its messages, in every storage form
the ROS 2 source reads; an MCAP file without an index gives None (the source then reads the
messages). Real recordings written by rosbags and mcap-ros2-support."""
import os

import pytest

from pepper_interface_tests.sources.ros2index import record_times
from rosbags_support import reads_ros2

# writes recordings with rosbag/rosbags (imports cost ~1 s)
pytestmark = [pytest.mark.integration, reads_ros2]

FORMS = ('sqlite3', 'mcap', 'mcap-zstd-file', 'sqlite3-zstd-message', 'sqlite3-split', 'mcap-split',
         'db3-file', 'mcap-ros2-support-file')


def write(form, path, recs):
    import ros2_recordings as rr
    if form == 'db3-file':
        folder = rr.write_rosbags(path, recs, 'sqlite3')
        return os.path.join(folder, os.path.basename(folder) + '.db3')
    if form == 'mcap-ros2-support-file':
        return rr.write_mcap_ros2(str(path) + '.mcap', recs)
    if form.endswith('-split'):
        return rr.write_split(path, recs, form.split('-')[0])
    storage = form.split('-')[0]
    compression = 'file' if form.endswith('-file') else 'message' if form.endswith('-message') else None
    return rr.write_rosbags(path, recs, storage, compression=compression)


def messages_times(path):
    from rosbags.rosbag2 import Reader
    with Reader(path) as reader:
        return sorted(t for _c, t, _raw in reader.messages())


@pytest.mark.parametrize('form', FORMS)
def test_the_index_gives_every_record_time(form, tmp_path):
    from rosbags.rosbag2 import Reader

    import ros2_recordings as rr
    path = write(form, tmp_path / 'rec', rr.records(seconds=1.0, first_ns=1700000000123456700))
    with Reader(path) as reader:
        indexed = record_times(reader)
    assert indexed is not None
    expected = messages_times(path)
    assert sorted(indexed) == expected and len(expected) > 50


def test_an_mcap_file_without_an_index_gives_none(tmp_path):
    """Messages written outside chunks (mcap's use_chunking=False): no chunk index to read."""
    from mcap.reader import make_reader
    from mcap.writer import Writer
    from rosbags.rosbag2 import Reader

    import ros2_recordings as rr
    src = rr.write_mcap_ros2(str(tmp_path / 'indexed.mcap'), rr.records(seconds=1.0))
    dst = str(tmp_path / 'plain.mcap')
    with open(src, 'rb') as f, open(dst, 'wb') as g:
        reader = make_reader(f)
        w = Writer(g, use_chunking=False)
        w.start(profile='ros2', library='test')
        summary = reader.get_summary()
        schemas = {k: w.register_schema(s.name, s.encoding, s.data) for k, s in summary.schemas.items()}
        channels = {k: w.register_channel(c.topic, c.message_encoding, schemas[c.schema_id], c.metadata)
                    for k, c in summary.channels.items()}
        for _schema, channel, message in reader.iter_messages():
            w.add_message(channels[channel.id], message.log_time, message.data, message.publish_time)
        w.finish()
    with Reader(dst) as reader:
        assert record_times(reader) is None
    assert messages_times(dst) == messages_times(src)
