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
import math
import sys

import rospy
from geometry_msgs.msg import Quaternion
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, JointState, LaserScan, Range
from std_msgs.msg import String

JOINTS = ['HeadYaw', 'HeadPitch', 'HipRoll', 'HipPitch', 'KneePitch', 'LShoulderPitch',
          'LShoulderRoll', 'LElbowYaw', 'LElbowRoll', 'LWristYaw', 'LHand', 'RShoulderPitch',
          'RShoulderRoll', 'RElbowYaw', 'RElbowRoll', 'RWristYaw', 'RHand',
          'WheelFL', 'WheelFR', 'WheelB']


def stamp(h, fault, frame):
    h.stamp = rospy.Time(0) if fault == 'zero_stamp' else (
        rospy.Time.now() - rospy.Duration(30) if fault == 'old_stamp' else rospy.Time.now())
    h.frame_id = 'wrong_frame' if fault == 'frame' else FRAME.get('frame', frame)


FRAME = {}   # {'frame': frame_id given with --frame}


def make(kind, fault, i):
    if kind == 'range':
        m = Range(radiation_type=Range.ULTRASOUND, field_of_view=0.5236, min_range=0.25, max_range=2.55)
        if fault == 'bad_limits':
            m.min_range, m.max_range = 3.0, 1.0
        m.range = float('nan') if fault == 'nan' else (6.0 if fault == 'out_of_range' else 1.0 + 0.5 * math.sin(i / 5.0))
        stamp(m.header, fault, 'SonarBack_frame')
        return m
    if kind == 'laser':
        m = LaserScan(angle_min=-2.0944, angle_max=2.0944, range_min=0.1, range_max=3.0, scan_time=0.1)
        m.angle_increment = (m.angle_max - m.angle_min) / 60
        r = [1.5 + 0.2 * math.sin(k / 4.0 + i / 10.0) for k in range(61)]
        for k in list(range(15, 23)) + list(range(38, 46)):
            r[k] = -1.0
        if fault == 'nan':
            r = [float('nan')] * 61
        if fault == 'wrong_ranges':
            r = r[:40]
        m.ranges = r
        stamp(m.header, fault, 'base_footprint')
        return m
    if kind == 'joints':
        names = list(JOINTS)
        if fault == 'missing_joint':
            names.remove('HeadYaw')
        if fault == 'dup_joint':
            names[1] = names[0]
        # each joint swings around the middle of its URDF limits (sensors/joint_limits.py)
        m = JointState(name=names, position=[_middle(n) + 0.1 * math.sin(i / 20.0) for n in names],
                       velocity=[0.0] * (len(names) - (1 if fault == 'short_velocity' else 0)),
                       effort=[0.0] * len(names))
        if fault == 'nan':
            m.position[2] = float('nan')
        stamp(m.header, fault, '')
        return m
    if kind == 'odometry':
        m = Odometry(child_frame_id='base_link')
        m.pose.pose.position.x = 0.01 * i
        m.pose.pose.orientation = Quaternion(0, 0, 0, 2.0 if fault == 'broken_quaternion' else 1.0)
        m.twist.twist.linear.x = 0.1
        stamp(m.header, fault, 'odom')
        return m
    if kind == 'imu':
        m = Imu()
        m.orientation = Quaternion(0, 0, 0, 0.5 if fault == 'broken_quaternion' else 1.0)
        # the inertial board's raw values carry noise from message to message
        m.linear_acceleration.z = float('nan') if fault == 'nan' else 9.81
        m.angular_velocity.z = 0.001 * math.sin(1.3 * i)
        stamp(m.header, fault, 'base_footprint')
        return m
    if kind == 'string':
        return String(data='not a sensor')
    raise SystemExit('unknown kind ' + kind)


def _middle(name):
    from pepper_interface_tests.sensors.joint_limits import LIMITS
    lo, hi = LIMITS.get(name, (None, None))[:2]
    return 0.0 if lo is None else (lo + hi) / 2.0


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
