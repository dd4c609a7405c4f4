"""Test helper, a process of its own: what a robot receives from sensorTest --move on ROS 2,
recorded by a plain rclpy node with naoqi_driver2's three subscriptions (/cmd_vel,
/joint_angles: src/subscribers/teleop.cpp:38-46; /move_base_simple/goal: moveto.cpp:45; all
depth 10, reliable). One JSON line per message, as test/nodes/motion_recorder.py writes on ROS 1.

    python ros2_motion_recorder.py OUT.jsonl      (prints "recorder up" once subscribed)
"""
import json
import math
import sys
import threading
import time

from ros2_spin import spin_until_sigterm


def main():
    import rclpy
    from geometry_msgs.msg import PoseStamped, Twist
    from naoqi_bridge_msgs.msg import JointAnglesWithSpeed
    out = open(sys.argv[1], 'a')
    lock = threading.Lock()

    def write(row):
        row['t'] = time.time()
        with lock:
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
               'angles': [float(a) for a in m.joint_angles], 'speed': m.speed, 'relative': m.relative})

    rclpy.init()
    node = rclpy.create_node('motion_recorder')
    node.create_subscription(Twist, '/cmd_vel', twist, 10)
    node.create_subscription(PoseStamped, '/move_base_simple/goal', goal, 10)
    node.create_subscription(JointAnglesWithSpeed, '/joint_angles', joints, 10)
    spin_until_sigterm(rclpy, node, 'recorder up')


if __name__ == '__main__':
    main()
