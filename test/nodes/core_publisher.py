#!/usr/bin/env python3
"""Test helper: publish one kind of sensor message on a topic, good or with one fault.

usage: core_publisher.py KIND TOPIC [--rate HZ] [--fault NAME] [--die-after S] [--node NAME]
                         [--frame FRAME_ID]
KIND: range, laser, joints, odometry, imu, string (a wrong type), listener (subscribes a
std_msgs/String topic and prints what it receives).
Faults: nan, out_of_range, broken_quaternion, zero_stamp, old_stamp, frame, missing_joint,
dup_joint, short_velocity, bad_limits, wrong_ranges.
--frame sets header.frame_id instead of the kind's default (e.g. SonarFront_frame for the front
sonar); the `frame` fault still wins.
"""
import argparse
import os
import sys

import rospy
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, JointState, LaserScan, Range
from std_msgs.msg import String

# the test helpers (test/helpers/, beside this script's folder test/nodes/)
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), 'helpers'))
import fake_pepper as fake  # noqa: E402

FRAME = {}   # {'frame': frame_id given with --frame}
BUILDERS = {'range': fake.sonar, 'laser': fake.laser, 'joints': fake.joints,
            'odometry': fake.odometry, 'imu': fake.imu}


def make(kind, fault, i):
    """One message of `kind` (test/helpers/fake_pepper.py), stamped now, with `fault` ('' for none)."""
    if kind == 'string':
        return String(data='not a sensor')
    if kind not in BUILDERS:
        raise SystemExit('unknown kind ' + kind)
    frame = FRAME.get('frame')
    kw = {'frame_id': frame} if frame is not None else {}
    return BUILDERS[kind](i, rospy.Time.now(), fault, **kw)


TYPES = {'range': Range, 'laser': LaserScan, 'joints': JointState, 'odometry': Odometry,
         'imu': Imu, 'string': String}


def main():
    p = argparse.ArgumentParser()
    p.add_argument('kind')
    p.add_argument('topic')
    p.add_argument('--rate', type=float, default=10.0)
    p.add_argument('--fault', default='')
    p.add_argument('--die-after', type=float, default=0.0)
    p.add_argument('--node', default='core_publisher')
    p.add_argument('--frame', default=None)
    a = p.parse_args(rospy.myargv(sys.argv)[1:])
    if a.frame is not None:
        FRAME['frame'] = a.frame
    rospy.init_node(a.node, anonymous=True)
    if a.kind == 'listener':
        rospy.Subscriber(a.topic, String, lambda m: (print('heard: ' + m.data), sys.stdout.flush()))
        print('listening', flush=True)
        rospy.spin()
        return
    pub = rospy.Publisher(a.topic, TYPES[a.kind], queue_size=10)
    print('publishing', flush=True)
    rate = rospy.Rate(a.rate)
    start = rospy.get_time()
    i = 0
    while not rospy.is_shutdown():
        if a.die_after and rospy.get_time() - start > a.die_after:
            break
        pub.publish(make(a.kind, a.fault, i))
        i += 1
        rate.sleep()


if __name__ == '__main__':
    main()
