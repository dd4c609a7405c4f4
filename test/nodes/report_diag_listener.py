#!/usr/bin/env python3
"""Test helper: a real rospy subscriber to /diagnostics; prints every DiagnosticArray as one
JSON line {"t": receive time, "status": [{name, level, message, hardware_id, values}]}.

usage: report_diag_listener.py [TOPIC]   (default /diagnostics; prints "listening" when subscribed)
"""
import json
import sys
import time

import rospy
from diagnostic_msgs.msg import DiagnosticArray


def main():
    topic = (rospy.myargv(sys.argv)[1:] or ['/diagnostics'])[0]
    rospy.init_node('diag_listener', anonymous=True)

    def callback(msg):
        print(json.dumps({'t': time.time(), 'stamp': msg.header.stamp.to_sec(), 'status': [
            {'name': s.name, 'level': s.level if isinstance(s.level, int) else ord(s.level),
             'message': s.message, 'hardware_id': s.hardware_id,
             'values': {kv.key: kv.value for kv in s.values}} for s in msg.status]}), flush=True)

    rospy.Subscriber(topic, DiagnosticArray, callback, queue_size=50)
    print('listening', flush=True)
    rospy.spin()


if __name__ == '__main__':
    main()
