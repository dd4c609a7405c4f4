#!/usr/bin/env python3
"""Test helper: publish what the real drivers publish (read from their source), healthy or
with one real fault, on a topic; or publish /clock at a real-time factor.

usage: driver_publisher.py KIND TOPIC [--rate HZ] [--fault NAME] [--node NAME]
                           [--channel-map 3,5,0,2] [--samples N] [--rtf R]
KIND
  sonar        naoqi_driver sonar (converters/sonar.cpp): advertises 0.25-2.55 m, fov 0.5236,
               range = raw distance, 4 m (nothing in front); faults: nan
  laser        naoqi_driver laser (converters/laser.cpp): 61 slots, -1.0 in 15-22 and 38-45,
               raw distances of 5 m (a wide room), range_max 3.0; faults: all_blind
  sim_laser    pepper_virtual laser_publisher.py /pepper/laser_2: 488 slots over +-120 deg,
               NaN except 40 returns; faults: no_returns (all NaN)
  sim_sonar    Gazebo sonar: min 0, max 5, fov 1.05, 1.5 m + noise
  imu          naoqi_driver IMU (converters/imu.cpp): covariance[0] = -1 x 3, gravity in the
               accelerometer; faults: nan_attitude
  audio_buffer stock naoqi_driver audio (event/audio.cpp): naoqi_bridge_msgs/AudioBuffer
               built from its definition (naoqi_msgs.py), interleaved, frequency 48000,
               --channel-map codes (default 3,5,0,2); channel named by code c carries a tone
               of fake_pepper.MIC_TONES[name]; faults: dead:<name> (that microphone all zeros)
  clock        sets /use_sim_time true and publishes rosgraph_msgs/Clock about every 5 ms:
               100 s + --rtf x wall seconds since start
Rates are kept with rospy.Rate, i.e. on the simulation clock when /use_sim_time is true, as
the simulator's publishers do.
"""
import argparse
import math
import os
import sys
import time

import rospy

# the test helpers (test/helpers/, beside this script's folder test/nodes/)
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), 'helpers'))
import fake_pepper as fake  # noqa: E402
from pepper_interface_tests.emulator import profiles


def sonar(a, i):
    sim = a.kind == 'sim_sonar'
    # Gazebo: 1.5 m + noise; naoqi_driver: the raw distance, 4 m when nothing is in front
    distance = 1.5 + 0.05 * math.sin(i) if sim else 4.0 + 0.01 * (i % 3)
    return fake.sonar(i, platform='simulator' if sim else 'robot', sensor='frontSonar',
                      range=float('nan') if a.fault == 'nan' else distance)


def laser(a, i):
    # raw distances of 5 m carry measurement noise from scan to scan (a stuck rule relies on it)
    return fake.laser(i, distance=5.0, swing=0.01,
                      blind=range(profiles.LASER_BEAMS) if a.fault == 'all_blind' else fake.BLIND)


def sim_laser(a, i):
    return fake.sim_laser(i, returns=() if a.fault == 'no_returns' else range(200, 240), distance=2.0)


def imu(a, i):
    m = fake.imu(i, orientation=(float('nan'),) * 4 if a.fault == 'nan_attitude' else (0, 0, 0, 1.0),
                 covariance=fake.UNKNOWN_COVARIANCE)
    return m


def audio_buffer(a, i):
    dead = a.fault.split(':', 1)[1] if a.fault.startswith('dead:') else None
    return fake.stock_audio_buffer(i, cmap=[int(c) for c in a.channel_map.split(',')], dead=dead,
                                   samples=a.samples)


MAKERS = {'sonar': sonar, 'sim_sonar': sonar, 'laser': laser, 'sim_laser': sim_laser, 'imu': imu,
          'audio_buffer': audio_buffer}


def publish_clock(a):
    from rosgraph_msgs.msg import Clock
    rospy.set_param('/use_sim_time', True)
    rospy.init_node(a.node, anonymous=True)
    pub = rospy.Publisher('/clock', Clock, queue_size=10)
    start = time.monotonic()
    print('clock', flush=True)
    while not rospy.is_shutdown():   # sim time follows wall time x rtf, however late the loop
        pub.publish(Clock(clock=rospy.Time.from_sec(100.0 + a.rtf * (time.monotonic() - start))))
        time.sleep(0.005)


def main():
    p = argparse.ArgumentParser()
    p.add_argument('kind', choices=sorted(MAKERS) + ['clock'])
    p.add_argument('topic')
    p.add_argument('--rate', type=float, default=10.0)
    p.add_argument('--fault', default='')
    p.add_argument('--node', default='driver_publisher')
    p.add_argument('--channel-map', default='3,5,0,2')
    p.add_argument('--samples', type=int, default=8192)
    p.add_argument('--rtf', type=float, default=1.0)
    a = p.parse_args(rospy.myargv(sys.argv)[1:])
    if a.kind == 'clock':
        return publish_clock(a)
    rospy.init_node(a.node)
    first = MAKERS[a.kind](a, 0)
    pub = rospy.Publisher(a.topic, type(first), queue_size=10)
    rate = rospy.Rate(a.rate)
    i = 0
    print('publishing', flush=True)
    while not rospy.is_shutdown():
        m = MAKERS[a.kind](a, i)
        if hasattr(m, 'header'):
            m.header.stamp = rospy.Time.now()
        pub.publish(m)
        i += 1
        try:
            rate.sleep()
        except rospy.ROSTimeMovedBackwardsException:
            pass


if __name__ == '__main__':
    main()
