"""Unit: TfBuffer's answers are tf2's: interpolation, extrapolation refused with its gap, a
missing frame, two trees, the latest common time, static transforms, the cache time. The same
tests run on ROS 1 (tf2_ros.Buffer) and in the ROS 2 tier (tools/ros2/tests.sh runs this file:
ROS 2's own tf2_py BufferCore), so both give the same answers."""
import os

import genpy
import pytest

from pepper_interface_tests.emulator.tf_publisher import tf_message
from pepper_interface_tests.sources import tf_buffer
from pepper_interface_tests.sources.tf_buffer import TF2_MISSING, TfBuffer

pytestmark = pytest.mark.skipif(bool(TF2_MISSING), reason='tf2 is not importable on this Python')
ONE = (0.0, 0.0, 0.0, 1.0)


def put(buf, transforms, t, static=False):
    return buf.add(tf_message(transforms, genpy.Time.from_sec(t)).transforms, static, '/test')


def moving():
    """base -> a moving 2 m along x between stamps 1 and 2; a -> b fixed, 0.5 m along y."""
    buf = TfBuffer()
    put(buf, [('base', 'a', (0.0, 0.0, 0.0), ONE), ('a', 'b', (0.0, 0.5, 0.0), ONE)], 1.0)
    put(buf, [('base', 'a', (2.0, 0.0, 0.0), ONE), ('a', 'b', (0.0, 0.5, 0.0), ONE)], 2.0)
    return buf


def test_the_ros_version_s_own_tf2_keeps_the_tree():
    if os.environ.get('ROS_VERSION') == '2':
        assert tf_buffer.tf2_core is not None and tf_buffer.tf2_ros is None
        assert 'rospy' not in __import__('sys').modules
    else:
        assert tf_buffer.tf2_ros is not None and tf_buffer.tf2_core is None


def test_between_two_stamps_tf2_interpolates():
    buf = moving()
    (x, y, z), q = buf.pose('base', 'b', 1.5)
    assert (x, y, z) == pytest.approx((1.0, 0.5, 0.0), abs=1e-9) and q == pytest.approx(ONE)
    assert buf.lookup('b', 'base', 1.25).ok and buf.lookup('b', 'base', 2.0).ok


@pytest.mark.parametrize('stamp, gap', [(2.3, 0.3), (0.5, -0.5)], ids=['future', 'past'])
def test_beyond_the_data_tf2_refuses_and_says_by_how_much(stamp, gap):
    got = moving().lookup('b', 'base', stamp)
    assert not got.ok and got.kind == 'extrapolation', got.error
    assert got.gap == pytest.approx(gap, abs=1e-6), got.error
    assert moving().pose('base', 'b', stamp) is None


def test_a_frame_never_named_is_missing_and_two_trees_are_unconnected():
    buf = moving()
    put(buf, [('other', 'c', (1.0, 0.0, 0.0), ONE)], 1.5)
    missing = buf.lookup('nowhere', 'base', 1.5)
    assert not missing.ok and missing.kind == 'missing', missing.error
    apart = buf.lookup('c', 'base', 1.5)
    assert not apart.ok and apart.kind == 'unconnected', apart.error
    assert buf.latest('c', 'base') is None


def test_the_latest_common_time_of_a_chain_and_of_a_static_one():
    buf = moving()
    assert buf.latest('b', 'base') == 2.0
    put(buf, [('base', 's', (0.0, 0.0, 1.0), ONE)], 1.0, static=True)
    assert buf.latest('s', 'base') == 0.0       # static: any time
    assert buf.lookup('s', 'base', 100.0).ok and buf.pose('base', 's', 0.0)[0] == pytest.approx((0, 0, 1))


def test_the_frames_and_their_parents_as_tf2_holds_them():
    buf = moving()
    assert sorted(buf.frames()) == ['a', 'b', 'base']
    assert buf.parents() == {'a': 'base', 'b': 'a'}


def test_stamps_older_than_the_cache_time_are_dropped():
    buf = TfBuffer(cache_time=2.0)
    for t in range(1, 11):
        put(buf, [('base', 'a', (float(t), 0.0, 0.0), ONE)], float(t))
    assert buf.lookup('a', 'base', 9.0).ok
    old = buf.lookup('a', 'base', 3.0)
    assert not old.ok and old.kind == 'extrapolation' and old.gap < 0, old.error


def test_a_message_is_found_at_its_own_stamp_in_seconds():
    """The checks ask at float seconds; tf2 holds both the stamps and the questions on ROS 1's
    grid (tf2_py's to_sec then ros::Time::fromSec), so a message's own stamp is never a few
    hundred nanoseconds beyond the data."""
    buf = TfBuffer()
    stamp = genpy.Time(1700000000, 123456789)
    buf.add(tf_message([('base', 'a', (1.0, 0.0, 0.0), ONE)], stamp).transforms, False, '/test')
    assert buf.latest('a', 'base') == stamp.to_sec()
    assert buf.lookup('a', 'base', stamp.to_sec()).ok
