"""The image-encoding table (media/encodings.py): each row reads its bytes in place, and the camera
check judges a 16-bit image on its own range (an infrared image filling 10 bits is not black;
a frame of zeros still is), with real serialized messages."""
import numpy as np
import pytest

from check_feed import feed, wire
from fake_pepper import image
from media_tools import make_check
from pepper_interface_tests.media import encodings
from pepper_interface_tests.media.encodings import ENCODINGS

SEVEN = ('rgb8', 'bgr8', 'mono8', 'yuv422', '16UC1', '32FC1', 'mono16')


def test_the_seven_encodings_are_rows_with_the_layout_of_image_encodings_h():
    assert set(SEVEN) <= set(ENCODINGS)
    assert {n: ENCODINGS[n].bytes_per_pixel for n in SEVEN} == {
        'rgb8': 3, 'bgr8': 3, 'mono8': 1, 'yuv422': 2, '16UC1': 2, '32FC1': 4, 'mono16': 2}
    for e in ENCODINGS.values():       # the emulator's wrong label is another real encoding
        assert not e.mislabel or (e.mislabel in ENCODINGS and e.mislabel != e.name), e
    assert encodings.bytes_per_pixel('bayer_rggb8') == 1 and encodings.bytes_per_pixel('nonsense') is None


@pytest.mark.parametrize('name', SEVEN)
def test_each_row_reads_its_bytes_in_place(name):
    e = ENCODINGS[name]
    h, w = 4, 6
    values = (np.arange(h * w * e.channels) * 37 % 1000).astype(e.dtype).reshape(h, w, e.channels)
    padded = np.zeros((h, w * e.bytes_per_pixel + 8), np.uint8)     # a step with padding
    padded[:, :w * e.bytes_per_pixel] = values.view(np.uint8).reshape(h, -1)
    msg = wire(image(padded, name, step=padded.shape[1], width=w, height=h))
    got = encodings.view(msg, e)
    assert got.shape == (h, w, e.channels) and np.array_equal(got, values)
    if e.dtype != 'f4':
        eight, pix_fmt = encodings.to_8bit(got, e, int(values.max()))
        assert eight.dtype == np.uint8 and eight.shape[:2] == (h, w) and pix_fmt


def test_a_16_bit_image_is_brought_to_8_bits_on_its_own_range():
    e = ENCODINGS['16UC1']
    ten_bit = np.full((2, 2, 1), 1023, np.uint16)
    assert encodings.bits(1023) == 10 and encodings.bits(3) == 8
    assert encodings.to_8bit(ten_bit, e, 1023)[0].max() == 255
    assert encodings.to_8bit(ten_bit // 4, e, 1023)[0].max() == 63     # a quarter as bright
    assert encodings.to_8bit(ten_bit, e, 65535)[0].max() == 3          # on the type's range: black


def infrared(i, w=320, h=240, top=1023):
    """A 16UC1 infrared frame filling 10 bits: a gradient with a moving bright disc."""
    y, x = np.mgrid[0:h, 0:w]
    px = (200 + 500 * x / (w - 1) + 100 * np.sin(y / 15.0)).astype(np.uint16)
    cx = int(w * (0.2 + 0.6 * (i % 40) / 40.0))
    px[(x - cx) ** 2 + (y - h // 2) ** 2 < (h // 6) ** 2] = top
    return image(px, '16UC1', frame_id='CameraDepth_optical_frame')


def test_the_camera_check_passes_a_10_bit_infrared_image_and_fails_a_black_one(tmp_path):
    """16UC1 in the camera family: read in place (no cv_bridge failure), judged on 10 bits."""
    expect = {'encoding': '16UC1', 'frame_id': None, 'width': None, 'height': None}
    c = feed(make_check('frontCamera', tmp_path, record=False, expect=expect), [infrared(i) for i in range(12)])
    j = c.judgement()
    assert j.reasons == [] and c.converted == 12, j.reasons
    assert c.found.brightness_mean.mean > 60, c.found.brightness_mean      # 8-bit mean of a 10-bit image
    assert any('own range: 10 bits' in n for n in c.notes), c.notes
    black = [image(np.zeros((240, 320), np.uint16), '16UC1') for _ in range(12)]
    c = feed(make_check('frontCamera', tmp_path, record=False, expect=expect), black)
    assert any('image black' in r for r in c.judgement().reasons), c.judgement().reasons


def test_a_yuv422_image_is_judged_on_its_luma(tmp_path):
    h, w = 120, 160
    frames = []
    for i in range(8):
        uyvy = np.zeros((h, w, 2), np.uint8)
        uyvy[:, :, 0] = 128
        uyvy[:, :, 1] = (np.arange(w) * 255 // w + 3 * i).astype(np.uint8)       # luma ramp
        frames.append(image(uyvy.reshape(h, w * 2), 'yuv422', width=w, height=h))
    expect = {'encoding': 'yuv422', 'frame_id': None, 'width': None, 'height': None}
    c = feed(make_check('frontCamera', tmp_path, record=False, expect=expect), frames)
    assert c.judgement().reasons == [] and c.converted == 8
    assert 120 < c.found.brightness_mean.mean < 140, c.found.brightness_mean
