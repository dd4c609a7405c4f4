"""The history depth of each of naoqi_driver2's publishers, which the emulator gives its own on
ROS 2 (on ROS 1 a publisher's queue size is the emulator's own choice: publishers.py).

Every one of them is reliable and volatile (none is transient-local but /robot_description,
which the emulator does not publish: docs/drivers.md). Read from ros-naoqi/naoqi_driver2 at tag
2.1.2 and confirmed by what it offered in its golden recordings (test/fixtures/real-driver2/,
the offered QoS in each metadata.yaml; test/emulator/test_conformance2.py holds both)."""
from typing import Dict

# src/publishers/basic.hpp:72 `create_publisher<T>(topic_, 10)`: the laser, both IMUs, odom,
# /diagnostics, the touch events and the audio (src/naoqi_driver.cpp:709, 720, 734, 841, 958;
# src/event/touch.cpp:48, src/event/audio.hpp:87); /joint_states too (src/publishers/joint_state.cpp:46)
DEFAULT_DEPTH = 10
DEPTH_BY_FAMILY: Dict[str, int] = {
    # image_transport::create_camera_publisher(node, topic_) (src/publishers/camera.cpp:51)
    # takes rmw_qos_profile_default, keep-last 10 (image_transport 3.1.9 image_transport.hpp:75-77;
    # rmw qos_profiles.h:51-56)
    'camera': 10,
    'depth': 10,
    # src/publishers/sonar.cpp:53 `create_publisher<sensor_msgs::msg::Range>(topics_[i], 1)`
    'range': 1,
    # tf2_ros::TransformBroadcaster (src/publishers/joint_state.cpp:48): DynamicBroadcasterQoS,
    # keep-last 100 (geometry2 0.25.8 tf2_ros/include/tf2_ros/qos.hpp:49)
    'tf': 100,
}
# /info: an InfoPublisher is a BasicPublisher (src/publishers/info.hpp:36), keep-last 10, volatile
INFO_DEPTH = 10


def depth(family: str) -> int:
    """The keep-last depth naoqi_driver2 publishes a stream of this check family with."""
    return DEPTH_BY_FAMILY.get(family, DEFAULT_DEPTH)
