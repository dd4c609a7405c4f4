#!/usr/bin/env python3
"""Test helper: the motion check's live witnesses (motion/witnesses.Witnesses, real rospy
subscriptions) on PREFIX's joint states, odometry and IMU, on the wall clock; on SIGINT writes
what they recorded to OUT as JSON: per witness each message's (stamp, handled at), and the
recording's placed series (joints' HeadYaw, odometry yaw, gyro z).

Usage: witness_listener.py PREFIX OUT
"""
import json
import sys
import time

import rospy

from pepper_interface_tests.motion.record import Recording
from pepper_interface_tests.motion.witnesses import Witnesses


class Logged(Witnesses):
    def handle(self, role, msg, t):
        self.log.setdefault(role, []).append((msg.header.stamp.to_sec(), t))
        super().handle(role, msg, t)


def main():
    prefix, out = sys.argv[1], sys.argv[2]
    rospy.init_node('witness_listener', anonymous=True, disable_signals=True)
    rec = Recording()
    topics = {'jointState': prefix + '/joint_states', 'odometry': prefix + '/odom', 'imu': prefix + '/imu'}
    Logged.log = {}
    w = Logged(topics, rec, clock=time.time)
    print('listener up', flush=True)
    try:
        while True:
            time.sleep(0.1)
    except KeyboardInterrupt:
        pass
    w.close()
    with rec.lock:
        data = {'log': Logged.log, 'joints': [(t, p['HeadYaw']) for t, p in rec.joints],
                'odom': rec.odom_yaw, 'gyro': [(g[0], g[3]) for g in rec.gyro], 'behind': getattr(rec, 'behind', None)}
    with open(out, 'w') as f:
        json.dump(data, f)
    print('written', flush=True)


if __name__ == '__main__':
    main()
