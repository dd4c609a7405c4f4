#!/usr/bin/env python3
"""Test helper: run sensors/audio.py's LevelMonitor on a real microphone topic.

usage: media_level_probe.py TOPIC SECONDS LOUD_FILE
Listens for SECONDS, then reads the time.monotonic() at which media_publisher.py turned loud
from LOUD_FILE and prints JSON: heard() over the 2 s after the switch ("loud") and over a
quiet stretch before it ("quiet"), and has_baseline() at the end.
"""
import json
import sys
import time

import rospy

from pepper_interface_tests.sensors.audio import LevelMonitor


def main():
    topic, seconds, loud_file = sys.argv[1], float(sys.argv[2]), sys.argv[3]
    rospy.init_node('level_probe', anonymous=True, disable_signals=True)
    monitor = LevelMonitor(topic).start()
    time.sleep(seconds)
    monitor.stop()
    with open(loud_file) as f:
        loud_at = float(f.read())
    print(json.dumps({'loud': monitor.heard(loud_at, loud_at + 2.0),
                      'quiet': monitor.heard(loud_at - 1.2, loud_at - 0.1),
                      'has_baseline': monitor.has_baseline(),
                      'levels': len(monitor._levels)}), flush=True)
    rospy.signal_shutdown('done')


if __name__ == '__main__':
    main()
