#!/usr/bin/env python3
"""Test helper: publish camera, depth or microphone messages on a topic, good or with one fault.

usage: media_publisher.py KIND TOPIC [--rate HZ] [--fault NAME] [--width W] [--height H]
                          [--count N] [--report FILE] [--node NAME] [--frame-id ID]
KIND  camera  sensor_msgs/Image rgb8, a moving pattern (every frame differs)
      stereo  rgb8, two different views side by side (width = 2 x view width)
      depth   16UC1 in mm (a ramp 0.5-3.5 m, a band of invalid zero pixels)
      audio   AudioCustomMsg, 4 channels, --samples per buffer at --sample-rate
Faults
  camera/stereo: frozen (the same frame every time), black, constant (mid grey), wrong_step
      (step one byte short), wrong_encoding (bgra8 with a matching layout), size_change
      (every other frame half size), same_halves (stereo views identical)
  depth: zero (all pixels 0), float_m (32FC1 in metres, NaN band), bad_encoding (rgb8)
  audio: silent:<channel> (that channel all zeros), tone (each microphone carries its sine of
      fake_pepper.MIC_TONES), lengths (frontRight one sample short)
--loud-after S (audio): quiet noise (about -50 dBFS) for S seconds, then loud noise (about
-15 dBFS); the time.monotonic() of the switch is written to --loud-file.
--delivery SHAPE (audio): buffers made at --sample-rate, handed over as a busy network or PC
does (the start waits for a subscriber): steady (each when made), start-burst (the 8 buffers
made while the bridge connected at once, then steady), pauses (every 2 s the last 0.4 s held,
then sent at once: the 0.30-0.42 s pauses of issue 41), groups (two or three at a time).
--count N publishes N messages, starting once a subscriber is connected, then stays up (so
the count in a listening window is known exactly). --report FILE writes {"published": N}
at exit (SIGINT/SIGTERM or after --count).
"""
import argparse
import json
import os
import signal
import sys
import time

import numpy as np
import rospy
from sensor_msgs.msg import Image

# the test helpers (test/helpers/, beside this script's folder test/nodes/)
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), 'helpers'))
import fake_pepper as fake  # noqa: E402
from media_tools import pattern  # noqa: E402


def image(a, pixels, encoding, step=None):
    return fake.image(pixels, encoding, step=step, t=rospy.Time.now(), frame_id=a.frame_id)


def make_camera(a, i, cache):
    w, h = a.width, a.height
    if a.fault == 'size_change' and i % 2:
        w, h = w // 2, h // 2
    if a.fault == 'frozen':
        px = cache.setdefault('frozen', pattern(w, h, 0))
    elif a.fault == 'black':
        px = np.zeros((h, w, 3), np.uint8)
    elif a.fault == 'constant':
        px = np.full((h, w, 3), 128, np.uint8)
    elif a.kind == 'stereo':
        view = pattern(w // 2, h, i)
        other = view if a.fault == 'same_halves' else np.roll(view, 7, axis=1)
        px = np.concatenate([view, other], axis=1)
    else:
        px = pattern(w, h, i)
    if a.fault == 'wrong_encoding':
        px4 = np.dstack([px, np.full((h, w), 255, np.uint8)])
        return image(a, px4, 'bgra8')
    step = w * 3 - 1 if a.fault == 'wrong_step' else w * 3
    return image(a, px, 'rgb8', step)


def make_depth(a, i, cache):
    w, h = a.width, a.height
    if 'ramp' not in cache:
        ramp = np.tile(np.linspace(500, 3500, w, dtype=np.float64), (h, 1))
        cache['ramp'] = ramp
    mm = (cache['ramp'] + 20 * (i % 10)).astype(np.uint16)
    mm[: h // 10] = 0        # invalid band
    if a.fault == 'zero':
        mm[:] = 0
    if a.fault == 'float_m':
        m = mm.astype(np.float32) / 1000.0
        m[: h // 10] = np.nan
        return image(a, m, '32FC1')
    if a.fault == 'bad_encoding':
        return image(a, pattern(w, h, i), 'rgb8')
    return image(a, mm, '16UC1')


def make_audio(a, i, cache):
    n = a.samples
    rng = cache.setdefault('rng', np.random.default_rng(1))
    chans = None                             # --fault tone: fake_pepper.MIC_TONES at 8000
    if a.fault != 'tone' and a.loud_after is not None:
        loud = time.monotonic() >= cache.setdefault('loud_at', time.monotonic() + a.loud_after)
        if loud and not cache.get('told'):
            cache['told'] = True
            with open(a.loud_file, 'w') as f:
                f.write('%.6f' % cache['loud_at'])
        chans = [rng.normal(0, 6000.0 if loud else 100.0, n) for _ in range(4)]
    elif a.fault != 'tone':
        chans = [rng.normal(0, 1500.0, n) for _ in range(4)]     # noise, about -27 dBFS
    return fake.audio_buffer(i, n, a.sample_rate, tones=True, amplitude=8000.0, channels=chans,
                             silent=a.fault[len('silent:'):] if a.fault.startswith('silent:') else None,
                             short='frontRight' if a.fault == 'lengths' else None)


BURST = 8                      # start-burst: buffers made before the subscriber connected
HOLD_EVERY, HOLD = 2.0, 0.4    # pauses: every HOLD_EVERY s the last HOLD s are held


def handed_over(shape, i, period):
    """When (s after the start) buffer `i`, made every `period` s, is published in `shape`."""
    if shape == 'start-burst':
        return max(0.0, (i - (BURST - 1)) * period)
    made = i * period
    if shape == 'pauses':
        return made if made % HOLD_EVERY < HOLD_EVERY - HOLD else (made // HOLD_EVERY + 1) * HOLD_EVERY
    if shape == 'groups':       # groups of 2 and 3 buffers in turn: 5 buffers per cycle
        cycle, k = divmod(i, 5)
        last = cycle * 5 + (1 if k < 2 else 4)
        return last * period
    return made


def deliver(pub, a, make, period):
    """Publishes the audio buffers in the shape `a.delivery` until stopped (module docstring)."""
    published, cache, i = 0, {}, 0
    while pub.get_num_connections() == 0 and not rospy.is_shutdown():
        time.sleep(0.02)
    time.sleep(0.3)      # let the subscriber's connection settle
    t0 = time.monotonic()
    while not rospy.is_shutdown():
        delay = t0 + handed_over(a.delivery, i, period) - time.monotonic()
        if delay > 0:
            time.sleep(delay)     # the shape's pace: the behaviour under test
        pub.publish(make(a, i, cache))
        published += 1
        i += 1
        yield published


def main():
    p = argparse.ArgumentParser()
    p.add_argument('kind', choices=('camera', 'stereo', 'depth', 'audio'))
    p.add_argument('topic')
    p.add_argument('--rate', type=float, default=None)
    p.add_argument('--fault', default='')
    p.add_argument('--width', type=int, default=None)
    p.add_argument('--height', type=int, default=None)
    p.add_argument('--samples', type=int, default=4096)
    p.add_argument('--sample-rate', type=float, default=48000.0)
    p.add_argument('--count', type=int, default=0)
    p.add_argument('--loud-after', type=float, default=None)
    p.add_argument('--loud-file', default=None)
    p.add_argument('--report', default=None)
    p.add_argument('--node', default='media_publisher')
    p.add_argument('--frame-id', default='')
    p.add_argument('--delivery', default='', choices=('', 'steady', 'start-burst', 'pauses', 'groups'))
    a = p.parse_args(rospy.myargv()[1:])
    defaults = {'camera': (320, 240), 'stereo': (640, 180), 'depth': (320, 240), 'audio': (0, 0)}[a.kind]
    a.width, a.height = a.width or defaults[0], a.height or defaults[1]
    if a.kind == 'audio':
        from pepper_interface_tests.msg import AudioCustomMsg as cls
        rate = a.rate or a.sample_rate / a.samples
        make = make_audio
    else:
        cls, rate = Image, a.rate or 10.0
        make = make_depth if a.kind == 'depth' else make_camera

    rospy.init_node(a.node, anonymous=True, disable_signals=True)
    pub = rospy.Publisher(a.topic, cls, queue_size=100)
    published = [0]
    stop = [False]

    def finish(*_):
        stop[0] = True

    signal.signal(signal.SIGINT, finish)
    signal.signal(signal.SIGTERM, finish)

    def report():
        if a.report:
            with open(a.report, 'w') as f:
                json.dump({'published': published[0]}, f)

    if a.delivery:
        for published[0] in deliver(pub, a, make, a.samples / a.sample_rate):
            if stop[0]:
                break
        report()
        rospy.signal_shutdown('done')
        return 0
    if a.count:
        while not stop[0] and pub.get_num_connections() == 0:
            time.sleep(0.02)
        time.sleep(0.3)      # let the subscriber's connection settle
    cache = {}
    period = 1.0 / rate
    next_t = time.monotonic()
    i = 0
    print('publishing %s on %s at %.2f Hz%s' % (a.kind, a.topic, rate, ' (%s)' % a.fault if a.fault else ''),
          flush=True)
    while not stop[0] and not rospy.is_shutdown():
        if a.count and published[0] >= a.count:
            report()
            while not stop[0]:
                time.sleep(0.05)
            break
        pub.publish(make(a, i, cache))
        published[0] += 1
        i += 1
        next_t += period
        delay = next_t - time.monotonic()
        if delay > 0:
            time.sleep(delay)
        else:
            next_t = time.monotonic()
    report()
    rospy.signal_shutdown('done')
    return 0


if __name__ == '__main__':
    sys.exit(main())
