#!/usr/bin/env python3
"""Test helper: a transform tree on TOPIC as naoqi_driver's (odom -> base_link -> base_footprint,
joint_state.cpp:162-185), 50 Hz, each message stamped when it is made, OFFSET s added (a driver
clock behind: negative), delivered steadily, or with --bursts as a starved reader's backlog
builds and drains: in each 3.6 s, 2.8 s handing one message on every 100 ms (a fifth of the
pace: the delay grows to 2.2 s), then the whole backlog at once, then steadily. No pause is
longer than 100 ms. A real rospy node.

Usage: bursty_tf.py TOPIC OFFSET [--bursts]
Prints "tf up".
"""
import sys
import time

import rospy
from geometry_msgs.msg import TransformStamped
from tf2_msgs.msg import TFMessage

PERIOD = 0.02                  # s between two messages made (50 Hz)
CYCLE, SLOW = 3.6, 2.8          # s: a cycle, and its first part at the slow pace
SLOW_GAP = 0.1


def tree(stamp):
    out = []
    for parent, child, z in (('odom', 'base_link', 0.0), ('base_link', 'base_footprint', -0.82)):
        t = TransformStamped()
        t.header.stamp, t.header.frame_id, t.child_frame_id = stamp, parent, child
        t.transform.translation.z, t.transform.rotation.w = z, 1.0
        out.append(t)
    return TFMessage(transforms=out)


def main():
    topic, offset, bursts = sys.argv[1], float(sys.argv[2]), '--bursts' in sys.argv
    rospy.init_node('bursty_tf', anonymous=True, disable_signals=True)
    pub = rospy.Publisher(topic, TFMessage, queue_size=500)
    print('tf up', flush=True)
    start, queue, n, sent_at = time.time(), [], 0, 0.0
    try:
        while not rospy.is_shutdown():
            now = time.time()
            while start + n * PERIOD <= now:        # made on time, stamped when made
                queue.append(tree(rospy.Time.from_sec(start + n * PERIOD + offset)))
                n += 1
            gap = SLOW_GAP if bursts and (now - start) % CYCLE < SLOW else 0.0
            while queue and now - sent_at >= gap:
                pub.publish(queue.pop(0))
                sent_at = now
                if gap:
                    break
            time.sleep(0.002)
    except KeyboardInterrupt:
        pass


if __name__ == '__main__':
    main()
