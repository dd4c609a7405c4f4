#!/usr/bin/env python3
"""Test helper: Pepper's four microphones on PREFIX/audio, hearing what is said on PREFIX/speech,
delivered late on a busy PC. A real rospy node.

48 kHz in buffers of 4096 samples per channel (one every 85 ms): a quiet room (amplitude 30,
about -60 dBFS), and from 0.3 s after a sentence arrives on PREFIX/speech, 2 s of speech
(amplitude 3000) unless --mute (a loudspeaker that says nothing). With --hold S, from the
sentence's arrival on, the buffers are held S s and then published at once (a busy PC: they
waited in a queue), steadily afterwards. naoqi_driver's AudioBuffer stamped when captured
(event/audio.cpp:175-178), or with --custom the CSSR4Africa bridge's AudioCustomMsg (no header).

Usage: held_microphone.py PREFIX [--hold S] [--mute] [--custom]
Prints "microphone up", then "heard: <sentence>".
"""
import argparse
import os
import sys
import time

import numpy as np
import rospy
from std_msgs.msg import String

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), 'helpers'))
import fake_pepper as fake  # noqa: E402

RATE, N = 48000, 4096
QUIET, LOUD, SPEAKS, LASTS = 30.0, 3000.0, 0.3, 2.0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('prefix')
    ap.add_argument('--hold', type=float, default=0.0)
    ap.add_argument('--mute', action='store_true')
    ap.add_argument('--custom', action='store_true')
    a = ap.parse_args()
    rospy.init_node('held_microphone', anonymous=True, disable_signals=True)
    said = []
    rospy.Subscriber(a.prefix + '/speech', String,
                     lambda m: (said.append(time.time()), print('heard: ' + m.data, flush=True)))
    if a.custom:
        cls = fake._cls('pepper_interface_tests/AudioCustomMsg')
    else:
        from pepper_interface_tests.sources.naoqi_msgs import audio_buffer_class
        cls = audio_buffer_class()
    pub = rospy.Publisher(a.prefix + '/audio', cls, queue_size=200)
    print('microphone up', flush=True)
    start, i, held = time.time(), 0, []
    rng = np.random.default_rng(1)
    try:
        while not rospy.is_shutdown():
            time.sleep(max(0.0, start + (i + 1) * N / float(RATE) - time.time()))
            now = time.time()
            loud = said and not a.mute and said[0] + SPEAKS <= now <= said[0] + SPEAKS + LASTS
            x = (LOUD if loud else QUIET) * rng.standard_normal((4, N))
            x = np.clip(x, -32768, 32767).astype(np.int16)
            if a.custom:
                names = ('rearLeft', 'rearRight', 'frontLeft', 'frontRight')
                msg = cls(**{name: x[k].tolist() for k, name in enumerate(names)})
            else:
                msg = cls()
                msg.header.stamp = rospy.Time.from_sec(now)
                msg.frequency, msg.channelMap = RATE, bytes((3, 5, 0, 2))
                msg.data = x.T.reshape(-1).tolist()
            if said and now < said[0] + a.hold:
                held.append(msg)
            else:
                for m in held + [msg]:
                    pub.publish(m)
                held = []
            i += 1
    except KeyboardInterrupt:
        pass


if __name__ == '__main__':
    main()
