#!/usr/bin/env python3
"""Test helper: a real libqi client asks the fake NAOqi (pepperFakeNaoqi at --url) what
naoqi_driver asks it, with the driver's own arguments, and prints the answers as one JSON line.
It also registers a touch subscriber service as the driver does (touch.cpp:94-97) and takes the
subscriber object naoqi_driver2 takes (ALMemory.subscriber), and records the events each receives
for --seconds."""
import argparse
import json
import os
import sys
import time

import qi

LASER = 'Device/SubDeviceList/Platform/LaserSensor/%s/Horizontal/Seg%02d/%s/Sensor/Value'
SONAR = 'Device/SubDeviceList/Platform/%s/Sonar/Sensor/Value'


class Touch:
    def __init__(self):
        self.events = []

    def touchCallback(self, key, value, message):
        self.events.append([key, value])


def main():
    p = argparse.ArgumentParser()
    p.add_argument('--url', required=True)
    p.add_argument('--seconds', type=float, default=0.0)
    p.add_argument('--move', action='store_true',
                   help='also command a turn and a head yaw, as the driver\'s subscribers do')
    p.add_argument('--audio-relay', action='store_true',
                   help='take three buffers from FakeAudioFrames as audio_relay.cpp does')
    a = p.parse_args()
    s = qi.Session()
    s.connect(a.url)
    mem, motion, video = s.service('ALMemory'), s.service('ALMotion'), s.service('ALVideoDevice')
    out = {}
    out['type'] = mem.getData('RobotConfig/Body/Type')
    out['sonar'] = [mem.getListData([SONAR % 'Front', SONAR % 'Back']) for _ in range(3)]
    keys = [LASER % (b, i, c) for b in ('Right', 'Front', 'Left') for i in range(1, 16) for c in 'XY']
    out['laser'] = []
    for _ in range(3):
        out['laser'].append(mem.getListData(keys))
        time.sleep(0.15)
    joints = motion.getBodyNames('JointActuators')
    diag = [k for j in joints for k in ('Device/SubDeviceList/%s/Temperature/Sensor/Value' % j,
                                       'Device/SubDeviceList/%s/Hardness/Actuator/Value' % j)]
    diag += ['BatteryChargeChanged', 'BatteryPowerPluggedChanged', 'BatteryFullChargedFlagChanged',
             'Device/SubDeviceList/Battery/Current/Sensor/Value']
    out['joints'] = joints
    out['diag'] = mem.getListData(diag)
    out['limits'] = motion.getLimits(joints[0])
    out['angles'] = motion.getAngles('Body', True)
    out['position'] = motion.getPosition('Torso', 1, True)
    out['velocity'] = motion.getRobotVelocity()
    out['sensor_names'] = motion.getSensorNames()
    out['config'] = motion.getRobotConfig()
    try:
        out['velocity_key'] = mem.getData('Motion/Velocity/Sensor/WheelFL')
    except RuntimeError as e:
        out['velocity_key'] = 'raised: ' + str(e).splitlines()[0]
    out['imu'] = mem.getListData(['DCM/Time'] + ['Device/SubDeviceList/InertialSensorBase/%s/Sensor/Value' % n
                                                 for n in ('AngleX', 'AngleY', 'AngleZ', 'GyroscopeX',
                                                           'GyroscopeY', 'GyroscopeZ', 'AccelerometerX',
                                                           'AccelerometerY', 'AccelerometerZ')])
    out['images'] = {}
    for name, cam, res, cs in (('front', 0, 1, 11), ('depth', 2, 9, 17), ('xtion', 2, 1, 23),
                               ('ir', 2, 1, 20), ('stereo', 3, 15, 11)):
        h = video.subscribeCamera(name, cam, res, cs, 10)
        try:
            img = video.getImageRemote(h)
            out['images'][name] = [list(img[:6]), type(img[6]).__name__, len(img[6])] + list(img[7:])
        except RuntimeError as e:
            out['images'][name] = 'raised: ' + str(e).splitlines()[0]
        video.unsubscribe(h)
    if a.move:      # moveto.cpp:49-129 and teleop.cpp:55-65 call these
        out['before'] = [motion.getPosition('Torso', 1, True), motion.getAngles('Body', True)]
        motion.moveTo(0.0, 0.0, -0.5)     # right: the idle circle turns left
        motion.setAngles(['HeadYaw'], [0.4], 0.2)
        time.sleep(3.0)
        out['after'] = [motion.getPosition('Torso', 1, True), motion.getAngles('Body', True)]
    out['version'] = s.service('ALSystem').systemVersion()
    out['mic'] = s.service('ALRobotModel')._getMicrophoneConfig()
    touch = Touch()
    s.registerService('ROS-Driver-FrontTactilTouched', touch)
    mem.subscribeToEvent('FrontTactilTouched', 'ROS-Driver-FrontTactilTouched', 'touchCallback')
    # naoqi_driver2's way (src/event/touch.cpp:91-92): ALMemory.subscriber(key), its "signal"
    signalled = []
    subscriber = mem.subscriber('FrontTactilTouched')
    subscriber.signal.connect(lambda v: signalled.append(['FrontTactilTouched', v]))
    time.sleep(a.seconds)
    out['touch'] = touch.events
    out['touch_signal'] = signalled
    services = [i['name'] for i in s.services()]
    out['audio_services'] = [n for n in ('ALAudioDevice', 'FakeAudioFrames') if n in services]
    if a.audio_relay:     # what audio_relay.cpp asks, with the driver's preferences (audio.cpp:107-114)
        frames = s.service('FakeAudioFrames')
        frames.setClientPreferences('ROS-Driver-Audio', 48000, 0, False)
        frames.subscribe('ROS-Driver-Audio')
        got = [frames.next_buffer('ROS-Driver-Audio') for _ in range(4)]
        out['buffers'] = [[b[0], b[1], b[2] + b[3] * 1e-6, type(b[4]).__name__, len(b[4])] for b in got]
        frames.unsubscribe('ROS-Driver-Audio')
        try:
            frames.next_buffer('ROS-Driver-Audio')
            out['after_unsubscribe'] = 'answered'
        except RuntimeError as e:
            out['after_unsubscribe'] = 'raised: ' + str(e).splitlines()[0]
    sys.stdout.write(json.dumps(out) + '\n')
    sys.stdout.flush()
    os._exit(0)


if __name__ == '__main__':
    main()
