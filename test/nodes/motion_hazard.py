#!/usr/bin/env python3
"""Test helper: a hazard that appears during sensorTest --move's turn, on a topic of its own
(the test's topics file points the sensor there), published by a real rospy node.

Usage: motion_hazard.py sonar|bumper TOPIC TRIGGER_FILE

sonar: sensor_msgs/Range at 10 Hz, 2.0 m (free space) until TRIGGER_FILE exists, then 0.2 m
(closer than the motion check's stop_distance). bumper: pepper_interface_tests/Bumper (the
naoqi_bridge_msgs definition), one "released" event at the start, then "back pressed" once
TRIGGER_FILE exists. Prints "hazard up" once advertised.
"""
import os
import sys

import rospy
from sensor_msgs.msg import Range

from pepper_interface_tests.msg import Bumper


def main():
    kind, topic, trigger = sys.argv[1:4]
    rospy.init_node('motion_hazard', anonymous=True, disable_signals=True)
    cls = Range if kind == 'sonar' else Bumper
    pub = rospy.Publisher(topic, cls, queue_size=10)
    print('hazard up', flush=True)
    rate = rospy.Rate(10)
    pressed = False
    try:
        while not rospy.is_shutdown():
            near = os.path.exists(trigger)
            if kind == 'sonar':
                m = Range(radiation_type=Range.ULTRASOUND, field_of_view=0.5236, min_range=0.25,
                          max_range=2.55, range=0.2 if near else 2.0)
                m.header.stamp = rospy.Time.now()
                m.header.frame_id = 'SonarFront_frame'
                pub.publish(m)
            elif near and not pressed:
                pub.publish(Bumper(bumper=Bumper.back, state=Bumper.statePressed))
                pressed = True
            rate.sleep()
    except KeyboardInterrupt:
        pass


if __name__ == '__main__':
    main()
