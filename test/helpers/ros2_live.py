"""Test helper, a process of its own: naoqi_driver2-shaped streams published live over rclpy.

The messages are those of ros2_recordings.records() (the data the ROS 1 bag and the ROS 2
recordings of the same test hold), published at their record times from now on, restamped
with the wall clock, on naoqi_driver2's names, with naoqi_driver2's QoS (reliable, keep-last 10;
the sonars keep-last 1: its src/publishers/basic.hpp:72 and sonar.cpp:53).

    python ros2_live.py [--faulty] [--fork] [--seconds S] [--leave-out a,b]
Prints "publishing" once every publisher exists; ends after S seconds or on SIGTERM/SIGINT.
"""
import argparse
import os
import signal
import sys
import time

import genpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ros2_recordings as rec  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--faulty', action='store_true')
    ap.add_argument('--fork', action='store_true')
    ap.add_argument('--seconds', type=float, default=6.0)
    ap.add_argument('--leave-out', default='')
    ap.add_argument('--wait', type=float, default=30.0, help='s to wait for every topic to have a subscriber')
    a = ap.parse_args()
    import rclpy

    from pepper_interface_tests.sources.ros2wire import RawPublisher
    rclpy.init()
    node = rclpy.create_node('naoqi_driver')
    stop = []
    signal.signal(signal.SIGTERM, lambda *_: stop.append(1))
    leave = tuple(s for s in a.leave_out.split(',') if s)
    recs = rec.records(faulty=a.faulty, fork=a.fork, seconds=a.seconds, leave_out=leave)
    pubs = {}
    for r in recs:
        if r.sensor not in pubs:
            depth = 1 if 'Sonar' in r.sensor else 10
            pubs[r.sensor] = RawPublisher(node, rec.TOPICS[r.sensor][1], r.msg._type, depth)
    # naoqi_driver2 converts and publishes a stream only while it has a subscriber: the timeline
    # (and its faults, e.g. the odometry's jump after 20 messages) starts once all have one
    deadline = time.monotonic() + a.wait
    print('publishing', flush=True)
    while time.monotonic() < deadline and not stop and \
            not all(p.get_num_connections() > 0 for p in pubs.values()):
        time.sleep(0.05)
    start = time.monotonic()
    try:
        for r in recs:
            delay = start + (r.t - rec.T0) - time.monotonic()
            if delay > 0:
                time.sleep(delay)
            if stop:
                break
            if hasattr(r.msg, 'header'):
                r.msg.header.stamp = genpy.Time.from_sec(time.time())
            pubs[r.sensor].publish(r.msg)
    except KeyboardInterrupt:
        pass
    node.destroy_node()
    rclpy.try_shutdown()


if __name__ == '__main__':
    main()
