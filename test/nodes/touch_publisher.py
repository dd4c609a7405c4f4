#!/usr/bin/env python3
"""Test helper: publish touch events as naoqi_driver does (src/event/touch.cpp): the
naoqi_bridge_msgs type built from its definition (sources/naoqi_msgs.py, the package not
installed), latched off, one message per event, each when its time comes after the first
subscriber; or publish /diagnostics arrays named like another node's (not the driver's).

usage: touch_publisher.py TYPE TOPIC EVENTS      TYPE: Bumper, HandTouch or HeadTouch;
                                                 EVENTS: index:state@seconds,... e.g. 0:1@0.5,0:0@0.8
       touch_publisher.py diagnostics NAME       statuses "NAME: laser" at 2 Hz (another node's)
"""
import sys
import time

import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus

from pepper_interface_tests.sensors import touch
from pepper_interface_tests.sources import naoqi_msgs


def events(kind, topic, spec):
    cls = naoqi_msgs.known_class('naoqi_bridge_msgs/' + kind)
    field = touch.zones_of(kind)[0]
    pub = rospy.Publisher(topic, cls, queue_size=10)
    while pub.get_num_connections() == 0 and not rospy.is_shutdown():
        time.sleep(0.02)
    t0 = time.monotonic()
    for item in spec.split(','):
        what, _, at = item.partition('@')
        index, state = (int(x) for x in what.split(':'))
        time.sleep(max(0.0, t0 + float(at) - time.monotonic()))
        msg = cls()
        setattr(msg, field, index)
        msg.state = state
        pub.publish(msg)
    rospy.spin()


def diagnostics(name):
    pub = rospy.Publisher('/diagnostics', DiagnosticArray, queue_size=10)
    rate = rospy.Rate(2)
    while not rospy.is_shutdown():
        pub.publish(DiagnosticArray(status=[DiagnosticStatus(level=2, name='%s: laser' % name, message='FAIL')]))
        rate.sleep()


if __name__ == '__main__':
    rospy.init_node('touch_publisher', anonymous=True, disable_signals=False)
    if sys.argv[1] == 'diagnostics':
        diagnostics(sys.argv[2])
    else:
        events(sys.argv[1], sys.argv[2], sys.argv[3])
