#!/usr/bin/env python3
"""Test helper: what a robot receives from sensorTest --move, recorded by a real rospy node in a
process of its own (so it outlives sensorTest and sees what really went out on the wire).

Usage: motion_recorder.py OUT.jsonl

Subscribes to naoqi_driver's three command topics (/cmd_vel, /move_base_simple/goal,
/joint_angles: src/naoqi_driver.cpp:937-938) and appends one JSON line per message to OUT:
{"t": receive time, "topic": ..., ...the command's numbers}. Prints "recorder up" once subscribed.
"""
import json
import math
import sys
import threading

import rospy
from geometry_msgs.msg import PoseStamped, Twist

from pepper_interface_tests.msg import JointAnglesWithSpeed

LOCK = threading.Lock()


def main():
    out = open(sys.argv[1], 'a')

    def write(row):
        row['t'] = rospy.get_time()
        with LOCK:
            out.write(json.dumps(row) + '\n')
            out.flush()

    def twist(m):
        write({'topic': '/cmd_vel', 'vx': m.linear.x, 'vy': m.linear.y, 'vth': m.angular.z})

    def goal(m):
        q = m.pose.orientation
        yaw = math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))
        write({'topic': '/move_base_simple/goal', 'frame': m.header.frame_id,
               'x': m.pose.position.x, 'y': m.pose.position.y, 'yaw': yaw})

    def joints(m):
        write({'topic': '/joint_angles', 'names': list(m.joint_names),
               'angles': list(m.joint_angles), 'speed': m.speed, 'relative': m.relative})

    rospy.init_node('motion_recorder', anonymous=True, disable_signals=True)
    rospy.Subscriber('/cmd_vel', Twist, twist, queue_size=50)
    rospy.Subscriber('/move_base_simple/goal', PoseStamped, goal, queue_size=50)
    rospy.Subscriber('/joint_angles', JointAnglesWithSpeed, joints, queue_size=50)
    print('recorder up', flush=True)
    try:
        rospy.spin()
    except KeyboardInterrupt:
        pass


if __name__ == '__main__':
    main()
