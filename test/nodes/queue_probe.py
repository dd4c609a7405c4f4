#!/usr/bin/env python3
"""Test helper: a subscriber whose callback stalls, as sensorTest's live source subscribes.

usage: queue_probe.py TOPIC QUEUE_SIZE BUFF_SIZE STALL_S SECONDS
Subscribes TOPIC as rospy.AnyMsg with QUEUE_SIZE and BUFF_SIZE (sources/live.py does the same
with the check's queue_size and buff_size), blocks in the callback of the first message for
STALL_S seconds (a slow disk under the encoder), then counts; after SECONDS prints JSON
{"received": n}.
"""
import json
import sys
import time

import rospy


def main():
    topic, queue_size, buff_size = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    stall, seconds = float(sys.argv[4]), float(sys.argv[5])
    received = [0]

    def callback(_msg):
        received[0] += 1
        if received[0] == 1:
            time.sleep(stall)          # the stall under test

    rospy.init_node('queue_probe', anonymous=True, disable_signals=True)
    rospy.Subscriber(topic, rospy.AnyMsg, callback, queue_size=queue_size, buff_size=buff_size)
    time.sleep(seconds)
    print(json.dumps({'received': received[0]}), flush=True)
    rospy.signal_shutdown('done')


if __name__ == '__main__':
    main()
