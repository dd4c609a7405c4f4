#!/usr/bin/env python3
"""Test helper: naoqi_driver's /diagnostics of a resting robot (every joint's Stiffness 0),
arriving late: its first message goes out DELAY s after the first subscriber connects, then
one a second (naoqi_driver's "diag" frequency). A real rospy node.

Usage: late_diagnostics.py TOPIC DELAY
Prints "diagnostics up" once advertised.
"""
import sys
import time

import rospy
from diagnostic_msgs.msg import DiagnosticArray

from pepper_interface_tests.emulator.events import JOINTS, driver_array


def main():
    topic, delay = sys.argv[1], float(sys.argv[2])
    rospy.init_node('late_diagnostics', anonymous=True, disable_signals=True)
    pub = rospy.Publisher(topic, DiagnosticArray, queue_size=10)
    print('diagnostics up', flush=True)
    try:
        while pub.get_num_connections() == 0 and not rospy.is_shutdown():
            time.sleep(0.02)
        time.sleep(delay)
        while not rospy.is_shutdown():
            pub.publish(driver_array({j: 40.0 for j in JOINTS}, 90, charging=False, stiffness=0.0))
            time.sleep(1.0)
    except KeyboardInterrupt:
        pass


if __name__ == '__main__':
    main()
