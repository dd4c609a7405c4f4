"""ros2types: the ROS 2 type definitions a recording can be read with, and the conversion of a
CDR message into the ROS 1 bytes the checks decode. Pure: no master, no recording."""
from types import SimpleNamespace

from rosbags.typesys import Stores, get_typestore

from pepper_interface_tests.sources import ros2types
from rosbags_support import reads_ros2

pytestmark = reads_ros2

HUMBLE = get_typestore(Stores.ROS2_HUMBLE)    # its module chain imported once, at collection
NONE = SimpleNamespace(format=SimpleNamespace(name='NONE'), data='')


def conn(topic, msgtype, msgdef=NONE):
    return SimpleNamespace(topic=topic, msgtype=msgtype, msgdef=msgdef)


def test_ros1_names():
    assert ros2types.ros1_name('sensor_msgs/msg/LaserScan') == 'sensor_msgs/LaserScan'
    assert ros2types.ros1_name('naoqi_bridge_msgs/msg/AudioBuffer') == 'naoqi_bridge_msgs/AudioBuffer'
    assert ros2types.ros1_name('sensor_msgs/LaserScan') == 'sensor_msgs/LaserScan'


def test_every_msg_file_is_registered_under_the_drivers_packages(tmp_path):
    (tmp_path / 'Bumper.msg').write_text('Header header\nuint8 bumper\nuint8 state\n')
    (tmp_path / 'Broken.msg').write_text('uint8[ x\n')
    (tmp_path / 'notes.txt').write_text('not a message\n')
    types = ros2types.package_msg_types(str(tmp_path))
    for pkg in ros2types.MSG_PACKAGES:
        assert '%s/msg/Bumper' % pkg in types
    assert 'naoqi_bridge_msgs/msg/AudioBuffer' in types          # naoqi_driver2's, always
    assert not any(name.endswith('/Broken') or name.endswith('/notes') for name in types)


def test_a_header_converts_with_seq_zero_and_the_same_stamp(tmp_path):
    from sensor_msgs.msg import Range
    ts = HUMBLE
    msg = ts.types['sensor_msgs/msg/Range'](
        header=ts.types['std_msgs/msg/Header'](
            stamp=ts.types['builtin_interfaces/msg/Time'](sec=1700000000, nanosec=123456789),
            frame_id='SonarBack_frame'),
        radiation_type=0, field_of_view=0.52, min_range=0.25, max_range=2.55, range=3.5)
    c = ros2types.Converter([conn('/sonar/back', 'sensor_msgs/msg/Range')], str(tmp_path))
    assert c.problems == {}
    header = c.header('sensor_msgs/msg/Range')
    assert header['type'] == 'sensor_msgs/Range' and header['md5sum'] == Range._md5sum
    ros1 = Range()
    ros1.deserialize(c.to_ros1(ts.serialize_cdr(msg, 'sensor_msgs/msg/Range'), 'sensor_msgs/msg/Range'))
    assert (ros1.header.seq, ros1.header.stamp.secs, ros1.header.stamp.nsecs) == (0, 1700000000, 123456789)
    assert ros1.header.frame_id == 'SonarBack_frame' and abs(ros1.range - 3.5) < 1e-6
    assert c.to_ros1(b'\x00\x01\x00\x00\x01', 'sensor_msgs/msg/Range') == b''    # truncated: undecodable


def test_audio_buffer_keeps_the_ros1_definition_the_checks_read(tmp_path):
    c = ros2types.Converter([conn('/audio', 'naoqi_bridge_msgs/msg/AudioBuffer')], str(tmp_path))
    assert c.problems == {}
    header = c.header('naoqi_bridge_msgs/msg/AudioBuffer')
    assert 'uint8[] channelMap' in header['message_definition']


def test_a_type_without_a_definition_is_named():
    c = ros2types.Converter([conn('/laser', 'acme_msgs/msg/Scan'),
                             conn('/imu/base', 'sensor_msgs/msg/Imu')], '/nonexistent')
    assert list(c.problems) == ['/laser']
    assert 'acme_msgs/msg/Scan' in c.problems['/laser']
    broken = SimpleNamespace(format=SimpleNamespace(name='MSG'), data='float32[ broken')
    c = ros2types.Converter([conn('/laser', 'acme_msgs/msg/Scan', broken)], '/nonexistent')
    assert 'cannot be read' in c.problems['/laser']


def test_standard_types_follow_the_recordings_distro():
    humble = ros2types.standard_types('humble')['sensor_msgs/msg/Range'][1]
    assert [f for f, _ in humble][-1] == 'range'
    assert ros2types.standard_types(None) == ros2types.standard_types('humble')
    assert ros2types.standard_types('no such distro') == ros2types.standard_types('humble')
    rolling = ros2types.standard_types('rolling')['sensor_msgs/msg/Range'][1]
    assert [f for f, _ in rolling][-1] == 'variance'


def test_a_type_built_from_its_generated_definition_decodes_the_converted_bytes(tmp_path):
    """A type no ROS 1 package provides (here a touch message from msg/): its class is built
    from the generated ROS 1 definition, which must carry the Header's seq as the bytes do."""
    from rosbags.typesys import get_types_from_msg

    from pepper_interface_tests.sources import messages
    (tmp_path / 'Bumper.msg').write_text('Header header\nuint8 bumper\nuint8 state\n')
    ts = get_typestore(Stores.ROS2_HUMBLE)
    ts.register(get_types_from_msg('std_msgs/Header header\nuint8 bumper\nuint8 state\n',
                                   'naoqi_bridge_msgs/msg/Bumper'))
    raw = ts.serialize_cdr(ts.types['naoqi_bridge_msgs/msg/Bumper'](
        header=ts.types['std_msgs/msg/Header'](stamp=ts.types['builtin_interfaces/msg/Time'](sec=5, nanosec=7),
                                               frame_id='base_link'), bumper=2, state=1),
        'naoqi_bridge_msgs/msg/Bumper')
    c = ros2types.Converter([conn('/bumper', 'naoqi_bridge_msgs/msg/Bumper')], str(tmp_path))
    header = c.header('naoqi_bridge_msgs/msg/Bumper')
    assert 'uint32 seq' in header['message_definition']
    msg = messages.message_class(header['type'], header['message_definition'])()
    msg.deserialize(c.to_ros1(raw, 'naoqi_bridge_msgs/msg/Bumper'))
    assert (msg.header.stamp.secs, msg.header.stamp.nsecs, msg.header.frame_id) == (5, 7, 'base_link')
    assert (msg.bumper, msg.state) == (2, 1)
