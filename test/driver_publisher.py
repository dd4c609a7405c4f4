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
               of TONES[name]; faults: dead:<name> (that microphone all zeros)
  clock        sets /use_sim_time true and publishes rosgraph_msgs/Clock about every 5 ms:
               100 s + --rtf x wall seconds since start
Rates are kept with rospy.Rate, i.e. on the simulation clock when /use_sim_time is true, as
the simulator's publishers do.
"""
import argparse
import math
import sys
import time

import numpy as np
import rospy

from pepper_interface_tests.sources.naoqi_msgs import CHANNEL_NAMES, audio_buffer_class

TONES = {'rearLeft': 500.0, 'rearRight': 1000.0, 'frontLeft': 1500.0, 'frontRight': 2500.0}
BLIND = list(range(15, 23)) + list(range(38, 46))


def sonar(a, i):
    from sensor_msgs.msg import Range
    sim = a.kind == 'sim_sonar'
    m = Range(radiation_type=Range.ULTRASOUND, field_of_view=1.05 if sim else 0.523598776,
              min_range=0.0 if sim else 0.25, max_range=5.0 if sim else 2.55)
    m.range = float('nan') if a.fault == 'nan' else (1.5 + 0.05 * math.sin(i) if sim else 4.0 + 0.01 * (i % 3))
    m.header.frame_id = 'SonarFront_frame'
    return m


def laser(a, i):
    from sensor_msgs.msg import LaserScan
    m = LaserScan(angle_min=-2.0944, angle_max=2.0944, range_min=0.1, range_max=3.0, scan_time=0.1)
    m.angle_increment = (2 * 2.0944) / 61
    # raw distances carry measurement noise from scan to scan (a stuck rule relies on it)
    m.ranges = [-1.0 if (k in BLIND or a.fault == 'all_blind') else
                5.0 + 0.01 * (k % 5) + 0.003 * math.sin(1.7 * i + k) for k in range(61)]
    m.header.frame_id = 'base_footprint'
    return m


def sim_laser(a, i):
    from sensor_msgs.msg import LaserScan
    n = 61 * 8
    half = math.radians(120.0)
    m = LaserScan(angle_min=-half, angle_max=half, angle_increment=2 * half / n,
                  range_min=0.1, range_max=7.0)
    r = [float('nan')] * n
    if a.fault != 'no_returns':
        for k in range(200, 240):
            # the model's Gaussian noise (sd 0.01 m, pepperGazeboCPU.xacro) per scan
            r[k] = 2.0 + 0.01 * (k % 7) + 0.005 * math.sin(1.7 * i + k)
    m.ranges = r
    m.header.frame_id = 'base_footprint'
    return m


def imu(a, i):
    from geometry_msgs.msg import Quaternion
    from sensor_msgs.msg import Imu
    m = Imu()
    m.orientation = Quaternion(*([float('nan')] * 4 if a.fault == 'nan_attitude' else (0, 0, 0, 1.0)))
    # the inertial board's raw values carry noise from message to message
    m.angular_velocity.z = 0.01 + 0.001 * math.sin(1.3 * i)
    m.linear_acceleration.z = 9.81 + 0.01 * math.sin(0.7 * i)
    for cov in (m.orientation_covariance, m.angular_velocity_covariance, m.linear_acceleration_covariance):
        cov[0] = -1.0
    m.header.frame_id = 'base_footprint'
    return m


def audio_buffer(a, i):
    cmap = [int(c) for c in a.channel_map.split(',')]
    dead = a.fault.split(':', 1)[1] if a.fault.startswith('dead:') else None
    t = (np.arange(a.samples) + i * a.samples) / 48000.0
    cols = []
    for code in cmap:
        name = CHANNEL_NAMES[code]
        x = np.zeros(a.samples) if name == dead else 3000 * np.sin(2 * np.pi * TONES[name] * t)
        cols.append(x.astype(np.int16))
    m = audio_buffer_class()()
    m.frequency = 48000
    m.channelMap = bytes(cmap)
    m.data = np.stack(cols, axis=1).reshape(-1).tolist()
    return m


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
