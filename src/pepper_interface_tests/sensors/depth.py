"""Depth cameras (sensor_msgs/Image): Pepper's depth camera and the RealSense aligned depth.

Accepted encodings: 16UC1 (and mono16) in millimetres (Pepper, RealSense), 32FC1 in metres
(some simulator builds). Any other encoding is a counted failure "not a depth encoding".
Per message (counted): the layout checks of the cameras (camera.py), the expected encoding
when configured, and "all zero" when a frame has no valid pixel at all.
Over the window (FAIL at the end):
  * valid share: mean share of valid pixels (non-zero and finite) below `min_valid_share`;
  * median depth (median over frames of each frame's median of valid pixels, in metres)
    outside `median_range` [m, m].
Data that cannot be real (reasons in config/sensorExpectations.yaml):
  * frozen: `frozen_frames` identical consecutive images (sampled bytes first, every byte only
    when those match, as the cameras do); the Xtion's depth is noisy at every pixel edge;
  * a single value everywhere: every sampled valid pixel the same depth, in more than half
    of the frames (a real scene has a floor, walls and noise). Checked with the frozen test,
    where `frozen_frames` is set (a sensor with noise): Gazebo's noise-free depth of a wall
    square to the camera is one value everywhere;
  * most of the image outside the camera's `physical_range` [m, m]: in more than half of the
    frames, more than half of the sampled valid pixels beyond what the camera can measure;
  * partial failure: frames with no valid pixel from some time to the end of the window
    (at least 3 frames and 1 s) fail as "depth all zero from t = ..." even when they are
    fewer than the whole window.
Aligned depth (`aligned_to`: the colour sensor; judged when the topic is an aligned one,
a segment `aligned_depth_to_<stream>` as realsense-ros names it): realsense-ros (ros1-legacy,
b14ce43) base_realsense_node.cpp reprojects depth into the colour image with
rs2::align(RS2_STREAM_COLOR) (:1259) and publishes the result under the colour stream's index
(:1708-1718) with a copy of the colour's camera_info (:1955-1965), whose frame_id is the colour
optical frame (:1890); the image's width and height are the aligned frame's (:2375-2382,
:2419-2423): the colour image's. So an aligned depth of another size than its colour stream
is not aligned (realsense-ros PR #2793: 848x480 unaligned depth on the aligned topic beside
640x480 colour): FAIL naming both sizes; a frame_id other than the colour's, where both carry
one, FAILs too. The colour's first image comes from its own window (RunContext.images); when
it has not been seen by the end of this window (not in the run, or later in sequential mode),
a note says the pair was not compared.
Reported: min / median / max depth (m), valid share. The image is a numpy view over the
message's bytes (no copy); the valid share (and so "all zero") counts every pixel, the median,
min and max use every 4th row and column (19,200 pixels of a 640x480 frame).
Video: depth mapped to 8 bits over the fixed range `video_range` [m, m] of the sensor
(default 0-5 m, the same for every frame, not normalised per frame), colour-mapped with
the JET map (near = blue, far = red; MATLAB's formula, as OpenCV's COLORMAP_JET); invalid
pixels are black. The video's frames are made as planar yuv420p in the video writer's thread
(table look-ups: Y per pixel, U and V per 2x2 block; ffmpeg converts nothing), the live view
and the JPEGs get the same colours as packed BGR0 (colour_map).
"""
import math
from typing import TYPE_CHECKING, Dict, List, Optional, Tuple

import numpy as np

from ..media import encodings
from ..media.recording import YUV420P, to_bgr
from .base import Acc, StuckRun, TrailingRun, fmt, same_bytes
from .camera import SERIES_MAX, ImageCheck
from .values import Point
from .values.depth import DepthValues, MedianSpread

if TYPE_CHECKING:
    import genpy

    from ..plan.expectations import DepthExpect
    from ..plan.settings import SensorPlan
    from .base import RunContext

# the depth encodings of the table (media/encodings.py): in millimetres, in metres
MM_ENCODINGS = tuple(e.name for e in encodings.ENCODINGS.values() if e.metres == 0.001)
M_ENCODINGS = tuple(e.name for e in encodings.ENCODINGS.values() if e.metres == 1.0)
STRIDE = 4        # statistics sample every 4th row and column
ALIGNED_PREFIX = 'aligned_depth_to_'    # realsense-ros's aligned topics (base_realsense_node.cpp:989)


def jet_table() -> np.ndarray:
    """0..255 -> packed little-endian BGR0 pixel of the JET colour map (MATLAB's classic
    piecewise-linear jet, which OpenCV's COLORMAP_JET samples: dark blue, blue, cyan, yellow,
    red, dark red), computed with numpy so that recording depth does not import OpenCV."""
    x = np.arange(256) / 255.0

    def ramp(centre):
        return np.round(255 * np.clip(1.5 - np.abs(4 * x - centre), 0, 1)).astype(np.uint32)

    b, g, r = ramp(1.0), ramp(2.0), ramp(3.0)
    return (b | (g << 8) | (r << 16)).astype('<u4')


def yuv_tables(bgr0: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Packed BGR0 pixels -> (Y, packed U | V << 8) in BT.601 limited range, the conversion
    swscale applies to RGB by default (so the video's colours are those ffmpeg would make)."""
    b, g, r = ((bgr0 >> shift) & 0xff for shift in (0, 8, 16))
    y = 16 + (65.481 * r + 128.553 * g + 24.966 * b) / 255
    u = 128 + (-37.797 * r - 74.203 * g + 112.0 * b) / 255
    v = 128 + (112.0 * r - 93.786 * g - 18.214 * b) / 255
    y, u, v = (np.clip(np.rint(c), 0, 255).astype(np.uint16) for c in (y, u, v))
    return y.astype(np.uint8), (u | (v << 8)).astype('<u2')


class DepthCheck(ImageCheck):
    family = 'depth'
    expect: 'DepthExpect'

    def __init__(self, plan: 'SensorPlan', ctx: 'RunContext') -> None:
        super().__init__(plan, ctx)
        lo, hi = self.expect.video_range
        self.video_range = (float(lo), float(hi))
        self.min_valid_share = self.expect.min_valid_share
        self.median_range = self.expect.median_range
        self.share = Acc()
        self.medians: List[float] = []
        self.centre = Acc()         # mean depth of the frame's middle third (drift)
        self.lo = Acc()
        self.hi = Acc()
        self.all_zero = 0
        self.stuck = StuckRun(self.expect.frozen_frames)
        self.last_data: Optional[np.ndarray] = None     # the previous image's bytes
        self.zero_run = TrailingRun()
        self.single = 0             # frames whose sampled valid pixels hold one value
        self.outside = 0            # frames mostly outside physical_range
        self.physical = self.expect.physical_range
        self._lut: Optional[np.ndarray] = None     # millimetres -> packed BGR0 pixel (uint32)
        self._jet: Optional[np.ndarray] = None     # 0..255 -> packed BGR0 pixel
        self._yuv: Dict[str, Tuple[np.ndarray, np.ndarray]] = {}   # 'mm' / 'index' -> (Y table, packed U|V table)
        self.median_series: List[Point] = []
        self.valid_series: List[Point] = []
        self.found: Optional[DepthValues] = None

    def settled(self) -> bool:
        return self.count >= 5

    def _judge_alignment(self) -> None:
        """The aligned depth against the colour image it is aligned to (the docstring above)."""
        colour = self.expect.aligned_to
        topic = self.plan.topic or ''
        if not colour or not any(p.startswith(ALIGNED_PREFIX) for p in topic.split('/')) \
                or self.geometry is None:
            return
        mine = self.ctx.images.get(self.plan.name)
        theirs = self.ctx.images.get(colour)
        if mine is None or theirs is None:
            self.notes.append('aligned depth not compared with %s: no image of it was seen before this '
                              'window ended' % colour)
            return
        (w, h, frame), (cw, ch, cframe) = mine, theirs
        if (w, h) != (cw, ch):
            self.fail('aligned depth is %dx%d but %s, the colour image it is aligned to, is %dx%d: depth '
                      'aligned to colour has the colour image\'s size (the driver is publishing unaligned '
                      'depth on %s; realsense-ros: align_depth)' % (w, h, colour, cw, ch, topic))
        if frame and cframe and frame != cframe:
            self.fail('aligned depth is in frame "%s" but %s, the colour image it is aligned to, in "%s": '
                      'aligned depth carries the colour image\'s frame_id' % (frame, colour, cframe))

    def on_message(self, msg: 'genpy.Message', t: float) -> None:
        if not self.check_layout(msg):
            return
        if msg.encoding in MM_ENCODINGS:
            scale = 0.001
        elif msg.encoding in M_ENCODINGS:
            scale = 1.0
        else:
            self.failures.add('depth_encoding', 'encoding "%s" is not a depth encoding '
                              '(16UC1 or mono16 in mm, 32FC1 in m)' % msg.encoding)
            return
        depth = self.depth_view(msg)
        if depth is None:
            return
        if depth.ndim == 3:
            depth = depth[:, :, 0]
        # valid share over every pixel (a vectorised count, cheap); median, min and max from
        # every STRIDE-th row and column
        valid_all = depth if scale != 1.0 else np.isfinite(depth) & (depth > 0)
        n_valid = int(np.count_nonzero(valid_all))
        share = n_valid / float(depth.size)
        self.share.add(share)
        median = None
        self._frozen(msg, t)
        self.zero_run.add(not n_valid, t)
        if not n_valid:
            self.all_zero += 1
            self.failures.add('all_zero', 'depth image has no valid pixel (all zero or not finite)')
        else:
            sample = depth[::STRIDE, ::STRIDE]
            values = sample[sample > 0] if scale != 1.0 else sample[np.isfinite(sample) & (sample > 0)]
            if not values.size:     # the few valid pixels all fall between the sampled ones
                values = depth[depth > 0] if scale != 1.0 else depth[np.isfinite(depth) & (depth > 0)]
            median = float(np.median(values)) * scale
            self.medians.append(median)
            self._centre(sample, scale)
            v_lo, v_hi = float(values.min()) * scale, float(values.max()) * scale
            self.lo.add(v_lo)
            self.hi.add(v_hi)
            if v_lo == v_hi:
                self.single += 1
            if self.physical is not None:
                lo_mm, hi_mm = self.physical[0] / scale, self.physical[1] / scale
                if v_lo < lo_mm * scale or v_hi > hi_mm * scale:
                    out = int(np.count_nonzero((values < lo_mm) | (values > hi_mm)))
                    if out > values.size / 2:
                        self.outside += 1
        if len(self.valid_series) < SERIES_MAX:
            self.valid_series.append((round(t, 3), round(share, 4)))
            self.median_series.append((round(t, 3), None if median is None else round(median, 4)))
        kind = 'depth_mm' if scale != 1.0 else 'depth_m'
        if self.viewer is not None:
            self.viewer.post(self.plan.name, to_bgr(*self.colour_map(depth, kind)))
        if self.recorder is not None:
            self.recorder.add(depth, t, kind)

    def _centre(self, sample, scale):
        """The mean depth of the valid pixels in the middle third of the frame (rows and
        columns), a fixed region the drift from a baseline compares (outputs/drift.py)."""
        h, w = sample.shape[:2]
        mid = sample[h // 3:h - h // 3, w // 3:w - w // 3]
        ok = mid[mid > 0] if scale != 1.0 else mid[np.isfinite(mid) & (mid > 0)]
        if ok.size:
            self.centre.add(float(ok.mean()) * scale)

    def _frozen(self, msg, t):
        """Identical to the previous image (same_bytes, as the cameras' frozen test)."""
        if self.stuck.limit is None:
            return
        data = np.frombuffer(msg.data, np.uint8)
        self.stuck.repeat(same_bytes(self.last_data, data), t)
        self.last_data = data

    def depth_view(self, msg: 'genpy.Message') -> Optional[np.ndarray]:
        """The depth image as a numpy view over the message's bytes (cv_bridge for anything
        unusual); None (and a counted failure) when it cannot be read."""
        enc = encodings.lookup(msg.encoding)
        if enc is None or enc.metres is None or msg.step % np.dtype(enc.dtype).itemsize:
            return self.convert(msg, 'passthrough')
        self.converted += 1
        return encodings.view(msg, enc)[:, :, 0]

    def _millimetres(self, depth, kind):
        return kind == 'depth_mm' and depth.dtype.kind == 'u' and depth.dtype.itemsize == 2

    def _mm_table(self):
        """Every 16-bit millimetre value -> packed BGR0 pixel (JET over video_range, 0 black)."""
        if self._lut is None:
            lo, hi = self.video_range
            metres = np.arange(65536, dtype=np.float64) * 0.001
            grey = np.clip((metres - lo) / (hi - lo) * 255.0, 0, 255).astype(np.uint8)
            lut = self._jet_table()[grey]
            lut[0] = 0          # invalid: black (assigned whole: the viewer may call this too)
            self._lut = lut
        return self._lut

    def _jet_table(self):
        if self._jet is None:
            self._jet = jet_table()
        return self._jet

    def _grey_index(self, depth, kind):
        """Metres (or non-16-bit millimetres) -> uint16 index: 0 invalid, 1 + 0..255 over
        video_range."""
        lo, hi = self.video_range
        metres = depth.astype(np.float32) * np.float32(0.001 if kind == 'depth_mm' else 1.0)
        invalid = ~np.isfinite(metres) | (metres <= 0)
        index = np.clip((np.nan_to_num(metres) - lo) * (255.0 / (hi - lo)), 0, 255).astype(np.uint16) + 1
        index[invalid] = 0
        return index

    def colour_map(self, depth: np.ndarray, kind: str) -> Tuple[np.ndarray, str]:
        """Depth -> (BGR0 uint8 frame, 'bgr0') for the live view (and the video of an odd
        size): fixed range video_range to 0..255, JET colour map, invalid pixels black."""
        if self._millimetres(depth, kind):
            packed = np.take(self._mm_table(), depth)
        else:
            packed = np.take(np.concatenate([[0], self._jet_table()]).astype('<u4'),
                             self._grey_index(depth, kind))
        return packed.view(np.uint8).reshape(packed.shape + (4,)), 'bgr0'

    def prepare_frame(self, depth: np.ndarray, kind: str) -> Tuple[np.ndarray, str]:
        """Depth -> the video's frame, in the video writer's thread: the colours of colour_map
        written straight as planar yuv420p (Y from every pixel, U and V from every 2nd row and
        column, as swscale's point sampling): about 0.4 ms for 640x480 and 40 % of the bytes
        of BGR0, and ffmpeg converts nothing (measured: -0.15 s of encoder CPU per 300 VGA
        frames; the encoder costs the same for these colours as for grey). Odd sizes: BGR0."""
        h, w = depth.shape[:2]
        if h % 2 or w % 2:
            return self.colour_map(depth, kind)
        if self._millimetres(depth, kind):
            key, index = 'mm', depth
        else:
            key, index = 'index', self._grey_index(depth, kind)
        if key not in self._yuv:
            table = self._mm_table() if key == 'mm' else np.concatenate([[0], self._jet_table()]).astype('<u4')
            self._yuv[key] = yuv_tables(table)
        y_table, uv_table = self._yuv[key]
        out = np.empty(w * h * 3 // 2, np.uint8)
        q = w * h // 4
        np.take(y_table, index, out=out[:w * h].reshape(h, w), mode='clip')   # clip: unbuffered
        uv = np.take(uv_table, index[::2, ::2], mode='clip').view(np.uint8)
        out[w * h:w * h + q].reshape(h // 2, w // 2)[...] = uv[:, 0::2]
        out[w * h + q:].reshape(h // 2, w // 2)[...] = uv[:, 1::2]
        return out.reshape(h * 3 // 2, w), YUV420P

    def finish(self) -> None:
        self.finish_media()
        converted = bool(self.converted)    # the rest is measured on converted frames only
        median = float(np.median(self.medians)) if self.medians else None
        depth_m = MedianSpread(round(self.lo.lo or 0.0, 4) if self.lo.n else None,
                               round(median, 4) if median is not None else None,
                               round(self.hi.hi or 0.0, 4) if self.hi.n else None)
        self.found = self.image_values(
            DepthValues, video_range_m=list(self.video_range), frames_all_zero=self.all_zero,
            valid_share=self.share.spread(4) if converted else None, depth_m=depth_m if converted else None,
            longest_identical_run=self.stuck.longest if converted else None,
            centre_depth_m=self.centre.spread(4).mean,
            median_depth_m=list(self.median_series), valid_series=list(self.valid_series))
        self._judge_alignment()
        if not converted:
            return
        mean_share = self.share.total / self.share.n if self.share.n else 0.0
        if median is not None:
            self.notes.append('Depth min %s, median %s, max %s m; valid pixels %.1f%% (mean)'
                              % (fmt(self.lo.lo, 3), fmt(median, 3), fmt(self.hi.hi, 3), 100 * mean_share))
        frozen = self.stuck.finding('frames', 'frozen_frames')
        if frozen:
            self.fail('depth image frozen: ' + frozen)
        if self.all_zero == self.converted:
            self.fail('depth all zero: no valid pixel in any of the %d frames' % self.converted)
            return
        trailing = self.zero_run.since()
        if trailing and trailing[1] >= 3 and trailing[2] >= 1.0:
            self.fail('depth all zero from t = %s s to the end of the window (%d frames, %s s)'
                      % (fmt(trailing[0], 2), trailing[1], fmt(trailing[2], 1)))
        n = self.converted - self.all_zero
        if self.stuck.limit is not None and self.single > n / 2.0:
            self.fail('depth image holds a single value everywhere in %d of %d frames (a real '
                      'scene has a floor, walls and noise)' % (self.single, n))
        if self.physical is not None and self.outside > n / 2.0:
            self.fail('most of the depth image outside the camera\'s physical range [%s, %s] m '
                      'in %d of %d frames' % (fmt(self.physical[0]), fmt(self.physical[1]),
                                              self.outside, n))
        if self.min_valid_share is not None and mean_share < float(self.min_valid_share):
            self.fail('only %.1f%% of the pixels are valid (min_valid_share %s%%)'
                      % (100 * mean_share, fmt(100 * float(self.min_valid_share), 1)))
        if self.median_range and median is not None:
            lo, hi = float(self.median_range[0]), float(self.median_range[1])
            if not (lo <= median <= hi) or not math.isfinite(median):
                self.fail('median depth %s m outside median_range [%s, %s] m'
                          % (fmt(median, 3), fmt(lo), fmt(hi)))
