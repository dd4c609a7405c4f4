#!/usr/bin/env python3
"""Test helper: the motion witnesses naoqi_driver stamps at sampling (joint states, odometry,
IMU), published in bursts: each message stamped when it is sampled (as joint_state.cpp:94,
odom.cpp:58, imu.cpp:103 stamp right after fetching the values), those sampled during a hold
published together when it ends (a busy PC handing them over late). A real rospy node.

The robot turns 0.5 rad between s = 1 and s = 2 (s: seconds since the start), yaw
0.25 (1 - cos(pi (s - 1))), gyro z its derivative; HeadYaw follows the same curve, the three
wheels 6 times it. Samples at 50 Hz; those of HOLD are published at its end.

Usage: bursty_witnesses.py PREFIX OFFSET  (OFFSET: s added to every stamp: a driver's clock)
Prints "witnesses up", then "start <wall time of s = 0>" and "done".
"""
import math
import sys
import time

import rospy
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, JointState

HOLD = (1.5, 2.3)       # s: sampled then, published at its end
END, PERIOD = 3.5, 0.02
WHEELS = ('WheelFL', 'WheelFR', 'WheelB')


def yaw(s):
    return 0.0 if s < 1 else 0.5 if s > 2 else 0.25 * (1 - math.cos(math.pi * (s - 1)))


def rate(s):
    return 0.25 * math.pi * math.sin(math.pi * (s - 1)) if 1 <= s <= 2 else 0.0


def sample(s, stamp):
    j = JointState(name=['HeadYaw'] + list(WHEELS), position=[yaw(s)] + [6 * yaw(s)] * 3)
    o = Odometry()
    o.pose.pose.orientation.z, o.pose.pose.orientation.w = math.sin(yaw(s) / 2), math.cos(yaw(s) / 2)
    i = Imu()
    i.angular_velocity.z = rate(s)
    for m in (j, o, i):
        m.header.stamp = stamp
    return j, o, i


def main():
    prefix, offset = sys.argv[1], float(sys.argv[2])
    rospy.init_node('bursty_witnesses', anonymous=True, disable_signals=True)
    pubs = [rospy.Publisher(prefix + t, c, queue_size=200) for t, c in
            (('/joint_states', JointState), ('/odom', Odometry), ('/imu', Imu))]
    print('witnesses up', flush=True)
    while any(p.get_num_connections() == 0 for p in pubs):
        time.sleep(0.02)
    time.sleep(1.0)
    start = time.time()
    print('start %.6f' % start, flush=True)
    held = []
    n = 0
    while n * PERIOD <= END:
        time.sleep(max(0.0, start + n * PERIOD - time.time()))
        now = time.time()
        s = now - start         # the values of when it is sampled (a loaded PC wakes late)
        msgs = sample(s, rospy.Time.from_sec(now + offset))
        if HOLD[0] <= s < HOLD[1]:
            held.append(msgs)
        else:
            for m in held + [msgs]:
                for p, x in zip(pubs, m):
                    p.publish(x)
            held = []
        n += 1
    time.sleep(0.5)
    print('done', flush=True)


if __name__ == '__main__':
    main()
