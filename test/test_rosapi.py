"""Unit: rosapi's logging on ROS 1 reaches rospy's own functions (loginfo, logwarn, logerr)."""
import pytest

from pepper_interface_tests import rosapi

pytestmark = pytest.mark.unit


@pytest.mark.parametrize('log', [rosapi.loginfo, rosapi.logwarn, rosapi.logerr])
def test_each_level_is_one_of_rospys_functions(log, capsys):
    """rosapi.logerr once called rospy.logerror, which does not exist: a traceback where the
    emulator meant to say why a publisher failed."""
    log('rosapi says %s', 'hello')
