"""Cameras (sensor_msgs/Image): front, bottom, stereo and RealSense colour.

Per message (counted FAIL reasons):
  * layout: `step * height == len(data)` and `step >= width * bytes per pixel` of the encoding;
    a message with a broken layout is not converted further;
  * encoding, width and height as expected (`encoding`, `width`, `height`, when configured);
  * conversion: an encoding of the table (media/encodings.py: rgb8, bgr8, mono8, yuv422,
    16UC1, mono16, ...) is read as a numpy view over the message's bytes (no copy, no colour
    conversion) and brought to 8 bits there (a 16-bit image on its own range: the bits its
    stream's brightest pixel so far fills, so an infrared image filling 10 bits is not black);
    any other encoding goes through cv_bridge to BGR, and a conversion error is counted,
    never raised;
  * stereo (stereoCamera, or `stereo: true`): an even width (two views of width/2 side by
    side) and left and right views that are not identical.
Over the window (FAIL at the end):
  * black / constant: brightness mean below `min_brightness` ("black") or pixel standard
    deviation below `min_spread` ("constant") in more than `bad_frame_share` of the frames
    (default 0.5; fewer bad frames are a warning: a camera may start dark while its exposure
    settles); an image that turns black partway and stays black to the end of the window, for
    at least `frozen_frames` frames and 1 s, fails from that time whatever its share ("image
    black from t = 4.1 s to the end of the window");
  * frozen: `frozen_frames` (default 5) or more identical consecutive frames, saying from when
    to when. Pepper can send the same frame twice at low rates, so this must stay above 2.
Cost: brightness and spread use every 8th row and column (4,800 pixels of a 640x480 frame);
the frozen test compares the whole image data with the previous frame's bytes (exact; a
memcmp that stops at the first differing byte, so a changing image costs next to nothing);
the video is encoded by the recorder's ffmpeg, fed the raw bytes (recording.py).
Artifacts: `video` (the catalog's mp4 name), `first_frame`, `last_frame` (JPEG).
"""
import math
import os
import struct
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Tuple, Type, TypeVar

import numpy as np

from ..media import encodings
from ..media.recording import VideoRecorder, save_jpeg, to_bgr
from ..sources.cdr_fast import Ros2Image
from .base import Acc, Check, StuckRun, TrailingRun, fmt, same_bytes
from .values import Point
from .values.camera import CameraValues, ImageValues, Stereo, VideoSummary
from .wear import focus_and_noise

if TYPE_CHECKING:
    import genpy

    from ..plan.expectations import CameraExpect, ImageExpect
    from ..plan.settings import SensorPlan
    from .base import RunContext

SERIES_MAX = 2000
V = TypeVar('V', bound=ImageValues)   # an image family's values
_U32 = struct.Struct('<I')
_HEADER = struct.Struct('<3I')       # seq, stamp secs, stamp nsecs
_SIZE = struct.Struct('<2I')         # height, width
_STEP = struct.Struct('<BI')         # is_bigendian, step
STRIDE = 8        # statistics sample every 8th row and column
# s between two frames whose sharpness and noise are measured (sensors/wear.py, about 1 ms a VGA
# frame): one a second, 10 over a 10 s window, whatever the rate (their means are the drift's;
# a still robot's frames differ by their noise, which each frame's 76,800 grey pixels average)
WEAR_PERIOD = 1.0

def _string(view, pos):
    """(position after, text) of the length-prefixed UTF-8 string at `pos`."""
    (length,) = _U32.unpack_from(view, pos)
    end = pos + 4 + length
    if end > len(view):
        raise struct.error('string runs past the end of the message')
    return end, bytes(view[pos + 4:end]).decode('utf-8', 'replace')


# glibc malloc settings (mallopt) for a process that receives image streams. rospy allocates
# fresh buffers for every message (the recv() chunks, the message's bytes); with glibc's
# defaults a freed frame-sized buffer goes back to the kernel (an mmap of its own, or the free
# top of a thread's arena beyond its small pad) and the next message faults its pages in
# again. Measured with the benchmark (docs/media.md): 347,000 page faults and 1.36 s of system
# CPU per recording round, about 67,000 and 0.94 s with these settings (sensorTest -0.4 to
# -0.5 s, with recording on or off); with a 64 MB pad the saving is the same but sensorTest's
# peak RSS grew by 30 MB, with 8 MB it did not.
M_TRIM_THRESHOLD, M_TOP_PAD, M_MMAP_THRESHOLD = -1, -2, -3
MALLOC_SETTINGS = ((M_MMAP_THRESHOLD, 32 << 20),    # glibc's maximum: no mmap of its own per frame
                   (M_TRIM_THRESHOLD, 16 << 20),    # the main heap keeps up to 16 MB free
                   (M_TOP_PAD, 8 << 20))            # each arena keeps 8 MB free (a few frames)
_malloc_tuned: List[bool] = []


def keep_freed_memory() -> None:
    """Apply MALLOC_SETTINGS once per process; nothing where the C library is not glibc."""
    if _malloc_tuned:
        return
    _malloc_tuned.append(True)
    try:
        import ctypes
        mallopt = ctypes.CDLL(None).mallopt
    except (OSError, AttributeError):
        return
    for param, value in MALLOC_SETTINGS:
        mallopt(param, value)


class ImageCheck(Check):
    """What colour and depth cameras share: layout checks, recording, viewer, artifacts."""
    expect: 'ImageExpect'
    # rospy's recv() size (bytes read per call). Measured on this machine with the benchmark's
    # streams (docs/media.md, "Benchmark"): 256 KB and 64 KB cost the same, 1 MB about 35 % more
    # CPU per receive thread and the often-quoted 2**24 about 50 % more: a recv() buffer above
    # glibc's mmap threshold is mapped, page-faulted and unmapped afresh on every call. With
    # MALLOC_SETTINGS (no such threshold below 32 MB) 1 MB was measured again: no better.
    buff_size = 1 << 18
    queue_seconds = 2.0
    prepare_frame: Any = None   # (frame, pix_fmt) -> (uint8 frame, ffmpeg pix_fmt), in the video writer
    colour_map: Any = None      # the same for the JPEGs of the first and last frame (default: prepare_frame)

    def __init__(self, plan: 'SensorPlan', ctx: 'RunContext') -> None:
        super().__init__(plan, ctx)
        keep_freed_memory()
        rate = self.expect.rate or (1.0, 35.0)   # no band: size the queue for 35 fps
        self.queue_size = max(10, int(round(float(rate[1]) * self.queue_seconds)))
        self.bridge = None
        # (width, height, encoding, step) of the first message
        self.geometry: Optional[Tuple[int, int, str, int]] = None
        video = plan.sensor.video
        self.recording = getattr(ctx.options, 'record', None) is not False and bool(video)
        self.recorder: Optional[VideoRecorder] = None
        if self.recording and video:
            self.recorder = VideoRecorder(os.path.join(ctx.output_dir, video),
                                          fallback_fps=self.expect.nominal or 10.0,
                                          max_fps=float(rate[1]), prepare=self.prepare_frame,
                                          preview=self.colour_map)
        self.viewer = ctx.services.viewer
        self.converted = 0
        self.top = 0            # a 16-bit stream's brightest value so far (its own range)
        self.sizes: Dict[Tuple[int, int, str], int] = {}   # (w, h, encoding) -> count, when it changes
        self.video: Optional[VideoSummary] = None          # the recorder's summary, once closed

    def decode(self, buff: bytes) -> 'genpy.Message':
        """sensor_msgs/Image from its serialized bytes with `data` a memoryview into `buff`:
        genpy's deserialize copies the pixels (about 0.1-0.2 ms for a 640x480 frame), this
        does not. The wire format is ROS's (header, height, width, encoding, is_bigendian,
        step, data; strings and arrays prefixed by a uint32 length). A short buffer raises
        struct.error as genpy does; a short data array stays short (the layout check says so).
        A ROS 2 recording's frame comes as a Ros2Image (sources/cdr_fast.py), its fields read
        from the CDR bytes and its pixels a view of them: the same message, no copy."""
        from genpy import Time

        from ..sources.messages import message_class
        if type(buff) is Ros2Image:        # a ROS 2 recording's frame, read in place
            return buff.message()
        view = memoryview(buff)
        msg = message_class('sensor_msgs/Image')()
        seq, secs, nsecs = _HEADER.unpack_from(view, 0)
        pos, text = _string(view, 12)
        msg.header.seq, msg.header.stamp, msg.header.frame_id = seq, Time(secs, nsecs), text
        msg.height, msg.width = _SIZE.unpack_from(view, pos)
        pos, msg.encoding = _string(view, pos + 8)
        msg.is_bigendian, msg.step = _STEP.unpack_from(view, pos)
        (length,) = _U32.unpack_from(view, pos + 5)
        msg.data = view[pos + 9:pos + 9 + length]
        return msg

    def fields(self, msg: 'genpy.Message') -> List[Tuple[str, Any]]:
        return [('Image Width', msg.width), ('Image Height', msg.height),
                ('Encoding', msg.encoding), ('Step', msg.step)]

    def start(self) -> None:
        # cv_bridge (and OpenCV) are imported only for an encoding that is not read in place
        # (media/encodings.py): they cost more CPU to import than a window of checks
        # a video of an earlier run must not pass for this one's
        if self.recorder is not None and os.path.exists(self.recorder.path):
            os.unlink(self.recorder.path)

    # ---- per message ---------------------------------------------------------------------
    def check_layout(self, msg: 'genpy.Message') -> bool:
        """Counted failures for a message whose bytes do not match its declared geometry.
        Returns False when the message cannot be converted."""
        key = (msg.width, msg.height, msg.encoding)
        if self.geometry is None:
            self.geometry = (msg.width, msg.height, msg.encoding, msg.step)
            self.ctx.images.setdefault(self.plan.name, (msg.width, msg.height, msg.header.frame_id))
        if key not in self.sizes and self.sizes:
            self.warnings.add('size_change', 'image geometry changed during the window', '%dx%d %s' % key)
        self.sizes[key] = self.sizes.get(key, 0) + 1
        ok = True
        expected = self.expect.encoding
        if expected and msg.encoding != expected:
            self.failures.add('encoding', 'encoding "%s" where "%s" is expected' % (msg.encoding, expected))
        for dim in ('width', 'height'):
            want = getattr(self.expect, dim)
            if want and getattr(msg, dim) != want:
                self.failures.add(dim, '%s %d where %d is expected' % (dim, getattr(msg, dim), want))
        if msg.width == 0 or msg.height == 0:
            self.failures.add('empty', 'empty image (%dx%d)' % (msg.width, msg.height))
            return False
        if msg.step * msg.height != len(msg.data):
            self.failures.add('datalen', 'step x height (%d x %d = %d) is not the data length'
                              % (msg.step, msg.height, msg.step * msg.height), len(msg.data))
            ok = False
        bpp = encodings.bytes_per_pixel(msg.encoding)
        if bpp is None:
            self.failures.add('unknown_enc', 'unknown encoding "%s"' % msg.encoding)
            ok = False
        elif msg.step < msg.width * bpp:
            self.failures.add('step', 'step %d is less than width x bytes per pixel (%d x %d)'
                              % (msg.step, msg.width, bpp), msg.step)
            ok = False
        return ok

    def _bridge(self):
        if self.bridge is None:
            from cv_bridge import CvBridge
            self.bridge = CvBridge()
        return self.bridge

    def convert(self, msg: 'genpy.Message', desired: str) -> Optional[np.ndarray]:
        """cv_bridge conversion; None (and a counted failure) when it fails."""
        try:
            image = self._bridge().imgmsg_to_cv2(msg, desired)
        except Exception as e:   # CvBridgeError, or numpy errors on odd buffers
            text = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
            self.failures.add('convert', 'cv_bridge cannot convert %s to %s' % (msg.encoding, desired), text)
            return None
        self.converted += 1
        return image

    def pixels(self, msg: 'genpy.Message') -> Tuple[Optional[np.ndarray], Optional[str]]:
        """(uint8 array (h, w, channels), ffmpeg pixel format): the table's encodings read in
        place and brought to 8 bits (media/encodings.py; a 16-bit image on its stream's own
        range, `self.top`), else cv_bridge's BGR conversion; (None, None) when it fails."""
        enc = encodings.lookup(msg.encoding)
        if enc is None or enc.dtype == 'f4':
            image = self.convert(msg, 'bgr8')
            return (None, None) if image is None else (image, 'bgr24')
        try:
            raw = encodings.view(msg, enc)
        except ValueError as e:
            self.failures.add('convert', 'cannot read %s' % msg.encoding, str(e))
            return None, None
        if enc.dtype == 'u2':
            self.top = max(self.top, int(raw[::STRIDE, ::STRIDE].max()))
        self.converted += 1
        return encodings.to_8bit(raw, enc, self.top)

    def show_and_record(self, frame: np.ndarray, t: float, pix_fmt: str = 'bgr24') -> None:
        if self.viewer is not None:
            self.viewer.post(self.plan.name, to_bgr(frame, pix_fmt))
        if self.recorder is not None:
            self.recorder.add(frame, t, pix_fmt)

    # ---- end -----------------------------------------------------------------------------
    def finish_media(self) -> None:
        """Close the recorder, write JPEG artifacts, report the recording."""
        rec = self.recorder
        if rec is None:
            if not self.recording and self.plan.sensor.video:
                self.notes.append('recording off')
            return
        summary = rec.close()
        self.video = VideoSummary(**summary)
        for note in rec.notes:
            self.notes.append('video: ' + note)
        if summary['file']:
            self.artifacts['video'] = summary['file']
            self.notes.append('video %s: %d frames, %dx%d, %s, %s fps'
                              % (summary['file'], summary['frames_written'], summary['width'],
                                 summary['height'], summary['codec'], fmt(summary['fps'], 2)))
        if rec.error:
            self.warn(rec.error)
        if rec.dropped:
            self.warn('%d of %d frames not recorded (the video writer fell behind or failed)'
                      % (rec.dropped, rec.received))
        if rec.resized:
            self.warn('%d frames of another size resized to %dx%d for the video'
                      % ((rec.resized,) + tuple(rec.size or (0, 0))))
        for kind, image in (('first_frame', rec.first_frame), ('last_frame', rec.last_frame)):
            if image is None:
                continue
            name = '%s_%s.jpg' % (self.plan.name, kind.split('_')[0])
            if save_jpeg(os.path.join(self.ctx.output_dir, name), *image):
                self.artifacts[kind] = name

    def image_values(self, cls: Type[V], **own: Any) -> V:
        """The family's values (`cls`, an ImageValues) with what every image check measured
        (the first message's geometry, the geometries when it changed, the video) and `own`."""
        w, h, enc, step = self.geometry if self.geometry else (None, None, None, None)
        geometries = {'%dx%d %s' % k: n for k, n in self.sizes.items()} if len(self.sizes) > 1 else None
        return cls(width=w, height=h, encoding=enc, step=step, geometries=geometries, video=self.video, **own)


class CameraCheck(ImageCheck):
    family = 'camera'
    expect: 'CameraExpect'

    def __init__(self, plan: 'SensorPlan', ctx: 'RunContext') -> None:
        super().__init__(plan, ctx)
        self.stereo = self.expect.stereo
        self.min_brightness = self.expect.min_brightness
        self.min_spread = self.expect.min_spread
        self.frozen_frames = self.expect.frozen_frames
        self.bad_share = self.expect.bad_frame_share
        self.brightness, self.spread = Acc(), Acc()
        self.black = self.constant = 0
        # (geometry, data) of the previous frame
        self.last_image: Optional[Tuple[Tuple[int, int, str, int], np.ndarray]] = None
        self.stuck = StuckRun(self.frozen_frames)
        self.black_run = TrailingRun()
        self.same_halves = 0
        self.brightness_series: List[Point] = []
        self.found: Optional[CameraValues] = None
        self.sharpness, self.noise = Acc(), Acc()       # a frame every WEAR_PERIOD s (drift)
        self.wear_at: Optional[float] = None            # when they were last measured

    def settled(self) -> bool:
        return self.count >= self.frozen_frames + 1

    def on_message(self, msg: 'genpy.Message', t: float) -> None:
        if not self.check_layout(msg):
            return
        if self.stereo and msg.width % 2:
            self.failures.add('stereo_odd', 'stereo width %d is odd: not two views side by side' % msg.width)
        image, pix_fmt = self.pixels(msg)
        if image is None or pix_fmt is None:     # both None: not converted
            return
        colour = image[:, :, :3] if image.shape[2] == 4 else image     # alpha is not brightness
        # integer sums (exact; no BLAS call, whose thread pool would spin on every frame)
        small = colour[::STRIDE, ::STRIDE].astype(np.uint32)
        n = small.size
        mean = int(small.sum(dtype=np.uint64)) / n
        std = math.sqrt(max(0.0, int(np.square(small).sum(dtype=np.uint64)) / n - mean * mean))
        self.brightness.add(mean)
        self.spread.add(std)
        if len(self.brightness_series) < SERIES_MAX:
            self.brightness_series.append((round(t, 3), round(mean, 2)))
        bad = None
        if mean < self.min_brightness:
            self.black += 1
            bad = 'black'
        elif std < self.min_spread:
            self.constant += 1
            bad = 'constant'
        self._frozen(msg, t)
        if self.wear_at is None or t - self.wear_at >= WEAR_PERIOD:
            self.wear_at = t
            sharp, noise = focus_and_noise(colour)
            self.sharpness.add(sharp)
            self.noise.add(noise)
        self.black_run.add(bad == 'black', t)
        if self.stereo and not bad and msg.width % 2 == 0:
            half = msg.width // 2
            if np.array_equal(colour[::4, :half:4], colour[::4, half::4]):
                self.same_halves += 1
                self.failures.add('stereo_same', 'stereo left and right views are identical')
        self.show_and_record(image, t, pix_fmt)

    def _frozen(self, msg, t):
        """Identical = the same geometry and byte-for-byte the same data as the previous frame
        (same_bytes: about 900 bytes spread over the frame first, every byte only when they
        match)."""
        geometry = (msg.width, msg.height, msg.encoding, msg.step)
        data = np.frombuffer(msg.data, np.uint8)
        last = self.last_image
        self.stuck.repeat(last is not None and last[0] == geometry and same_bytes(last[1], data), t)
        self.last_image = (geometry, data)

    def finish(self) -> None:
        self.finish_media()
        n = self.converted
        stereo = None
        if self.stereo and self.geometry:
            w, h = self.geometry[0], self.geometry[1]
            stereo = Stereo(w, h, w // 2, h, self.same_halves)
            self.notes.append('Stereo: %dx%d, two views of %dx%d' % (w, h, w // 2, h))
            if w != 2 * (w // 2):
                self.fail('stereo width %d is not twice a view width' % w)
        self.found = self.image_values(
            CameraValues, brightness_mean=self.brightness.spread(2), brightness_spread=self.spread.spread(2),
            frames_black=self.black, frames_constant=self.constant,
            longest_identical_run=self.stuck.longest, stereo=stereo, brightness=list(self.brightness_series),
            sharpness=self.sharpness.spread(4).mean, noise=self.noise.spread(3).mean)
        if not n:
            return
        self.notes.append('Brightness mean %s; spread (std) %s (0-255, every %dth row and column)'
                          % (self.brightness.text(), self.spread.text(), STRIDE))
        if self.top:
            self.notes.append('16-bit image judged on its own range: %d bits (brightest value %d), '
                              'brought to 0-255' % (encodings.bits(self.top), self.top))
        for word, frames, limit_text in (
                ('black', self.black, 'mean brightness below %s' % fmt(self.min_brightness)),
                ('constant', self.constant, 'pixel spread below %s' % fmt(self.min_spread))):
            if not frames:
                continue
            text = 'image %s (%s) in %d of %d frames' % (word, limit_text, frames, n)
            # turned black partway and stayed black: a partial failure, whatever its share
            trailing = self.black_run.since() if word == 'black' else None
            late = trailing and trailing[1] >= self.frozen_frames and trailing[2] >= 1.0
            if late and trailing is not None:
                text = ('image black from t = %s s to the end of the window (%d frames, %s s; '
                        '%s)' % (fmt(trailing[0], 2), trailing[1], fmt(trailing[2], 1), text))
            if late or frames > self.bad_share * n:
                self.fail(text)
            else:
                self.warn(text)
        if self.stuck.reached():
            self.fail('image frozen: %d identical consecutive frames %s (frozen_frames %d)'
                      % (self.stuck.longest, self.stuck.span(), self.frozen_frames))
        elif self.stuck.longest > 1:
            self.notes.append('Longest run of identical frames: %d' % self.stuck.longest)
