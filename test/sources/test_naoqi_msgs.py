"""The naoqi_bridge_msgs types this package carries without naoqi_bridge_msgs installed
(sources/naoqi_msgs.py, msg/*.msg) against the upstream text. Pure: no ROS master."""
import genpy.dynamic

from pepper_interface_tests.sources import messages, naoqi_msgs

# ros-naoqi/naoqi_bridge_msgs master (ec254a9), msg/JointAnglesWithSpeed.msg as published,
# comments and all: the md5sum of the real package's type is computed from exactly this text
UPSTREAM_JOINT_ANGLES = """Header header

# A list of joint names, corresponding to their names in the Nao docs.
# This must either have the same length as joint_angles or 
# length 1 if it's a keyword such as 'Body' (for all angles)
string[] joint_names
float32[] joint_angles

# fraction of max joint velocity [0:1]
float32 speed

# Absolute angle (=0, default) or relative change
uint8 relative
"""
# what a connection header or a bag carries after the text: the definition of each dependency
HEADER = '=' * 80 + '\nMSG: std_msgs/Header\nuint32 seq\ntime stamp\nstring frame_id\n'
# the md5sum of naoqi_bridge_msgs/JointAnglesWithSpeed as the generated code of other packages
# states it (e.g. the rosserial and rosnodejs headers generated from naoqi_bridge_msgs); a
# constant, so that an edit of the text above cannot move both sides of the test at once
UPSTREAM_MD5 = '052ca11f74a00ad6745dfff6ebc2b4d8'


def test_joint_angles_with_speed_has_the_upstream_md5sum():
    name = 'naoqi_bridge_msgs/JointAnglesWithSpeed'
    upstream = genpy.dynamic.generate_dynamic(name, UPSTREAM_JOINT_ANGLES + HEADER)[name]
    assert upstream._md5sum == UPSTREAM_MD5
    # known without naoqi_bridge_msgs installed, under the driver's own type name
    cls = naoqi_msgs.joint_angles_class()
    assert cls._type == name and cls._md5sum == UPSTREAM_MD5
    assert messages.message_class(name)._md5sum == UPSTREAM_MD5
    # built by catkin from msg/JointAnglesWithSpeed.msg
    own = messages.message_class('pepper_interface_tests/JointAnglesWithSpeed')
    assert own._md5sum == UPSTREAM_MD5 and own._type == 'pepper_interface_tests/JointAnglesWithSpeed'
    m = cls(joint_names=['HeadYaw'], joint_angles=[0.5], speed=0.1, relative=0)
    assert list(m.__slots__) == ['header', 'joint_names', 'joint_angles', 'speed', 'relative']
