#!/usr/bin/env python3
"""Measure the emulator: CPU use (psutil) and the rate of every topic with all of them subscribed.

Usage: python test/nodes/emu_measure.py [--seconds 20] [--profile robot|robot-stock|simulator] [--no-realsense]
       [--resolution QVGA]

Starts its own roscore on a free port, the emulator (robot profile: audio direct, RealSense on
unless --no-realsense), and emu_listen.py on every topic; samples the emulator's CPU time over
the listening window and prints a table (used for docs/emulator.md).
"""
import argparse
import json
import os
import subprocess
import sys
import time

import psutil

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), 'helpers'))   # test/helpers/
from rosmaster import Master, kill_group, script, spawn  # noqa: E402

ROBOT_TOPICS = ['/naoqi_driver/sonar/back', '/naoqi_driver/sonar/front',
                '/naoqi_driver/camera/front/image_raw', '/naoqi_driver/camera/bottom/image_raw',
                '/naoqi_driver/camera/depth/image_raw', '/naoqi_driver/camera/stereo/image_raw',
                '/naoqi_driver/laser', '/naoqi_driver/audio', '/joint_states',
                '/naoqi_driver/odom', '/naoqi_driver/imu/base', '/naoqi_driver/imu/torso']
REALSENSE_TOPICS = ['/camera/color/image_raw', '/camera/aligned_depth_to_color/image_raw']
SIMULATOR_TOPICS = ['/pepper/sonar_back', '/pepper/sonar_front', '/pepper/camera/front/image_raw',
                    '/pepper/camera/bottom/image_raw', '/pepper/camera/depth/image_raw',
                    '/pepper/laser_2', '/joint_states', '/pepper/odom']


def main():
    p = argparse.ArgumentParser()
    p.add_argument('--seconds', type=float, default=20.0)
    p.add_argument('--profile', default='robot')
    p.add_argument('--no-realsense', action='store_true')
    p.add_argument('--resolution', default='QVGA')
    a = p.parse_args()
    with Master() as m:
        env = m.env()
        cmd = script('pepperEmulator') + ['_profile:=' + a.profile,
                                          '_camera_resolution:=' + a.resolution]
        if a.profile != 'simulator':          # robot or robot-stock
            cmd += ['_audio:=direct', '_realsense:=%s' % ('false' if a.no_realsense else 'true')]
            topics = ROBOT_TOPICS + ([] if a.no_realsense else REALSENSE_TOPICS)
        else:
            topics = SIMULATOR_TOPICS
        emu = spawn(cmd, env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            listen = subprocess.Popen([sys.executable, os.path.join(HERE, 'emu_listen.py'),
                                       '--duration', str(a.seconds)] + topics, env=env,
                                      stdout=subprocess.PIPE)
            proc = psutil.Process(emu.pid)
            time.sleep(4.0)                     # subscriptions settle
            c0, w0 = proc.cpu_times(), time.time()
            time.sleep(max(1.0, a.seconds - 5.0))
            c1, w1 = proc.cpu_times(), time.time()
            out = json.loads(listen.communicate(timeout=a.seconds + 60)[0])
        finally:
            kill_group(emu)
    cpu = (c1.user + c1.system - c0.user - c0.system) / (w1 - w0)
    print('emulator CPU: %.0f%% of one core (user+system over %.0f s, %d cores, load %s)'
          % (100 * cpu, w1 - w0, psutil.cpu_count(), ' '.join('%.2f' % x for x in os.getloadavg())))
    print('%-45s %-36s %7s %8s' % ('topic', 'type', 'count', 'rate Hz'))
    for topic in topics:
        s = out.get(topic)
        if s is None:
            print('%-45s MISSING' % topic)
            continue
        print('%-45s %-36s %7d %8.2f' % (topic, s['type'], s['count'], s.get('rate', 0.0)))


if __name__ == '__main__':
    main()
