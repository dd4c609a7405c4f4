"""The emulator's fault tf:second_publisher: a second node on /tf, as a robot_state_publisher
started next to naoqi_driver with another robot description publishes it: here one fixed
transform, Head -> CameraTop_frame, 1 cm above naoqi_driver's (share/urdf/pepper.urdf:527,
CameraTop_sensor_fixedjoint at 0.0868 0 0.1631), at 10 Hz, stamped now.

Run by emulator/tf_publisher.py as `python -m pepper_interface_tests.emulator.second_publisher
TOPIC`; it ends with the master or on SIGTERM."""
import sys
from typing import List, Optional

import rospy
from geometry_msgs.msg import TransformStamped
from tf2_msgs.msg import TFMessage


def main(argv: Optional[List[str]] = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    topic = args[0] if args else '/tf'
    rospy.init_node('robot_state_publisher', anonymous=True, disable_signals=False)
    pub = rospy.Publisher(topic, TFMessage, queue_size=10)
    rate = rospy.Rate(10.0)
    while not rospy.is_shutdown():
        t = TransformStamped()
        t.header.stamp = rospy.Time.now()
        t.header.frame_id, t.child_frame_id = 'Head', 'CameraTop_frame'
        t.transform.translation.x, t.transform.translation.z = 0.0868, 0.1731
        t.transform.rotation.w = 1.0
        pub.publish(TFMessage(transforms=[t]))
        try:
            rate.sleep()
        except rospy.ROSInterruptException:
            break
    return 0


if __name__ == '__main__':
    sys.exit(main())
