#!/usr/bin/env python3
"""Test helper: publish touch events as naoqi_driver does (src/event/touch.cpp): the
naoqi_bridge_msgs type built from its definition (sources/naoqi_msgs.py, the package not
installed), latched off, one message per event, each when its time comes after the first
subscriber; or publish /diagnostics arrays named like another node's (not the driver's).

usage: touch_publisher.py TYPE TOPIC EVENTS      TYPE: Bumper, HandTouch or HeadTouch;
                                                 EVENTS: index:state@seconds,... e.g. 0:1@0.5,0:0@0.8
       touch_publisher.py diagnostics NAME       statuses "NAME: laser" at 2 Hz (another node's)
       touch_publisher.py operator TYPE TOPIC DELAYS
                                                 a person following /sensorTest/prompt: each zone
                                                 asked for (sensors/guide.py asked_zone) is pressed
                                                 DELAY s after its prompt arrives, for 0.3 s;
                                                 DELAYS: zone=seconds,... e.g. front=5,middle=0.5;
                                                 a zone not listed is never pressed
"""
import sys
import threading
import time

import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from std_msgs.msg import String

from pepper_interface_tests.sensors import guide, touch
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


def operator(kind, topic, spec):
    cls = naoqi_msgs.known_class('naoqi_bridge_msgs/' + kind)
    field, zones = touch.zones_of(kind)
    index = {z.id: i for i, z in enumerate(zones)}
    delays = {k: float(v) for k, v in (item.split('=') for item in spec.split(','))}
    pub = rospy.Publisher(topic, cls, queue_size=10)

    def send(i, state):
        msg = cls()
        setattr(msg, field, i)
        msg.state = state
        pub.publish(msg)

    def press(zone):
        send(index[zone], 1)
        time.sleep(0.3)
        send(index[zone], 0)

    def heard(msg):
        zone_id = guide.asked_zone(msg.data)
        zone = zone_id.partition('/')[2] if zone_id else None
        if zone in delays:
            timer = threading.Timer(delays[zone], press, args=(zone,))
            timer.daemon = True
            timer.start()
    rospy.Subscriber(guide.PROMPT_TOPIC, String, heard, queue_size=10)
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
    elif sys.argv[1] == 'operator':
        operator(sys.argv[2], sys.argv[3], sys.argv[4])
    else:
        events(sys.argv[1], sys.argv[2], sys.argv[3])
