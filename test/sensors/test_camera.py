"""Camera check (sensors/camera.py): per-message layout/encoding checks, black/constant/frozen
frames, stereo geometry, and the whole path through sensorTest with real rospy publishers."""
import json
import os
import subprocess
import sys
from dataclasses import asdict

import numpy as np
import pytest

from fake_pepper import image, serialized
from media_tools import (
    HERE,
    PUBLISHER,
    Publishers,
    explain,
    make_check,
    pattern,
    sensor_test,
    video_codec,
    video_info,
    video_rate_is_the_stream_rate,
)
from pepper_interface_tests.sensors.base import Services
from rosmaster import kill_group, spawn, wait_registered


def feed(check, frames, rate=10.0):
    for i, msg in enumerate(frames):
        check.feed(msg, i / rate)
    check.close()
    return check


def good(n, w=160, h=120):
    return [image(pattern(w, h, i), 'rgb8') for i in range(n)]


MALLOC_PROBE = """
import ctypes, sys
class MallInfo2(ctypes.Structure):
    _fields_ = [(n, ctypes.c_size_t) for n in ('arena', 'ordblks', 'smblks', 'hblks', 'hblkhd', 'usmblks',
                                              'fsmblks', 'uordblks', 'fordblks', 'keepcost')]
libc = ctypes.CDLL(None)
libc.mallinfo2.restype = MallInfo2
from pepper_interface_tests.sensors import camera
if sys.argv[1] == 'tuned':
    camera.keep_freed_memory()
before = libc.mallinfo2().hblks
frame = bytearray(921600)               # a 640x480 rgb8 frame's bytes
print(libc.mallinfo2().hblks - before)
"""


@pytest.mark.integration          # fresh Python processes: the setting is per process
def test_image_checks_keep_frame_sized_buffers_in_the_heap():
    """keep_freed_memory (called by every image check) stops glibc from giving a frame its own
    mmap, which is unmapped on free and faulted in again for the next message."""
    def mmapped(mode):
        out = subprocess.run([sys.executable, '-c', MALLOC_PROBE, mode], capture_output=True, text=True,
                             timeout=60)
        assert out.returncode == 0, out.stderr
        return int(out.stdout.strip())
    assert mmapped('default') == 1          # glibc's default: a chunk of its own, mapped afresh
    assert mmapped('tuned') == 0


def test_good_frames_pass_with_the_spec_fields_and_measured_values(tmp_path):
    c = feed(make_check('frontCamera', tmp_path, record=False), good(12))
    assert c.failure_reasons() == [] and c.warning_reasons() == []
    assert c.first_fields == [('Image Width', 160), ('Image Height', 120), ('Encoding', 'rgb8'), ('Step', 480)]
    v = c.result_values()
    assert v.width == 160 and v.height == 120 and v.step == 480
    assert 100 < v.brightness_mean.mean < 160
    assert v.longest_identical_run == 1
    assert 'video' not in c.artifacts      # record=False


def stalled_subscriber_receives(master, queue_size, buff_size, rate, frames):
    """Frames a subscriber made like sources/live.py's (AnyMsg, `queue_size`, `buff_size`)
    receives of `frames` QQVGA frames published at `rate` Hz while its callback blocks 2 s on
    the first one (queue_probe.py)."""
    topic = '/queue/image_raw'
    probe = spawn([sys.executable, os.path.join(HERE, 'queue_probe.py'), topic, str(queue_size), str(buff_size),
                   '2.0', str(frames / rate + 4.0)], master.env(), stdout=subprocess.PIPE, text=True)
    try:
        wait_registered(master, subscribed=[topic], subscriber='queue_probe')
        pub = spawn([sys.executable, PUBLISHER, 'camera', topic, '--rate', str(rate), '--count', str(frames),
                     '--width', '160', '--height', '120'], master.env(), stdout=subprocess.DEVNULL)
        out, _ = probe.communicate(timeout=60)
        kill_group(pub)
    finally:
        kill_group(probe)
    return json.loads(out)['received']


def test_a_callback_stalled_for_two_seconds_loses_no_frame_at_the_fastest_expected_rate(master, tmp_path):
    """What the camera's subscriber queue and buffer size are for: a callback blocked 2 s (a slow
    disk under the encoder) while the camera runs at the top of its band loses no frame. A
    queue of one message does lose frames, so the probe sees a loss when there is one."""
    c = make_check('frontCamera', tmp_path, record=False)
    top = c.expect.rate[1]
    frames = int(top * 2.0) + 1
    assert stalled_subscriber_receives(master, c.queue_size, c.buff_size, top, frames) == frames
    assert stalled_subscriber_receives(master, 1, c.buff_size, top, frames) < frames


def test_buff_size_reads_at_least_a_qvga_frame_per_call_and_stays_below_a_megabyte(tmp_path):
    c = make_check('frontCamera', tmp_path, record=False)
    # a recv() of at least a QVGA frame per call, and below the 1 MB that measured 35 % dearer (camera.py)
    assert 320 * 240 * 3 <= c.buff_size < 1 << 20


def test_wrong_step_is_counted_and_the_frame_not_converted(tmp_path):
    frames = [image(pattern(160, 120, i), 'rgb8', step=479) for i in range(5)]
    c = feed(make_check('frontCamera', tmp_path, record=False), frames)
    reasons = ' | '.join(c.failure_reasons())
    assert 'step x height (479 x 120 = 57480) is not the data length in 5 of 5 messages' in reasons
    assert 'step 479 is less than width x bytes per pixel (160 x 3)' in reasons
    assert c.converted == 0


def test_wrong_encoding_and_size_fail(tmp_path):
    bgra = np.dstack([pattern(160, 120, 0), np.full((120, 160), 255, np.uint8)])
    frames = [image(bgra, 'bgra8') for _ in range(1)] + good(2)
    c = feed(make_check('frontCamera', tmp_path, record=False, expect={'width': 320, 'height': 240}), frames)
    reasons = ' | '.join(c.failure_reasons())
    assert 'encoding "bgra8" where "rgb8" is expected in 1 of 3 messages' in reasons
    assert 'width 160 where 320 is expected in 3 of 3 messages' in reasons
    assert 'height 120 where 240 is expected' in reasons
    assert c.converted == 3                            # bgra8 converts: it is only unexpected


@pytest.mark.integration     # the real cv_bridge, which imports OpenCV (half a second)
def test_cv_bridge_error_is_a_counted_failure_not_a_crash(tmp_path):
    # depth in metres on a colour camera's topic: not an image cv_bridge turns into colour
    # (16UC1 is read in place since media/encodings.py: test/media/test_encodings.py)
    depth = np.full((120, 160), 1.5, np.float32)
    frames = [image(depth, '32FC1') for _ in range(3)]
    c = feed(make_check('frontCamera', tmp_path, record=False), frames)
    reasons = ' | '.join(c.failure_reasons())
    assert 'cv_bridge cannot convert 32FC1 to bgr8 in 3 of 3 messages' in reasons


@pytest.mark.parametrize('repeats,frozen', [(4, False), (5, True)])
def test_frozen_needs_frozen_frames_identical_frames_in_a_row(tmp_path, repeats, frozen):
    same = image(pattern(160, 120, 99), 'rgb8')
    frames = good(3) + [same] * repeats + [image(pattern(160, 120, 50 + i), 'rgb8') for i in range(3)]
    c = feed(make_check('bottomCamera', tmp_path, record=False), frames)
    assert c.result_values().longest_identical_run == repeats
    text = ' | '.join(c.failure_reasons())
    assert ('image frozen: %d identical consecutive frames' % repeats in text) is frozen, text


def test_frozen_is_exact_a_change_in_one_pixel_is_a_new_frame(tmp_path):
    base = pattern(160, 120, 7)
    frames = []
    for i in range(8):
        px = base.copy()
        px[61, 37, 1] = i                          # one byte, outside any strided sample
        frames.append(image(px, 'rgb8'))
    c = feed(make_check('bottomCamera', tmp_path, record=False), frames)
    assert c.result_values().longest_identical_run == 1 and c.failure_reasons() == []


def test_frozen_frames_late_in_the_window_are_found(tmp_path):
    same = image(pattern(160, 120, 99), 'rgb8')
    c = feed(make_check('frontCamera', tmp_path, record=False), good(40) + [same] * 6)
    assert any(r.startswith('image frozen: 6 identical consecutive frames from t = 4 s to the end '
                            'of the window') for r in c.failure_reasons()), c.failure_reasons()
    # a run that ends before the window does says where it ends
    c = feed(make_check('frontCamera', tmp_path, record=False), good(40) + [same] * 6 + good(3))
    assert any(r.startswith('image frozen: 6 identical consecutive frames from t = 4 s to t = 4.5 s')
               for r in c.failure_reasons()), c.failure_reasons()


@pytest.mark.parametrize('encoding', ['rgb8', 'bgr8', 'rgba8', 'bgra8', 'mono8'])
def test_eight_bit_encodings_are_read_in_place_with_the_same_statistics(tmp_path, encoding):
    px = pattern(160, 120, 3)
    if encoding in ('rgba8', 'bgra8'):
        px = np.dstack([px, np.zeros((120, 160), np.uint8)])     # alpha 0 must not darken the image
    elif encoding == 'mono8':
        px = px[:, :, 1]
    c = feed(make_check('frontCamera', tmp_path, record=False, expect={'encoding': encoding}),
             [image(px, encoding)] * 2)
    assert c.failure_reasons() == [] and c.converted == 2
    colour = px[:, :, :3] if px.ndim == 3 else px
    assert abs(c.result_values().brightness_mean.mean - colour[::8, ::8].mean()) < 0.01
    assert abs(c.result_values().brightness_spread.mean - colour[::8, ::8].std()) < 0.01


def test_decode_reads_the_wire_format_like_genpy_without_copying_the_pixels(tmp_path):
    import struct

    from sensor_msgs.msg import Image
    msg = image(pattern(160, 120, 4), 'rgb8')
    msg.header.seq, msg.header.frame_id = 42, 'CameraTop_optical_frame'
    msg.header.stamp.secs, msg.header.stamp.nsecs = 1700000000, 123456789
    raw = serialized(msg)
    c = make_check('frontCamera', tmp_path, record=False)
    ours, genpy = c.decode(raw), Image().deserialize(raw)
    for field in ('height', 'width', 'encoding', 'is_bigendian', 'step'):
        assert getattr(ours, field) == getattr(genpy, field), field
    assert ours.header.frame_id == genpy.header.frame_id and ours.header.seq == 42
    assert ours.header.stamp == genpy.header.stamp and ours.header.stamp.to_sec() == genpy.header.stamp.to_sec()
    assert bytes(ours.data) == genpy.data and isinstance(ours.data, memoryview)
    with pytest.raises(struct.error):
        c.decode(raw[:30])                         # cut inside the header: "could not be decoded"
    assert len(c.decode(raw[:-5]).data) == len(raw) - 5 - (len(raw) - len(genpy.data))   # short data stays short


def test_black_in_most_frames_fails_and_in_few_frames_warns(tmp_path):
    black = [image(np.zeros((120, 160, 3), np.uint8), 'rgb8') for _ in range(6)]
    c = feed(make_check('frontCamera', tmp_path, record=False), black + good(4))
    assert any(r.startswith('image black (mean brightness below 5) in 6 of 10 frames') for r in c.failure_reasons())
    c = feed(make_check('frontCamera', tmp_path, record=False), black[:2] + good(8))
    assert not any('black' in r for r in c.failure_reasons())
    assert 'image black (mean brightness below 5) in 2 of 10 frames' in c.warning_reasons()


def test_constant_grey_image_fails_as_constant(tmp_path):
    grey = [image(np.full((120, 160, 3), 128, np.uint8), 'rgb8') for _ in range(4)]
    c = feed(make_check('frontCamera', tmp_path, record=False), grey)
    assert any('image constant (pixel spread below 2) in 4 of 4 frames' in r for r in c.failure_reasons())
    assert c.result_values().frames_constant == 4 and c.result_values().frames_black == 0


def test_stereo_reports_two_views_and_fails_identical_halves(tmp_path):
    def pair(i, same):
        view = pattern(160, 90, i)
        return image(np.concatenate([view, view if same else np.roll(view, 5, axis=1)], axis=1), 'rgb8')
    c = feed(make_check('stereoCamera', tmp_path, record=False), [pair(i, False) for i in range(4)])
    assert c.failure_reasons() == []
    assert asdict(c.result_values().stereo) == {'width': 320, 'height': 90, 'view_width': 160,
                                                'view_height': 90, 'identical_views': 0}
    c = feed(make_check('stereoCamera', tmp_path, record=False), [pair(i, True) for i in range(4)])
    assert 'stereo left and right views are identical in 4 of 4 messages' in c.failure_reasons()


def test_frames_are_posted_to_the_viewer_service(tmp_path):
    from pepper_interface_tests.media.viewer import Viewer
    viewer = Viewer()            # not created through Viewer.create: no window is opened here
    feed(make_check('frontCamera', tmp_path, record=False, services=Services(viewer=viewer)), good(5))
    assert viewer.posted == {'frontCamera': 5}
    assert viewer._latest['frontCamera'].shape == (120, 160, 3)


# ---------------------------------------------------------------- through sensorTest

def test_sensor_test_judges_and_records_cameras(module_master, tmp_path):
    with Publishers(module_master, tmp_path) as pubs:
        pubs.add('frontCamera', 'camera', '--rate', 12, '--count', 24)
        pubs.add('bottomCamera', 'camera', '--rate', 10, '--fault', 'frozen')
        pubs.add('stereoCamera', 'stereo', '--rate', 10)
        pubs.add('realsenseRGBCamera', 'camera', '--rate', 10, '--fault', 'wrong_step')
        # scenario: the four publishers above, not a list of the colour cameras
        done, res = sensor_test(module_master, tmp_path, ['frontCamera', 'bottomCamera', 'stereoCamera',
                                                          'realsenseRGBCamera'], duration=5,
                                expect={'frontCamera': {'max_gap_factor': 5}})
        published = pubs.stop()
    assert res is not None, explain(done, res)
    s = res['by_name']
    assert done.returncode == 1, explain(done, res)
    front = s['frontCamera']
    assert front['verdict'] == 'PASS', explain(done, res)
    assert published['frontCamera'] == 24
    assert front['messages'] == 24, explain(done, res)
    out = os.path.join(str(tmp_path), 'out')
    frames, w, h, fps = video_info(os.path.join(out, 'frontCameraOutput.mp4'))
    assert frames == 24 and (w, h) == (320, 240)
    assert video_rate_is_the_stream_rate(fps, front), (fps, front['rate_hz'])   # measured, not a constant
    assert front['values']['video']['frames_written'] == 24
    assert video_codec(os.path.join(out, 'frontCameraOutput.mp4')) in ('h264', 'mpeg4')
    assert front['artifacts'] == {'video': 'frontCameraOutput.mp4', 'first_frame': 'frontCamera_first.jpg',
                                  'last_frame': 'frontCamera_last.jpg'}
    assert os.path.getsize(os.path.join(out, 'frontCamera_last.jpg')) > 1000
    assert ['Image Width', '320'] in front['fields'] and ['Step', '960'] in front['fields']

    bottom = s['bottomCamera']
    assert bottom['verdict'] == 'FAIL'
    assert any(r.startswith('image frozen: ') for r in bottom['reasons']), bottom['reasons']

    stereo = s['stereoCamera']
    assert stereo['verdict'] == 'PASS', explain(done, res)
    assert stereo['values']['stereo']['view_width'] == 320 and stereo['values']['stereo']['width'] == 640

    rs = s['realsenseRGBCamera']
    assert rs['verdict'] == 'FAIL'
    assert any('is not the data length' in r for r in rs['reasons']), rs['reasons']
    assert not os.path.exists(os.path.join(out, 'realsenseRGBOutput.mp4'))  # nothing valid to record
    assert not [f for f in os.listdir(out) if f.startswith('.')]          # no temporary files left
