#!/usr/bin/env python3
"""Test helper: publish sensor_msgs/Range at 10 Hz on TOPIC whose header.frame_id is hostile:
`control` = "Sonar\\x01\\x1b[31mRED\\x1b[0m\\x07" (a control character, ANSI colour escapes,
a bell), `huge` = 200,000 characters.

usage: odd_frame_publisher.py TOPIC control|huge
"""
import os
import sys

import rospy
from sensor_msgs.msg import Range

# the test helpers (test/helpers/, beside this script's folder test/nodes/)
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), 'helpers'))
import fake_pepper as fake  # noqa: E402

FRAMES = {'control': 'Sonar\x01\x1b[31mRED\x1b[0m\x07', 'huge': 'F' * 200000}


def main():
    topic, kind = sys.argv[1], sys.argv[2]
    rospy.init_node('odd_frame_publisher', anonymous=True)
    pub = rospy.Publisher(topic, Range, queue_size=10)
    rate = rospy.Rate(10)
    while not rospy.is_shutdown():
        m = fake.sonar(t=rospy.Time.now(), frame_id=FRAMES[kind], range=1.0)
        pub.publish(m)
        try:
            rate.sleep()
        except rospy.ROSInterruptException:
            break


if __name__ == '__main__':
    main()
