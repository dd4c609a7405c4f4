#!/usr/bin/env python3
"""Test helper: subscribe (real rospy) to topics for a while and print what arrived as JSON.

Usage: emu_listen.py --duration S [--wait S] [--speech TEXT --speech-at S] TOPIC [TOPIC ...]

Waits (up to --wait s) until every topic is advertised, subscribes with the advertised type,
listens for --duration s and prints one JSON object {topic: summary}. Each summary holds the
type, message count, receive rate, header facts and a per-type digest of the content (image
hashes, laser beams, quaternion norms, audio levels, ...). Optionally publishes a /speech
message at --speech-at s into the window. Run as a subprocess, one per check: rospy allows one
node per process.
"""
import argparse
import hashlib
import json
import math
import sys
import threading
import time

import numpy as np
import rosgraph
import rospy
import rostopic
from std_msgs.msg import String


def _norm(q):
    return math.sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w)


class Record:
    def __init__(self, topic, type_name):
        self.topic, self.type = topic, type_name
        self.times, self.stamps, self.seqs, self.frames = [], [], [], set()
        self.facts = {}
        self.lists = {}
        self.lock = threading.Lock()

    def add(self, key, value):
        self.lists.setdefault(key, []).append(value)

    def callback(self, msg):
        with self.lock:
            self.times.append(time.time())
            header = getattr(msg, 'header', None)
            if header is not None:
                self.stamps.append(header.stamp.to_sec())
                self.seqs.append(header.seq)
                self.frames.add(header.frame_id)
            getattr(self, 'on_' + self.type.replace('/', '_'), lambda m: None)(msg)

    def on_sensor_msgs_Image(self, m):
        self.facts.update(encoding=m.encoding, width=m.width, height=m.height, step=m.step,
                          data_len=len(m.data), is_bigendian=m.is_bigendian)
        data = bytes(m.data)
        self.add('digest', hashlib.md5(data).hexdigest())
        arr = np.frombuffer(data, np.uint16 if m.encoding in ('16UC1', '32FC1') and
                            len(data) == m.width * m.height * 2 else np.uint8)
        self.add('max', int(arr.max()) if arr.size else 0)
        self.add('zero_share', float(np.mean(arr == 0)) if arr.size else 1.0)
        self.add('mean', float(arr.mean()) if arr.size else 0.0)

    def on_sensor_msgs_LaserScan(self, m):
        r = np.array(m.ranges, dtype=np.float64)
        self.facts.update(n=len(r), angle_min=m.angle_min, angle_max=m.angle_max,
                          angle_increment=m.angle_increment, range_min=m.range_min,
                          range_max=m.range_max)
        blind = r == -1.0
        valid = ~blind & ~np.isnan(r)
        self.add('blind', int(blind.sum()))
        self.add('blind_idx', [int(i) for i in np.flatnonzero(blind)])
        self.add('nan', int(np.isnan(r).sum()))
        self.add('beyond', int(((r[valid] > m.range_max) | (r[valid] < m.range_min)).sum()))
        self.add('digest', hashlib.md5(r.tobytes()).hexdigest())
        if valid.any():
            self.add('valid_min', float(r[valid].min()))
            self.add('valid_max', float(r[valid].max()))

    def on_sensor_msgs_Range(self, m):
        self.facts.update(radiation_type=m.radiation_type, field_of_view=m.field_of_view,
                          min_range=m.min_range, max_range=m.max_range)
        self.add('range', None if math.isnan(m.range) else m.range)

    def on_sensor_msgs_Imu(self, m):
        self.add('qnorm', _norm(m.orientation))
        self.add('acc_z', None if math.isnan(m.linear_acceleration.z) else m.linear_acceleration.z)
        self.add('gyro_z', None if math.isnan(m.angular_velocity.z) else m.angular_velocity.z)
        self.facts.update(covariance0=[m.orientation_covariance[0],
                                       m.angular_velocity_covariance[0],
                                       m.linear_acceleration_covariance[0]])
        self.add('q_nan', any(math.isnan(v) for v in (m.orientation.x, m.orientation.y,
                                                       m.orientation.z, m.orientation.w)))

    def on_nav_msgs_Odometry(self, m):
        self.facts.update(child_frame_id=m.child_frame_id)
        p = m.pose.pose.position
        self.add('qnorm', _norm(m.pose.pose.orientation))
        self.add('x', None if math.isnan(p.x) else p.x)
        self.add('y', p.y)
        self.add('vx', None if math.isnan(m.twist.twist.linear.x) else m.twist.twist.linear.x)
        self.add('wz', m.twist.twist.angular.z)

    def on_sensor_msgs_JointState(self, m):
        self.facts.update(names=list(m.name), n_pos=len(m.position), n_vel=len(m.velocity),
                          n_eff=len(m.effort))
        pos = np.array(m.position, dtype=np.float64)
        self.add('nan', int(np.isnan(pos).sum()))
        self.facts.update(vel_nan=[n for n, v in zip(m.name, m.velocity) if math.isnan(v)],
                          eff_nan=[n for n, v in zip(m.name, m.effort) if math.isnan(v)])
        self.add('max_abs', float(np.nanmax(np.abs(pos))) if pos.size else 0.0)
        self.add('digest', hashlib.md5(pos.tobytes()).hexdigest())

    def on_pepper_interface_tests_AudioCustomMsg(self, m):
        t = self.times[-1]
        levels = []
        for name in ('rearLeft', 'rearRight', 'frontLeft', 'frontRight'):
            a = np.array(getattr(m, name), dtype=np.float64)
            levels.append(float(np.sqrt(np.mean(a * a))) if a.size else -1.0)
            self.facts['len_' + name] = len(a)
        self.add('rms', [t] + levels)

    def on_naoqi_bridge_msgs_AudioBuffer(self, m):
        t = self.times[-1]
        channel_map = list(bytearray(m.channelMap)) if isinstance(m.channelMap, bytes) \
            else list(m.channelMap)
        self.facts.update(frequency=m.frequency, channel_map=channel_map, data_len=len(m.data),
                          md5=m._md5sum)
        a = np.array(m.data, dtype=np.float64)
        n = len(channel_map) or 1
        block = a[:a.size // n * n].reshape(-1, n)          # interleaved: one frame per row
        self.add('rms', [t] + [float(np.sqrt(np.mean(block[:, c] ** 2))) for c in range(n)])

    def on_rosgraph_msgs_Clock(self, m):
        if len(self.times) % 10 == 1:
            self.add('clock', [self.times[-1], m.clock.to_sec()])

    def on_std_msgs_String(self, m):
        self.add('text', m.data)

    def summary(self):
        with self.lock:
            n = len(self.times)
            out = dict(type=self.type, count=n, frames=sorted(self.frames), **self.facts)
            if n >= 2:
                out['rate'] = (n - 1) / (self.times[-1] - self.times[0])
            if len(self.stamps) >= 2 and self.stamps[-1] > self.stamps[0]:
                out['stamp_rate'] = (len(self.stamps) - 1) / (self.stamps[-1] - self.stamps[0])
            if self.stamps:
                out['stamp_delay'] = max(abs(t - s) for t, s in zip(self.times, self.stamps))
                # the freshest message's: what its clock is, less this listener's own backlog
                out['stamp_delay_least'] = min(abs(t - s) for t, s in zip(self.times, self.stamps))
            out['seq_increasing'] = all(b > a for a, b in zip(self.seqs, self.seqs[1:]))
            out['first_time'] = self.times[0] if self.times else None
            out['last_time'] = self.times[-1] if self.times else None
            out.update(self.lists)
            return out


def main():
    p = argparse.ArgumentParser()
    p.add_argument('topics', nargs='+')
    p.add_argument('--duration', type=float, default=5.0)
    p.add_argument('--wait', type=float, default=20.0)
    p.add_argument('--speech')
    p.add_argument('--speech-topic', default='/speech')
    p.add_argument('--speech-at', type=float, default=2.0)
    p.add_argument('--absent', action='append', default=[],
                   help='a topic expected NOT to be published: not waited for, only reported')
    args = p.parse_args(rospy.myargv()[1:])
    rospy.init_node('emu_listen', anonymous=True, disable_signals=True)
    deadline = time.time() + args.wait
    types = {}
    while time.time() < deadline and len(types) < len(args.topics):
        for topic in args.topics:
            if topic not in types:
                type_name, _, _ = rostopic.get_topic_type(topic)
                if type_name:
                    types[topic] = type_name
        time.sleep(0.2)
    for topic in args.absent:
        type_name, _, _ = rostopic.get_topic_type(topic)
        if type_name:                   # known to the master (perhaps from an earlier node)
            types[topic] = type_name
    records, subs = {}, []
    for topic, type_name in types.items():
        if type_name == 'naoqi_bridge_msgs/AudioBuffer':      # usually not installed
            from pepper_interface_tests.sources.naoqi_msgs import audio_buffer_class
            cls = audio_buffer_class()
        else:
            cls = rostopic.get_topic_class(topic)[0]
        rec = records[topic] = Record(topic, type_name)
        subs.append(rospy.Subscriber(topic, cls, rec.callback, queue_size=50, buff_size=2 ** 24))
    speech_pub = rospy.Publisher(args.speech_topic, String, queue_size=1, latch=True) \
        if args.speech else None
    # the window opens once every subscriber is connected to its publishers (a loaded machine
    # can take a second or more), so counts and --speech-at are measured on a flowing stream
    connect_by = time.time() + min(args.wait, 10.0)
    awaited = [sub for sub in subs if sub.name not in args.absent]
    while time.time() < connect_by and not all(sub.get_num_connections() for sub in awaited):
        time.sleep(0.02)
    start = time.time()
    spoke_at = None
    while time.time() - start < args.duration:
        if speech_pub is not None and spoke_at is None and time.time() - start >= args.speech_at:
            speech_pub.publish(String(data=args.speech))
            spoke_at = time.time()
        time.sleep(0.02)
    for s in subs:
        s.unregister()
    state = rosgraph.Master('/emu_listen').getSystemState()
    publishers = {t: sorted(n) for t, n in state[0]}
    subscribers = {t: sorted(n) for t, n in state[1]}
    out = {'_meta': {'start': start, 'end': time.time(), 'spoke_at': spoke_at,
                     'missing': sorted(set(args.topics + args.absent) - set(types))}}
    for topic in args.topics + args.absent:
        if topic in records:
            out[topic] = records[topic].summary()
            out[topic]['publishers'] = publishers.get(topic, [])
        out.setdefault(topic, {})['subscribers'] = subscribers.get(topic, [])
        out[topic].setdefault('publishers', publishers.get(topic, []))
    json.dump(out, sys.stdout)
    sys.stdout.write('\n')
    sys.stdout.flush()
    rospy.signal_shutdown('done')


if __name__ == '__main__':
    main()
