"""Image encodings in one table: how each is read, brought to 8 bits and rendered.

The camera and depth checks (sensors/camera.py, sensors/depth.py), the video recorder's input,
the motion check's head witnesses (motion/witnesses.py) and the emulator's image publishers
(emulator/publishers.py) look an encoding up here; a new encoding is one row. The names and
layouts are ROS's (sensor_msgs/image_encodings.h); an encoding not in the table goes through
cv_bridge where a check can still use it (bytes_per_pixel, a counted conversion failure).

Bringing a 16-bit image to 8 bits (`to_8bit`) uses the stream's own range, not the type's:
the bits its brightest pixel so far fills (at least 8). A 16-bit infrared image whose pixels
fill 10 bits (0-1023) is shifted by 2, so that the content rules (black, constant, focus,
noise: docs/checks.md) and the video see it as an 8-bit camera's picture; judged on the
type's 0-65535 it would be a black frame. A frame of zeros is still black, and two equal
frames are still equal byte for byte (the frozen rule reads the message's own bytes).
"""
from typing import Any, Dict, NamedTuple, Optional, Tuple

import numpy as np


class Encoding(NamedTuple):
    name: str
    dtype: str                  # numpy type of one channel: 'u1', 'u2', 'f4'
    channels: int               # values per pixel in the message
    pix_fmt: str                # ffmpeg pixel format of the 8-bit frame made of it (to_8bit)
    # metres per unit when the encoding carries depth (0.001: millimetres), else None
    metres: Optional[float] = None
    # the emulator's picture for a camera-family stream of this encoding (scene.py): 'colour'
    # (the room in colour) or 'infrared' (the room's grey as an IR camera sees it, 10 bits)
    render: str = 'colour'
    # the label the emulator's wrong_encoding fault puts on these bytes (a plausible mistake)
    mislabel: str = ''

    @property
    def bytes_per_pixel(self) -> int:
        return np.dtype(self.dtype).itemsize * self.channels


ENCODINGS: Dict[str, Encoding] = {e.name: e for e in (
    Encoding('rgb8', 'u1', 3, 'rgb24', mislabel='bgr8'),
    Encoding('bgr8', 'u1', 3, 'bgr24', mislabel='rgb8'),
    Encoding('rgba8', 'u1', 4, 'rgba', mislabel='bgra8'),
    Encoding('bgra8', 'u1', 4, 'bgra', mislabel='rgba8'),
    Encoding('8UC3', 'u1', 3, 'bgr24'),
    Encoding('8UC4', 'u1', 4, 'bgra'),
    Encoding('mono8', 'u1', 1, 'gray', mislabel='mono16'),
    Encoding('8UC1', 'u1', 1, 'gray'),
    # YUV 4:2:2 (UYVY: U Y0 V Y1 per two pixels): the luma bytes make the 8-bit grey
    Encoding('yuv422', 'u1', 2, 'gray', mislabel='rgb8'),
    # depth in millimetres (naoqi_driver, the RealSense, Gazebo's openni_kinect), or an
    # infrared image in the camera family (naoqi_driver camera.cpp:215-224)
    Encoding('16UC1', 'u2', 1, 'gray', metres=0.001, render='infrared', mislabel='32FC1'),
    Encoding('mono16', 'u2', 1, 'gray', metres=0.001, render='infrared', mislabel='16UC1'),
    Encoding('32FC1', 'f4', 1, 'gray', metres=1.0, mislabel='16UC1'),
)}
# the other encodings of sensor_msgs/image_encodings.h a message may carry, by bytes per pixel
# (the layout check needs only that; nothing here decodes them)
OTHER_BYTES_PER_PIXEL = {
    'rgb16': 6, 'bgr16': 6, 'rgba16': 8, 'bgra16': 8, '16SC1': 2, '32SC1': 4, '64FC1': 8,
    'uyvy': 2, 'yuyv': 2, 'bayer_rggb8': 1, 'bayer_bggr8': 1, 'bayer_gbrg8': 1, 'bayer_grbg8': 1,
}


def lookup(name: str) -> Optional[Encoding]:
    return ENCODINGS.get(name)


def bytes_per_pixel(name: str) -> Optional[int]:
    """Bytes per pixel of an encoding: the table's, then cv_bridge's; None when unknown."""
    e = ENCODINGS.get(name)
    if e is not None:
        return e.bytes_per_pixel
    if name in OTHER_BYTES_PER_PIXEL:
        return OTHER_BYTES_PER_PIXEL[name]
    try:
        from cv_bridge import CvBridge
        dtype, channels = CvBridge().encoding_to_dtype_with_channels(name)
        return np.dtype(dtype).itemsize * channels
    except Exception:
        return None


def view(msg: Any, enc: Encoding) -> np.ndarray:
    """The image of a sensor_msgs/Image as a numpy view over its bytes (no copy): (h, w,
    channels) of the encoding's type, in its byte order. The layout (step, data length) must
    have been checked; ValueError when the bytes do not fit."""
    size = np.dtype(enc.dtype).itemsize
    dtype = np.dtype(('>' if msg.is_bigendian else '<') + enc.dtype) if size > 1 else np.dtype(enc.dtype)
    if msg.step % size:
        raise ValueError('step %d is not a whole number of %d-byte values' % (msg.step, size))
    rows = np.frombuffer(msg.data, dtype, msg.step * msg.height // size).reshape(msg.height, msg.step // size)
    return rows[:, :msg.width * enc.channels].reshape(msg.height, msg.width, enc.channels)


def bits(top: int) -> int:
    """The bits a stream's brightest value fills, at least 8 (a 16-bit image's own range)."""
    return max(8, int(top).bit_length())


def to_8bit(image: np.ndarray, enc: Encoding, top: int = 0) -> Tuple[np.ndarray, str]:
    """(uint8 (h, w, c), ffmpeg pixel format) of an image from `view`: 8-bit images as they
    are (a view), yuv422 its luma; a 16-bit image shifted down to 8 bits from the `top` value
    of its stream so far (its own range, `bits`)."""
    if enc.dtype == 'u1':
        if enc.name == 'yuv422':
            return image[:, :, 1:2], enc.pix_fmt
        return image, enc.pix_fmt
    if enc.dtype == 'u2':
        shift = bits(top) - 8
        return (image >> shift).astype(np.uint8), enc.pix_fmt
    raise ValueError('%s is not brought to 8 bits here (a depth encoding: sensors/depth.py)' % enc.name)


def full_scale(enc: Encoding) -> float:
    """The largest value of the encoding's type (a dimmed or brightened image is clipped to it)."""
    kind = np.dtype(enc.dtype)
    return float(np.iinfo(kind).max) if kind.kind in 'ui' else float('inf')
