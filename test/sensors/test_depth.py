"""Depth check (sensors/depth.py): 16UC1 mm (Pepper, RealSense), 32FC1 m (simulator), wrong
encodings, valid share and median limits, the fixed-range colour video; and through sensorTest."""
import os
from dataclasses import asdict

import numpy as np
import pytest

from check_feed import feed
from fake_pepper import image
from media_tools import Publishers, explain, make_check, sensor_test, video_info, video_rate_is_the_stream_rate
from pepper_interface_tests.media.recording import to_bgr


def feed_frames(check, frames, rate=10.0):
    for i, msg in enumerate(frames):
        check.feed(msg, i / rate)
    check.close()
    return check


def mm_frame(value_mm, w=160, h=120, invalid_rows=0):
    a = np.full((h, w), value_mm, np.uint16)
    a[:invalid_rows] = 0
    return image(a, '16UC1')


def test_pepper_16uc1_millimetres_pass_with_min_median_max(tmp_path):
    frames = [mm_frame(1500 + 10 * i, invalid_rows=12) for i in range(10)]
    # flat synthetic frames: a real Xtion's noise is absent, so its noise rules are off here
    c = feed_frames(make_check('depthCamera', tmp_path, record=False, expect={'frozen_frames': None}), frames)
    assert c.failure_reasons() == []
    d = c.result_values().depth_m
    assert d.min == 1.5 and d.max == 1.59 and abs(d.median - 1.545) < 1e-6
    assert abs(c.result_values().valid_share.mean - 0.9) < 1e-6
    assert c.first_fields == [('Image Width', 160), ('Image Height', 120), ('Encoding', '16UC1'), ('Step', 320)]


def test_all_zero_depth_fails_with_a_clear_reason(tmp_path):
    c = feed_frames(make_check('depthCamera', tmp_path, record=False), [mm_frame(0) for _ in range(4)])
    reasons = c.failure_reasons()
    assert 'depth image has no valid pixel (all zero or not finite) in 4 of 4 messages' in reasons
    assert 'depth all zero: no valid pixel in any of the 4 frames' in reasons


def test_simulator_32fc1_metres_with_nan_is_understood(tmp_path):
    m = np.full((120, 160), 2.0, np.float32)
    m[:30] = np.nan
    m[30:40] = np.inf
    frames = [image(m, '32FC1') for _ in range(5)]
    c = feed_frames(make_check('depthCamera', tmp_path, platform='simulator', record=False), frames)
    assert c.failure_reasons() == []
    assert asdict(c.result_values().depth_m) == {'min': 2.0, 'median': 2.0, 'max': 2.0}
    assert abs(c.result_values().valid_share.mean - 80 / 120) < 1e-3


def test_realsense_aligned_depth_16uc1(tmp_path):
    a = np.tile(np.linspace(300, 4000, 640).astype(np.uint16), (480, 1))
    c = feed_frames(make_check('realsenseDepthCamera', tmp_path, record=False), [image(a, '16UC1')] * 3)
    assert c.failure_reasons() == []
    assert c.result_values().width == 640 and c.result_values().depth_m.min == 0.3


def test_a_colour_image_on_a_depth_topic_is_a_wrong_encoding(tmp_path):
    rgb = np.zeros((120, 160, 3), np.uint8)
    c = feed_frames(make_check('depthCamera', tmp_path, platform='simulator', record=False), [image(rgb, 'rgb8')] * 3)
    assert any(r.startswith('encoding "rgb8" is not a depth encoding') for r in c.failure_reasons())
    c = feed_frames(make_check('depthCamera', tmp_path, record=False), [mm_frame(1000)] * 2 + [image(rgb, 'rgb8')])
    assert 'encoding "rgb8" where "16UC1" is expected in 1 of 3 messages' in c.failure_reasons()


def test_valid_share_and_median_limits(tmp_path):
    frames = [mm_frame(1500, invalid_rows=110) for _ in range(4)]      # 8 % valid
    c = feed_frames(make_check('depthCamera', tmp_path, record=False), frames)
    assert any(r.startswith('only 8.3% of the pixels are valid (min_valid_share 20%)') for r in c.failure_reasons())
    c = feed_frames(make_check('depthCamera', tmp_path, record=False), [mm_frame(9500)] * 4)
    assert 'median depth 9.5 m outside median_range [0.3, 8] m' in c.failure_reasons()


@pytest.mark.integration     # compares with OpenCV's own map: cv2 takes half a second to import
def test_video_uses_a_fixed_range_and_black_invalid_pixels(tmp_path):
    import cv2
    c = make_check('depthCamera', tmp_path, record=False)
    near = np.full((10, 10), 2500, np.uint16)      # 2.5 m: the middle of the 0-5 m range
    mixed = near.copy()
    mixed[:, 5:] = 4900
    mixed[0, 0] = 0
    a, b = colour(c, near, 'depth_mm'), colour(c, mixed, 'depth_mm')
    assert (a[5, 2] == b[5, 2]).all()              # same depth, same colour, whatever else is in view
    assert (b[0, 0] == 0).all() and b[5, 2].any()
    metres = colour(c, near.astype(np.float32) / 1000, 'depth_m')
    assert np.abs(metres.astype(int) - a.astype(int)).max() <= 2
    # the table is the JET map over 0-5 m, as OpenCV draws it: near is blue, far is red
    ramp = np.linspace(1, 5000, 256).astype(np.uint16).reshape(1, 256)
    ours = colour(c, ramp, 'depth_mm')[0].astype(int)
    opencv = cv2.applyColorMap(np.arange(256, dtype=np.uint8).reshape(1, 256), cv2.COLORMAP_JET)[0].astype(int)
    assert np.abs(ours - opencv).max() <= 12, np.abs(ours - opencv).max()
    assert ours[0, 0] > 100 and ours[0, 2] == 0 and ours[-1, 2] > 100 and ours[-1, 0] == 0


def colour(check, depth, kind):
    return to_bgr(*check.prepare_frame(depth, kind))


@pytest.mark.integration          # ffmpeg encodes the video
def test_depth_video_frames_are_yuv420p_with_the_colours_of_the_live_view(tmp_path):
    """The video is fed planar yuv420p made in Python (ffmpeg converts nothing): decoded, it
    shows the live view's colours; an odd size falls back to BGR0 (and is padded)."""
    rng = np.random.default_rng(3)
    frames = []
    for _ in range(8):
        mm = np.repeat(np.repeat(rng.integers(300, 6000, (60, 80)), 2, 0), 2, 1).astype(np.uint16)
        mm[:20] = 0                                # invalid rows: black
        frames.append(mm)
    c = make_check('depthCamera', tmp_path)
    assert c.prepare_frame(frames[0], 'depth_mm')[1] == 'yuv420p'
    assert c.prepare_frame(frames[0][:119, :159], 'depth_mm')[1] == 'bgr0'
    c = feed_frames(c, [image(f, '16UC1') for f in frames])
    video = c.result_values().video
    assert video.frames_written == 8 and (video.width, video.height) == (160, 120), video
    import cv2
    cap = cv2.VideoCapture(os.path.join(str(tmp_path), 'out', 'depthCameraOutput.mp4'))
    ok, decoded = cap.read()
    assert ok and decoded.shape == (120, 160, 3)
    want = to_bgr(*c.colour_map(frames[0], 'depth_mm')).astype(int)
    # H.264 at crf 28 on random 2x2 blocks: close, not exact; black stays black
    assert np.abs(decoded.astype(int) - want).mean() < 12, np.abs(decoded.astype(int) - want).mean()
    assert decoded[:18].max() < 40


def test_one_valid_pixel_anywhere_is_not_an_all_zero_frame(tmp_path):
    a = np.zeros((120, 160), np.uint16)
    a[57, 93] = 1200                               # outside the every-4th-pixel sample
    c = feed_frames(make_check('depthCamera', tmp_path, record=False), [image(a, '16UC1')] * 3)
    assert c.result_values().frames_all_zero == 0
    assert not any('depth all zero' in r or 'no valid pixel' in r for r in c.failure_reasons())


def test_big_endian_and_padded_rows_are_read_right(tmp_path):
    a = np.full((120, 160), 1500, np.uint16)
    padded = np.zeros((120, 170), '>u2')
    padded[:, :160] = a
    msg = image(padded, '16UC1', width=160)
    msg.is_bigendian = 1
    c = feed_frames(make_check('depthCamera', tmp_path, record=False, expect={'frozen_frames': None}), [msg] * 3)
    assert c.failure_reasons() == [] and c.result_values().depth_m.median == 1.5


# ---------------------------------------------------------------- through sensorTest

def test_sensor_test_depth_robot(module_master, tmp_path):
    with Publishers(module_master, tmp_path) as pubs:
        pubs.add('depthCamera', 'depth', '--rate', 10, '--fault', 'zero')
        pubs.add('realsenseDepthCamera', 'depth', '--rate', 15, '--count', 30, '--width', 640, '--height', 480)
        done, res = sensor_test(module_master, tmp_path, ['depthCamera', 'realsenseDepthCamera'], duration=5,
                                expect={'realsenseDepthCamera': {'max_gap_factor': 15}})
        published = pubs.stop()
    assert res is not None, explain(done, res)
    s = res['by_name']
    assert s['depthCamera']['verdict'] == 'FAIL'
    assert 'depth all zero: no valid pixel in any of the %d frames' % s['depthCamera']['messages'] \
        in s['depthCamera']['reasons'], explain(done, res)
    rs = s['realsenseDepthCamera']
    assert rs['verdict'] == 'PASS', explain(done, res)
    assert published['realsenseDepthCamera'] == 30 and rs['messages'] == 30
    assert 0.5 <= rs['values']['depth_m']['min'] and rs['values']['depth_m']['max'] <= 3.7
    frames, w, h, fps = video_info(os.path.join(str(tmp_path), 'out', 'realsenseDepthOutput.mp4'))
    assert frames == 30 and (w, h) == (640, 480) and video_rate_is_the_stream_rate(fps, rs), (fps, rs['rate_hz'])


def test_sensor_test_depth_simulator_32fc1(module_master, tmp_path):
    with Publishers(module_master, tmp_path) as pubs:
        pubs.add('depthCamera', 'depth', '--rate', 10, '--fault', 'float_m')
        done, res = sensor_test(module_master, tmp_path, ['depthCamera'], duration=3, platform='simulator')
    assert res is not None, explain(done, res)
    d = res['by_name']['depthCamera']
    assert d['verdict'] == 'PASS' and done.returncode == 0, explain(done, res)
    assert ['Encoding', '32FC1'] in d['fields']
    assert 1.5 < d['values']['depth_m']['median'] < 2.5
    frames, w, h, _ = video_info(os.path.join(str(tmp_path), 'out', 'depthCameraOutput.mp4'))
    assert frames == d['messages'] and (w, h) == (320, 240)


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


# ---------------------------------------------------------------- aligned depth (issue 45)
# realsense-ros's topics as data/pepperTopics.dat names them (base_realsense_node.cpp:989)
ALIGNED = '/camera/aligned_depth_to_color/image_raw'
UNALIGNED = '/camera/depth/image_rect_raw'
COLOUR_FRAME = 'camera_color_optical_frame'


def realsense_pair(tmp_path, depth_topic=ALIGNED, sensors=('realsenseRGBCamera', 'realsenseDepthCamera')):
    """The colour and depth checks of one run (one RunContext), from the package's real plan."""
    from pepper_interface_tests.plan import settings
    from pepper_interface_tests.sensors import check_class
    from pepper_interface_tests.sensors.base import RunContext
    topics = tmp_path / 'topics.dat'
    topics.write_text('RealSenseCameraRGB /camera/color/image_raw\nRealSenseCameraDepth %s\n' % depth_topic)
    plan = settings.load_plan(settings.Options(platform='robot', sensors=sensors, topics=str(topics),
                                               output_dir=str(tmp_path / 'out'), record=False))
    os.makedirs(plan.output_dir, exist_ok=True)
    ctx = RunContext(plan.output_dir, plan.platform, plan.options)
    return [check_class(sp.sensor.family)(sp, ctx) for sp in plan.sensors]


def colour_frames(w, h, frame_id=COLOUR_FRAME, n=5):
    from fake_pepper import camera_image
    return [camera_image(i, w, h, frame_id=frame_id) for i in range(n)]


def depth_frames(w, h, frame_id=COLOUR_FRAME, n=5):
    a = np.tile(np.linspace(300, 4000, w).astype(np.uint16), (h, 1))
    return [image(a + i, '16UC1', frame_id=frame_id) for i in range(n)]


def run_pair(tmp_path, colour, depth, depth_topic=ALIGNED):
    rgb, dep = realsense_pair(tmp_path, depth_topic)
    for i, (c, d) in enumerate(zip(colour, depth)):     # both windows at once, as in parallel mode
        rgb.feed(c, i / 15.0)
        dep.feed(d, i / 15.0)
    rgb.close()
    dep.close()
    return rgb, dep


def test_a_healthy_aligned_pair_passes(tmp_path):
    rgb, dep = run_pair(tmp_path, colour_frames(640, 480), depth_frames(640, 480))
    assert rgb.failure_reasons() == [] and dep.failure_reasons() == [], dep.failure_reasons()


def test_unaligned_depth_on_the_aligned_topic_fails_naming_both_sizes(tmp_path):
    """realsense-ros PR #2793: the 848x480 depth stream on aligned_depth_to_color beside
    640x480 colour. Before: PASS."""
    rgb, dep = run_pair(tmp_path, colour_frames(640, 480), depth_frames(848, 480))
    assert rgb.failure_reasons() == []
    reasons = dep.failure_reasons()
    assert any(r.startswith('aligned depth is 848x480 but realsenseRGBCamera, the colour image it is '
                            'aligned to, is 640x480') and ALIGNED in r for r in reasons), reasons


def test_aligned_depth_in_another_frame_than_its_colour_fails(tmp_path):
    rgb, dep = run_pair(tmp_path, colour_frames(640, 480),
                        depth_frames(640, 480, frame_id='camera_depth_optical_frame'))
    reasons = dep.failure_reasons()
    assert any('aligned depth is in frame "camera_depth_optical_frame" but realsenseRGBCamera, the colour '
               'image it is aligned to, in "camera_color_optical_frame"' in r for r in reasons), reasons


def test_a_frame_id_only_one_of_them_carries_is_not_compared(tmp_path):
    _, dep = run_pair(tmp_path, colour_frames(640, 480, frame_id=''), depth_frames(640, 480))
    assert dep.failure_reasons() == []


def test_unaligned_depth_on_its_own_topic_passes(tmp_path):
    """The depth stream on its own topic (depth/image_rect_raw, 848x480 in the depth optical
    frame) is not aligned to anything: its size is its own."""
    _, dep = run_pair(tmp_path, colour_frames(640, 480),
                      depth_frames(848, 480, frame_id='camera_depth_optical_frame'), depth_topic=UNALIGNED)
    assert dep.failure_reasons() == [], dep.failure_reasons()


def test_aligned_depth_without_its_colour_in_the_run_is_noted_not_judged(tmp_path):
    dep, = realsense_pair(tmp_path, sensors=('realsenseDepthCamera',))
    for i, d in enumerate(depth_frames(848, 480)):
        dep.feed(d, i / 15.0)
    dep.close()
    assert dep.failure_reasons() == []
    assert 'aligned depth not compared with realsenseRGBCamera: no image of it was seen before this window ended' \
        in dep.notes
