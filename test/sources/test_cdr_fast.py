"""cdr_fast: the one-copy CDR -> ROS 1 conversion of camera frames, microphone buffers and /tf gives
byte for byte what rosbags' cdr_to_ros1 gives, over the alignments a frame id, an encoding, a
width and a channel map of any length produce; anything unusual falls back to rosbags. Pure: no
master, no recording."""
import struct
from types import SimpleNamespace

import pytest
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from pepper_interface_tests.sources import cdr_fast, ros2types
from rosbags_support import reads_ros2

pytestmark = reads_ros2

STORE = get_typestore(Stores.ROS2_HUMBLE)
STORE.register(get_types_from_msg(ros2types.AUDIO_BUFFER_DEFINITION_ROS2, 'naoqi_bridge_msgs/msg/AudioBuffer'))
IMAGE, AUDIO, TF = 'sensor_msgs/msg/Image', 'naoqi_bridge_msgs/msg/AudioBuffer', 'tf2_msgs/msg/TFMessage'
NONE = SimpleNamespace(format=SimpleNamespace(name='NONE'), data='')


def header(frame_id, nanosec=123456700):
    return STORE.types['std_msgs/msg/Header'](
        stamp=STORE.types['builtin_interfaces/msg/Time'](sec=1700000000, nanosec=nanosec), frame_id=frame_id)


def image(frame_id='CameraTop_optical_frame', encoding='rgb8', width=3, height=2, bpp=3, bigendian=0):
    import numpy as np
    data = (np.arange(width * height * bpp) % 251).astype(np.uint8)
    msg = STORE.types[IMAGE](header=header(frame_id), height=height, width=width, encoding=encoding,
                             is_bigendian=bigendian, step=width * bpp, data=data)
    return bytes(STORE.serialize_cdr(msg, IMAGE))


def audio(frame_id='', channel_map=(3, 5, 0, 2), samples=5):
    import numpy as np
    msg = STORE.types[AUDIO](header=header(frame_id), frequency=48000,
                             channel_map=np.array(channel_map, np.uint8),
                             data=(np.arange(samples * max(1, len(channel_map))) * 37 - 400).astype(np.int16))
    return bytes(STORE.serialize_cdr(msg, AUDIO))


def tf(frames, nanosec=123456700):
    """A TFMessage of (parent, child) pairs, each with its own translation and rotation."""
    import numpy as np
    t = STORE.types
    out = []
    for k, (parent, child) in enumerate(frames):
        out.append(t['geometry_msgs/msg/TransformStamped'](
            header=header(parent, nanosec + k), child_frame_id=child,
            transform=t['geometry_msgs/msg/Transform'](
                translation=t['geometry_msgs/msg/Vector3'](x=0.1 * k, y=-2.5, z=np.pi),
                rotation=t['geometry_msgs/msg/Quaternion'](x=0.0, y=0.5, z=-0.5, w=0.7071))))
    return bytes(STORE.serialize_cdr(t[TF](transforms=out), TF))


def slow(raw, msgtype):
    return bytes(STORE.cdr_to_ros1(raw, msgtype))


@pytest.mark.parametrize('frame_id', ['', 'a', 'ab', 'abc', 'abcd', 'CameraDepth_optical_frame'])
@pytest.mark.parametrize('encoding,width,bpp', [('rgb8', 3, 3), ('16UC1', 5, 2), ('mono8', 7, 1), ('bgra8', 1, 4)])
def test_an_image_converts_as_rosbags_converts_it(frame_id, encoding, width, bpp):
    raw = image(frame_id, encoding, width, 3, bpp, bigendian=width % 2)
    assert cdr_fast.image(raw) == slow(raw, IMAGE)


def test_an_empty_image_converts_as_rosbags_converts_it():
    raw = image('x', 'rgb8', 0, 0)
    assert cdr_fast.image(raw) == slow(raw, IMAGE)


@pytest.mark.parametrize('frame_id', ['', 'a', 'ab', 'abc', 'abcde'])
@pytest.mark.parametrize('channel_map', [(), (0,), (3, 5), (3, 5, 0), (3, 5, 0, 2), (0, 1, 2, 3, 4)])
def test_an_audio_buffer_converts_as_rosbags_converts_it(frame_id, channel_map):
    raw = audio(frame_id, channel_map)
    assert cdr_fast.audio_buffer(raw) == slow(raw, AUDIO)


@pytest.mark.parametrize('frames', [[], [('a', 'b')], [('odom', 'base_link'), ('ab', 'abc')],
                                    [('torso', 'Neck'), ('Neck', 'Head'), ('Head', 'CameraTop_frame'),
                                     ('abcd', 'abcde')]])
def test_a_tf_message_converts_as_rosbags_converts_it(frames):
    raw = tf(frames)
    assert cdr_fast.tf_message(raw) == slow(raw, TF)


def test_the_ros1_bytes_decode_with_the_checks_classes():
    """The converted frame decodes as the camera check decodes a ROS 1 frame: seq 0, the stamp
    to the nanosecond, the pixels."""
    from pepper_interface_tests.sources import messages
    m = messages.message_class('sensor_msgs/Image')()
    m.deserialize(cdr_fast.image(image('CameraTop_optical_frame')))
    assert (m.header.seq, m.header.stamp.secs, m.header.stamp.nsecs) == (0, 1700000000, 123456700)
    assert (m.width, m.height, m.encoding, m.step, bytes(m.data)[:4]) == (3, 2, 'rgb8', 9, bytes([0, 1, 2, 3]))


def _fields(m):
    return (m.header.seq, m.header.stamp.secs, m.header.stamp.nsecs, m.header.frame_id, m.height,
            m.width, m.encoding, m.is_bigendian, m.step, bytes(m.data))


@pytest.mark.parametrize('frame_id', ['', 'a', 'abc', 'CameraDepth_optical_frame'])
@pytest.mark.parametrize('encoding,width,bpp', [('rgb8', 3, 3), ('16UC1', 5, 2), ('mono8', 0, 1)])
def test_a_frame_read_in_place_is_the_message_its_ros1_bytes_decode_to(frame_id, encoding, width, bpp):
    """Ros2Image: the camera check's message from the CDR bytes, pixels a view of them (no
    copy), the same fields as the check's decoding of the ROS 1 bytes; bytes() of it are those
    bytes; the camera check decodes either alike."""
    from pepper_interface_tests.sensors.camera import ImageCheck
    raw = image(frame_id, encoding, width, 2, bpp, bigendian=width % 2)
    frame = cdr_fast.Ros2Image(memoryview(raw))
    assert bytes(frame) == slow(raw, IMAGE)
    via_ros1 = ImageCheck.decode(None, bytes(frame))
    in_place = ImageCheck.decode(None, frame)
    assert _fields(in_place) == _fields(via_ros1)
    assert isinstance(in_place.data, memoryview) and in_place.data.obj is raw
    with pytest.raises((ValueError, struct.error)):
        cdr_fast.Ros2Image(raw[:len(raw) - 1 - len(raw) // 3])


def test_the_converter_hands_frames_in_place_and_the_rest_as_ros1_bytes():
    c = ros2types.Converter([SimpleNamespace(topic='/t', msgtype=m, msgdef=NONE) for m in (IMAGE, AUDIO)],
                            '/nonexistent')
    raw = image()
    assert isinstance(c.for_checks(raw, IMAGE), cdr_fast.Ros2Image)
    assert c.for_checks(audio(), AUDIO) == slow(audio(), AUDIO)
    # a frame the in-place reading refuses is converted as before: b'' when rosbags cannot
    assert c.for_checks(raw[:len(raw) // 2], IMAGE) == b''


@pytest.mark.parametrize('msgtype,raw', [(IMAGE, image()), (AUDIO, audio()),
                                         (TF, tf([('CameraTop_optical_frame', 'x')]))])
def test_unusual_bytes_are_left_to_rosbags(msgtype, raw):
    convert = cdr_fast.CONVERTERS[msgtype]
    big_endian = b'\x00\x00' + raw[2:]
    for bad in (raw[:len(raw) // 2], raw[:10], big_endian):
        with pytest.raises((ValueError, struct.error)):
            convert(bad)
    # a string whose NUL is missing
    no_nul = bytearray(raw)
    name = len('CameraTop_optical_frame')
    no_nul[{IMAGE: 16 + name, AUDIO: 16, TF: 20 + name}[msgtype]] = 1
    with pytest.raises(ValueError):
        convert(bytes(no_nul))
    # and the converter then answers as rosbags does: b'' for what cannot be converted
    c = ros2types.Converter([SimpleNamespace(topic='/t', msgtype=msgtype, msgdef=NONE)], '/nonexistent')
    assert msgtype in c.fast
    assert c.to_ros1(raw[:len(raw) // 2], msgtype) == b''
    assert c.to_ros1(raw, msgtype) == slow(raw, msgtype)


def test_another_layout_under_the_same_name_is_converted_by_rosbags():
    """A recording whose AudioBuffer is not naoqi_driver2's (here: no channel_map) keeps the
    general conversion."""
    text = 'std_msgs/Header header\nuint16 frequency\nint16[] data\n'
    msgdef = SimpleNamespace(format=SimpleNamespace(name='MSG'), data=text)
    c = ros2types.Converter([SimpleNamespace(topic='/audio', msgtype=AUDIO, msgdef=msgdef),
                             SimpleNamespace(topic='/image', msgtype=IMAGE, msgdef=NONE)], '/nonexistent')
    assert AUDIO not in c.fast and IMAGE in c.fast


def test_a_tf_layout_seen_before_converts_as_rosbags_converts_it_and_a_new_name_is_not_mixed_up():
    """The second message of a layout (other stamps and numbers) goes through the layout's byte
    map; a message of the same size whose frame name differs is converted field by field."""
    frames = [('odom', 'base_link'), ('torso', 'Neck'), ('Neck', 'Head')]
    first, second = tf(frames, nanosec=1), tf(frames, nanosec=999)
    assert cdr_fast.tf_message(first) == slow(first, TF)
    assert len(first) in cdr_fast._TF_LAYOUTS
    assert cdr_fast._TF_LAYOUTS[len(first)].apply(second) is not None
    assert cdr_fast.tf_message(second) == slow(second, TF)
    renamed = tf([('odom', 'base_link'), ('torso', 'Nock'), ('Neck', 'Head')], nanosec=5)
    assert len(renamed) == len(first) and cdr_fast._TF_LAYOUTS[len(first)].apply(renamed) is None
    assert cdr_fast.tf_message(renamed) == slow(renamed, TF)
