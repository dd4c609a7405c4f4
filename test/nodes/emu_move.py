#!/usr/bin/env python3
"""Test helper: command the robot as a user of naoqi_driver does (real rospy publishers of
/joint_angles, /move_base_simple/goal and /cmd_vel) and record what its sensors publish (real
subscribers); print one JSON object.

Usage: emu_move.py [--ns /naoqi_driver] [--head 0.3] [--turn 0.5] [--spin 0.3]

Once the three command topics are connected and odometry flows (t = 0), at the times of
SCHEDULE (printed with the data as "schedule"):
  head  /joint_angles  HeadYaw -> --head rad at speed 0.2 (setAngles)
  goal  /move_base_simple/goal  base_footprint, yaw --turn (moveTo: about 1.75 s for 0.5 rad)
  spin  /cmd_vel  angular.z --spin (move); stop: a zero twist; end: the recording ends.
Recorded, each with its receive time t (s since t = 0) and its header stamp: odometry (x, y,
yaw, twist), the base IMU (gyro, accelerometer, orientation yaw), /joint_states (HeadYaw and
the wheels), the laser's ranges, the front sonar, the front camera's column profile (grey mean
of the upper rows per column) and the last /diagnostics stiffness of HeadYaw.
"""
import argparse
import json
import math
import sys
import threading
import time

import numpy as np
import rospy
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import PoseStamped, Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Image, Imu, JointState, LaserScan, Range

from pepper_interface_tests.sources.naoqi_msgs import joint_angles_class

SCHEDULE = dict(head=0.8, goal=1.4, spin=3.8, stop=4.5, end=5.3)
T0 = [None]
DATA = {k: [] for k in ('odom', 'imu', 'joints', 'laser', 'sonar', 'camera')}
LAST = {}
LOCK = threading.Lock()


def yaw_of(q):
    return math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))


def record(key, row):
    with LOCK:
        if T0[0] is not None:
            DATA[key].append([round(time.monotonic() - T0[0], 4)] + row)


def on_odom(m):
    LAST['odom'] = True
    p = m.pose.pose
    record('odom', [m.header.stamp.to_sec(), p.position.x, p.position.y, yaw_of(p.orientation),
                    m.twist.twist.linear.x, m.twist.twist.angular.z])


def on_imu(m):
    g, a = m.angular_velocity, m.linear_acceleration
    record('imu', [m.header.stamp.to_sec(), g.x, g.y, g.z, a.x, a.y, a.z, yaw_of(m.orientation)])


def on_joints(m):
    pos = dict(zip(m.name, m.position))
    record('joints', [m.header.stamp.to_sec(), pos['HeadYaw'], pos['WheelFL'], pos['WheelFR'], pos['WheelB']])


def on_laser(m):
    record('laser', [m.header.stamp.to_sec(), [round(r, 4) for r in m.ranges]])


def on_sonar(m):
    record('sonar', [m.header.stamp.to_sec(), m.range])


def on_camera(m):
    img = np.frombuffer(m.data, np.uint8).reshape(m.height, m.width, 3)
    profile = img[: int(m.height * 0.4)].mean(axis=(0, 2))
    record('camera', [m.header.stamp.to_sec(), [round(float(v), 2) for v in profile]])


def on_diagnostics(m):
    for s in m.status:
        if s.name == 'naoqi_driver_joints:HeadYaw':
            LAST['stiffness'] = dict((kv.key, kv.value) for kv in s.values)['Stiffness']


def main():
    p = argparse.ArgumentParser()
    p.add_argument('--ns', default='/naoqi_driver')
    p.add_argument('--head', type=float, default=0.3)
    p.add_argument('--turn', type=float, default=0.5)
    p.add_argument('--spin', type=float, default=0.3)
    args = p.parse_args(rospy.myargv(sys.argv)[1:])
    rospy.init_node('emu_move', anonymous=True, disable_signals=True)
    ns = args.ns
    for topic, cls, cb in ((ns + '/odom', Odometry, on_odom), (ns + '/imu/base', Imu, on_imu),
                           ('/joint_states', JointState, on_joints), (ns + '/laser', LaserScan, on_laser),
                           (ns + '/sonar/front', Range, on_sonar),
                           (ns + '/camera/front/image_raw', Image, on_camera),
                           ('/diagnostics', DiagnosticArray, on_diagnostics)):
        rospy.Subscriber(topic, cls, cb, queue_size=20)
    joint_angles = rospy.Publisher('/joint_angles', joint_angles_class(), queue_size=10)
    goal = rospy.Publisher('/move_base_simple/goal', PoseStamped, queue_size=10)
    cmd_vel = rospy.Publisher('/cmd_vel', Twist, queue_size=10)
    deadline = time.monotonic() + 30
    while not (all(x.get_num_connections() for x in (joint_angles, goal, cmd_vel)) and 'odom' in LAST):
        if time.monotonic() > deadline:
            print(json.dumps({'error': 'the emulator did not connect'}))
            return 1
        time.sleep(0.05)
    T0[0] = time.monotonic()

    def at(t):
        time.sleep(max(0.0, T0[0] + t - time.monotonic()))

    at(SCHEDULE['head'])
    joint_angles.publish(joint_angles_class()(joint_names=['HeadYaw'], joint_angles=[args.head],
                                              speed=0.2, relative=0))
    at(SCHEDULE['goal'])
    g = PoseStamped()
    g.header.frame_id = 'base_footprint'
    g.pose.orientation.z, g.pose.orientation.w = math.sin(args.turn / 2), math.cos(args.turn / 2)
    goal.publish(g)
    at(SCHEDULE['spin'])
    spin = Twist()
    spin.angular.z = args.spin
    cmd_vel.publish(spin)
    at(SCHEDULE['stop'])
    cmd_vel.publish(Twist())
    at(SCHEDULE['end'])
    with LOCK:
        out = dict(DATA, stiffness=LAST.get('stiffness'), schedule=SCHEDULE)
        T0[0] = None
    print(json.dumps(out))
    return 0


if __name__ == '__main__':
    sys.exit(main())
