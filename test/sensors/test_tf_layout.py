"""Unit: a /tf message of a known layout decoded in place (sensors/tf_layout.py) is the message
genpy decodes, field for field, on the real driver's recording and on every kind of change
(a frame renamed at the same length, another size, a broken message, an nsecs past a second)."""
import io
import os
import struct

import genpy
import pytest
import rosbag
from tf2_msgs.msg import TFMessage

from pepper_interface_tests.emulator.tf_publisher import tf_message
from pepper_interface_tests.emulator.urdf_tree import JOINTS, driver_tree
from pepper_interface_tests.sensors.tf_layout import LayoutDecoder

HERE = os.path.dirname(os.path.abspath(__file__))
GOLDEN = os.path.join(HERE, '..', 'fixtures', 'real-driver', 'healthy_stereo.bag')
TF = 'tf2_msgs/TFMessage'


def fields(msg):
    """Every field of a TFMessage but the seq numbers (tf2 ignores them; not decoded in place)."""
    return [(t.header.frame_id, t.header.stamp.secs, t.header.stamp.nsecs, t.child_frame_id,
             t.transform.translation.x, t.transform.translation.y, t.transform.translation.z,
             t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z,
             t.transform.rotation.w) for t in msg.transforms]


def wire(joints, t):
    buff = io.BytesIO()
    tf_message(driver_tree(joints), genpy.Time.from_sec(t)).serialize(buff)
    return buff.getvalue()


STILL = {j.name: 0.0 for j in JOINTS if j.moving}


def test_the_real_drivers_tf_decodes_in_place_as_genpy_decodes_it():
    decoder = LayoutDecoder(TF)
    n = 0
    with rosbag.Bag(GOLDEN) as bag:
        for _topic, raw, _t in bag.read_messages(topics=['/tf'], raw=True):
            buff = raw[1]
            assert fields(decoder.decode('driver', buff)) == fields(TFMessage().deserialize(buff))
            n += 1
    assert n > 100
    assert decoder.learned == 1 and decoder.in_place == n - 1, (decoder.learned, decoder.in_place)


def test_a_moving_head_is_read_in_place_with_its_new_numbers():
    decoder = LayoutDecoder(TF)
    first = decoder.decode('k', wire(STILL, 10.0))
    turned = wire(dict(STILL, HeadYaw=0.5), 10.02)
    got = decoder.decode('k', turned)
    assert got is first and decoder.in_place == 1         # the same objects, overwritten
    assert fields(got) == fields(TFMessage().deserialize(turned))


def test_a_frame_renamed_at_the_same_length_is_decoded_by_genpy():
    decoder = LayoutDecoder(TF)
    buff = wire(STILL, 10.0)
    decoder.decode('k', buff)
    renamed = buff.replace(b'CameraTop_frame', b'CameraXop_frame')
    assert len(renamed) == len(buff) and renamed != buff
    got = decoder.decode('k', renamed)
    assert decoder.in_place == 0 and decoder.learned == 2
    assert 'CameraXop_frame' in [t.child_frame_id for t in got.transforms]
    assert fields(got) == fields(TFMessage().deserialize(renamed))


def test_another_size_or_a_broken_message_is_genpys_to_read():
    decoder = LayoutDecoder(TF)
    full = wire(STILL, 10.0)
    decoder.decode('k', full)
    only_odom = io.BytesIO()
    tf_message(driver_tree(STILL)[:1], genpy.Time.from_sec(10.02)).serialize(only_odom)
    got = decoder.decode('k', only_odom.getvalue())
    assert len(got.transforms) == 1 and decoder.in_place == 0
    with pytest.raises(genpy.DeserializationError):
        decoder.decode('k', full[:-9])        # cut: what genpy says, never a half-filled message


def test_nanoseconds_past_a_second_are_kept_as_genpy_keeps_them():
    decoder = LayoutDecoder(TF)
    buff = bytearray(wire(STILL, 10.0))
    decoder.decode('k', bytes(buff))
    struct.pack_into('<I', buff, 12, 1500000000)       # the first transform's nsecs
    got = decoder.decode('k', bytes(buff))
    assert got.transforms[0].header.stamp.nsecs == 1500000000 and decoder.in_place == 0
