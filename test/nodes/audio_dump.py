#!/usr/bin/env python3
"""Test helper: subscribe to an AudioCustomMsg topic and dump everything received to a .npz.

Prints 'ready' once subscribed, 'connected' when the first publisher connection exists and one
line 'msg <count> <length>' per message (so a test can follow progress). On SIGINT/SIGTERM or
after --seconds writes OUT.npz with: samples (4, total) int16 in field order rearLeft,
rearRight, frontLeft, frontRight; lengths (per message); recv_time (per message, wall clock).
"""
import argparse
import signal
import sys
import threading
import time

import numpy as np
import rospy
from rospy.numpy_msg import numpy_msg

from pepper_interface_tests.msg import AudioCustomMsg

FIELDS = ('rearLeft', 'rearRight', 'frontLeft', 'frontRight')


def main():
    p = argparse.ArgumentParser()
    p.add_argument('out')
    p.add_argument('--topic', default='/naoqi_driver/audio')
    p.add_argument('--seconds', type=float, default=0)
    args = p.parse_args(rospy.myargv(sys.argv)[1:])
    rospy.init_node('audio_dump', anonymous=True, disable_signals=True)
    chunks, times, lock, stop = [], [], threading.Lock(), threading.Event()

    def on_msg(msg):
        now = time.time()
        block = np.stack([np.asarray(getattr(msg, f), dtype=np.int16) for f in FIELDS])
        with lock:
            chunks.append(block)
            times.append(now)
            n = len(chunks)
        sys.stdout.write('msg %d %d\n' % (n, block.shape[1]))
        sys.stdout.flush()

    sub = rospy.Subscriber(args.topic, numpy_msg(AudioCustomMsg), on_msg, queue_size=2000)
    signal.signal(signal.SIGINT, lambda *_: stop.set())
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    print('ready', flush=True)
    deadline = time.time() + args.seconds if args.seconds else None
    announced = False
    while not stop.wait(0.05):
        if not announced and sub.get_num_connections() > 0:
            print('connected', flush=True)
            announced = True
        if deadline and time.time() > deadline:
            break
    sub.unregister()
    with lock:
        samples = np.concatenate(chunks, axis=1) if chunks else np.zeros((4, 0), np.int16)
        lengths = np.array([c.shape[1] for c in chunks], dtype=np.int64)
        recv = np.array(times)
    np.savez(args.out, samples=samples, lengths=lengths, recv_time=recv)
    print('saved %d' % len(lengths), flush=True)
    rospy.signal_shutdown('done')


if __name__ == '__main__':
    main()
