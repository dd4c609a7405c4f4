"""Depth and microphone rules for data that cannot be real (issue 10), on real serialised
messages: each message is built as a sensor_msgs/Image or AudioCustomMsg, serialised and
deserialised with genpy as it comes off the wire, and fed to the check with explicit times."""

import numpy as np

from fake_pepper import audio_buffer, image, serialized
from media_tools import make_check


def wire(msg):
    """The message as a subscriber receives it: serialised, then deserialised."""
    return type(msg)().deserialize(serialized(msg))


def feed(check, msgs, rate=10.0, start=0.05):
    for i, m in enumerate(msgs):
        check.feed(wire(m), start + i / rate)
    check.close()
    return check


def depth(i, w=160, h=120, rng=None):
    """A floor-and-wall scene in millimetres with the Xtion's noise and a few holes."""
    rng = rng or np.random.default_rng(i)
    yy = np.mgrid[0:h, 0:w][0]
    a = (1500 + 10 * yy + rng.normal(0, 8, (h, w))).astype(np.uint16)
    a[rng.integers(0, h, 50), rng.integers(0, w, 50)] = 0
    return image(a, '16UC1')


def test_a_healthy_depth_stream_passes(tmp_path):
    c = feed(make_check('depthCamera', tmp_path, record=False), [depth(i) for i in range(20)])
    assert c.failure_reasons() == [] and c.result_values().longest_identical_run == 1


def test_frozen_depth_fails_from_when_it_froze(tmp_path):
    frames = [depth(i) for i in range(8)] + [depth(99)] * 12
    c = feed(make_check('depthCamera', tmp_path, record=False), frames)
    assert 'depth image frozen: 12 identical frames in a row from t = 0.85 s to the end of the window ' \
           '(frozen_frames 10)' in c.failure_reasons(), c.failure_reasons()


def test_a_single_depth_everywhere_fails_on_the_robot_not_in_the_simulator(tmp_path):
    flat = [image(np.full((120, 160), 1500 + i, np.uint16), '16UC1') for i in range(6)]
    c = feed(make_check('depthCamera', tmp_path, record=False), flat)
    assert any(r.startswith('depth image holds a single value everywhere in 6 of 6 frames')
               for r in c.failure_reasons()), c.failure_reasons()
    # Gazebo's depth has no noise: a wall square to the camera is one value everywhere
    c = feed(make_check('depthCamera', tmp_path, platform='simulator', record=False), flat)
    assert c.failure_reasons() == []


def test_depth_mostly_beyond_the_physical_range_fails(tmp_path):
    """30 m over most of the image: 16UC1 can say it, an Xtion cannot measure it."""
    far = [image((30000 + (np.arange(160 * 120) + i) % 500).astype(np.uint16).reshape(120, 160),
                     '16UC1') for i in range(6)]
    frames = [depth(i) for i in range(2)] + far
    c = feed(make_check('depthCamera', tmp_path, record=False, expect={'median_range': None}), frames)
    assert "most of the depth image outside the camera's physical range [0, 10] m in 6 of 8 frames" \
        in c.failure_reasons(), c.failure_reasons()


def test_depth_that_turns_all_zero_partway_fails_from_when(tmp_path):
    zero = image(np.zeros((120, 160), np.uint16), '16UC1')
    frames = [depth(i) for i in range(15)] + [zero] * 12
    c = feed(make_check('depthCamera', tmp_path, record=False, expect={'frozen_frames': None}), frames)
    assert 'depth all zero from t = 1.55 s to the end of the window (12 frames, 1.1 s)' \
        in c.failure_reasons(), c.failure_reasons()


def custom(i, n=4096, dead=None, dead_from=None):
    """Tones of 500, 800, 1100 and 1400 Hz with a little noise (no two buffers alike); `dead`
    all zeros from buffer `dead_from` on."""
    rng = np.random.default_rng(i)
    tt = (np.arange(n) + i * n) / 48000.0
    return audio_buffer(i, n, channels=[(2000 * np.sin(2 * np.pi * (500 + 300 * k) * tt) + rng.normal(0, 50, n))
                                        .astype(np.int16) for k in range(4)],
                        silent=dead if dead_from is not None and i >= dead_from else None)


def test_microphone_buffers_that_repeat_fail(tmp_path):
    msgs = [custom(i) for i in range(5)] + [custom(5)] * 10
    c = feed(make_check('microphone', tmp_path, record=False), msgs, rate=48000 / 4096.0)
    assert any(r.startswith('microphone stream stuck: 10 identical buffers in a row from t = ')
               and r.endswith('to the end of the window (stuck_buffers 3)') for r in c.failure_reasons()), \
        c.failure_reasons()
    c = feed(make_check('microphone', tmp_path, record=False), [custom(i) for i in range(15)],
             rate=48000 / 4096.0)
    assert c.failure_reasons() == []


def test_a_microphone_channel_that_dies_halfway_fails_by_name_and_time(tmp_path):
    msgs = [custom(i, dead='frontLeft', dead_from=12) for i in range(30)]
    c = feed(make_check('microphone', tmp_path, record=False), msgs, rate=48000 / 4096.0)
    hits = [r for r in c.failure_reasons() if r.startswith('microphone frontLeft went silent from t = 1.07 s '
                                                           'to the end of the window (18 buffers')]
    assert hits, c.failure_reasons()
    assert not any('rearLeft' in r or 'frontRight' in r for r in c.failure_reasons())
