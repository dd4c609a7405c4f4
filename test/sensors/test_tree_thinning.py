"""Unit: the tree decodes a node's /tf at most once per THIN_S s of stamps per layout
(sensors/tree.py), counts the rest, and never thins /tf_static, another node or another layout;
the frames it places are those of every message."""
import io

import genpy
import pytest

from pepper_interface_tests.emulator.tf_publisher import tf_message
from pepper_interface_tests.emulator.urdf_tree import JOINTS, driver_tree
from pepper_interface_tests.sensors import tree
from pepper_interface_tests.sources.tf_buffer import TF2_MISSING

pytestmark = pytest.mark.skipif(bool(TF2_MISSING), reason='tf2_ros is not importable on this Python')


STILL = {j.name: 0.0 for j in JOINTS if j.moving}     # every joint's state: the whole tree


def wire(transforms, t):
    buff = io.BytesIO()
    tf_message(transforms, genpy.Time.from_sec(t)).serialize(buff)
    return buff.getvalue()


def feed(topic, node, transforms, t):
    topic.feed_raw(tree.TF_TYPE, wire(transforms, t), t, t, {'callerid': node})


def test_a_50_hz_tree_is_decoded_every_third_message_and_every_message_counted():
    record = tree.TreeRecord()
    topic = tree.TfTopic(record, '/tf', static=False)
    full = driver_tree(STILL)
    for i in range(50):                         # 1 s at 50 Hz
        feed(topic, '/naoqi_driver', full, 100.0 + i * 0.02)
    assert record.messages + record.thinned == 50
    # kept: the first, then each first message THIN_S or more after the last kept (0.06 s at 50 Hz)
    assert record.messages == 17, record.messages
    # the frames of the kept messages are placed at a stamp between them (interpolated)
    assert record.buffer.lookup('CameraTop_optical_frame', 'base_footprint', 100.51).ok


def test_other_nodes_layouts_static_and_a_clock_going_back_are_not_thinned():
    record = tree.TreeRecord()
    topic = tree.TfTopic(record, '/tf', static=False)
    static = tree.TfTopic(record, '/tf_static', static=True)
    full = driver_tree(STILL)
    one = [('torso', 'Neck', (0.0, 0.0, 0.1), (0.0, 0.0, 0.0, 1.0))]
    feed(topic, '/naoqi_driver', full, 10.0)
    feed(topic, '/robot_state_publisher', full, 10.01)    # another node
    feed(topic, '/naoqi_driver', one, 10.02)              # another layout
    feed(topic, '/naoqi_driver', full, 9.0)               # stamps went back: kept
    for i in range(3):
        feed(static, '/static_pub', one, 10.0 + 0.001 * i)
    assert record.thinned == 0 and record.messages == 7


def test_a_message_too_short_to_peek_is_decoded_as_before():
    assert tree._peek(b'') is None and tree._peek(b'\x00\x00\x00\x00') is None
    data = wire(driver_tree({}), 5.0)
    assert tree._peek(data[:18]) is None and tree._peek(data)[1] == pytest.approx(5.0)
