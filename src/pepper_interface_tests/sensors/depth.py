"""Depth cameras (sensor_msgs/Image): Pepper's depth camera and the RealSense aligned depth.

Accepted encodings: 16UC1 (and mono16) in millimetres (Pepper, RealSense), 32FC1 in metres
(some simulator builds). Any other encoding is a counted failure "not a depth encoding".
Per message (counted): the layout checks of the cameras (camera.py), the expected encoding
when configured, and "all zero" when a frame has no valid pixel at all.
Over the window (FAIL at the end):
  * valid share: mean share of valid pixels (non-zero and finite) below `min_valid_share`;
  * median depth (median over frames of each frame's median of valid pixels, in metres)
    outside `median_range` [m, m].
Reported: min / median / max depth (m), valid share. Statistics use every 2nd row and column.
Video: depth mapped to 8 bits over the fixed range `video_range` [m, m] of the sensor
(default 0-5 m, the same for every frame, not normalised per frame), colour-mapped with
OpenCV's JET map (near = blue, far = red); invalid pixels are black.
"""
import math

import numpy as np

from .base import Acc, fmt
from .camera import SERIES_MAX, ImageCheck

MM_ENCODINGS = ('16UC1', 'mono16')
M_ENCODINGS = ('32FC1',)


class DepthCheck(ImageCheck):
    family = 'depth'

    def __init__(self, plan, ctx):
        super().__init__(plan, ctx)
        lo, hi = self.expect.video_range
        self.video_range = (float(lo), float(hi))
        self.min_valid_share = self.expect.min_valid_share
        self.median_range = self.expect.median_range
        self.share = Acc()
        self.medians = []
        self.lo = Acc()
        self.hi = Acc()
        self.all_zero = 0
        self._lut = None
        self.series['median_depth_m'] = []
        self.series['valid_share'] = []

    def settled(self):
        return self.count >= 5

    def on_message(self, msg, t):
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
        depth = self.convert(msg, 'passthrough')
        if depth is None:
            return
        if depth.ndim == 3:
            depth = depth[:, :, 0]
        sample = depth[::2, ::2]
        if scale == 1.0:
            valid = np.isfinite(sample) & (sample > 0)
        else:
            valid = sample > 0
        n_valid = int(np.count_nonzero(valid))
        share = n_valid / float(sample.size)
        self.share.add(share)
        if not n_valid:
            self.all_zero += 1
            self.failures.add('all_zero', 'depth image has no valid pixel (all zero or not finite)')
            median = None
        else:
            values = sample[valid]
            median = float(np.median(values)) * scale
            self.medians.append(median)
            self.lo.add(float(values.min()) * scale)
            self.hi.add(float(values.max()) * scale)
        if len(self.series['valid_share']) < SERIES_MAX:
            self.series['valid_share'].append((round(t, 3), round(share, 4)))
            self.series['median_depth_m'].append((round(t, 3), None if median is None else round(median, 4)))
        if self.viewer is not None or self.recorder is not None:
            self.show_and_record(self.colourise(depth, scale), t)

    def colourise(self, depth, scale):
        """Depth -> BGR: fixed range video_range to 0..255, JET colour map, invalid pixels black."""
        import cv2
        lo, hi = self.video_range
        if scale != 1.0 and depth.dtype == np.uint16:
            if self._lut is None:   # one table for every 16-bit millimetre value
                mm = np.arange(65536, dtype=np.float64) * scale
                self._lut = np.clip((mm - lo) / (hi - lo) * 255.0, 0, 255).astype(np.uint8)
            grey = self._lut[depth]
            invalid = depth == 0
        else:
            metres = depth.astype(np.float32) * np.float32(scale)
            invalid = ~np.isfinite(metres) | (metres <= 0)
            grey = np.clip((np.nan_to_num(metres) - lo) * (255.0 / (hi - lo)), 0, 255).astype(np.uint8)
        bgr = cv2.applyColorMap(grey, cv2.COLORMAP_JET)
        bgr[invalid] = 0
        return bgr

    def finish(self):
        self.finish_media()
        self.values['video_range_m'] = list(self.video_range)
        self.values['frames_all_zero'] = self.all_zero
        if not self.converted:
            return
        mean_share = self.share.total / self.share.n if self.share.n else 0.0
        self.values['valid_share'] = self.share.as_dict(4)
        median = float(np.median(self.medians)) if self.medians else None
        self.values['depth_m'] = {'min': round(self.lo.lo, 4) if self.lo.n else None,
                                  'median': round(median, 4) if median is not None else None,
                                  'max': round(self.hi.hi, 4) if self.hi.n else None}
        if median is not None:
            self.notes.append('Depth min %s, median %s, max %s m; valid pixels %.1f%% (mean)'
                              % (fmt(self.lo.lo, 3), fmt(median, 3), fmt(self.hi.hi, 3), 100 * mean_share))
        if self.all_zero == self.converted:
            self.fail('depth all zero: no valid pixel in any of the %d frames' % self.converted)
            return
        if self.min_valid_share is not None and mean_share < float(self.min_valid_share):
            self.fail('only %.1f%% of the pixels are valid (min_valid_share %s%%)'
                      % (100 * mean_share, fmt(100 * float(self.min_valid_share), 1)))
        if self.median_range and median is not None:
            lo, hi = float(self.median_range[0]), float(self.median_range[1])
            if not (lo <= median <= hi) or not math.isfinite(median):
                self.fail('median depth %s m outside median_range [%s, %s] m'
                          % (fmt(median, 3), fmt(lo), fmt(hi)))
