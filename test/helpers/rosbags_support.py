"""Whether this Python's rosbags reads ROS 2 recordings for sensorTest (sources/ros2bag.py
ROSBAGS_MIN, 0.10). On Python 3.8, the Noetic tier's (tools/platform/noetic-tests.sh), only
rosbags 0.9.23 installs: sensorTest refuses ROS 2 recordings there in one sentence
(sources/test_ros2_bags.py shows it), and the tests of reading them are skipped."""
import pytest

from pepper_interface_tests.sources.ros2bag import ROSBAGS_MIN, rosbags_version

HAVE = rosbags_version()
OLD_ROSBAGS = HAVE < ROSBAGS_MIN
reads_ros2 = pytest.mark.skipif(OLD_ROSBAGS, reason='rosbags %s reads no ROS 2 recording for '
                                'sensorTest (it needs %s, Python 3.10+)'
                                % ('.'.join(map(str, HAVE)), '.'.join(map(str, ROSBAGS_MIN))))
