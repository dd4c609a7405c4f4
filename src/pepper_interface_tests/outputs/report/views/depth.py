"""Depth cameras: colour-mapped frames with their scale, the video, depth statistics, the
histogram when the check recorded one, median depth and valid pixels over time."""
from typing import List, Optional

from ....results import SensorResult
from ....sensors.values.depth import DepthHistogram, DepthValues
from .. import plots
from ..blocks import KV, Block, Heading, Image
from ..context import View
from ..values import Histogram, Series
from .camera import frames, frames_and_video, video_info, video_row
from .fmt import num, spread

DEFAULT_RANGE = (0.0, 5.0)     # plan/expectations.py DepthExpect.video_range's default


def _histogram(h: Optional[DepthHistogram]) -> Optional[Histogram]:
    if h is None or not h.counts:
        return None
    if len(h.edges) not in (len(h.counts), len(h.counts) + 1):
        return Histogram([float(i) for i in range(len(h.counts) + 1)], list(h.counts), 'bin')
    return Histogram(list(h.edges), list(h.counts))


def render(r: SensorResult, v: DepthValues, ctx: View) -> List[Block]:
    video = video_info(r, v.video)
    cells = frames(r, ctx, ' (colour-mapped)')
    if cells:
        span = v.video_range_m
        lo, hi = (span[0], span[1]) if span and len(span) >= 2 else DEFAULT_RANGE
        cells.append(Image(plots.colour_scale(lo, hi), 'depth colour scale', caption='black: no depth'))
    out = frames_and_video(r, video, ctx, cells)
    rows = []
    if v.width is not None:
        rows.append(('image', '%sx%s %s' % (v.width, v.height, v.encoding or '')))
    rows.append(('depth', spread(v.depth_m, 3, 'median', 'm')))
    rows.append(('valid pixels (share)', spread(v.valid_share, 3)))
    if v.frames_all_zero is not None:
        rows.append(('frames without a valid pixel', num(v.frames_all_zero)))
    row = video_row(video)
    if row:
        rows.append(row)
    out += [Heading('Depth statistics'), KV(rows)]
    histogram = _histogram(v.depth_histogram)
    if histogram:
        out += [Heading('Depth histogram'), Image(plots.histogram(histogram), 'depth histogram')]
    median, valid = Series.of(v.median_depth_m), Series.of(v.valid_series)
    if median or valid:
        out += [Heading('Over time'), Image(plots.depth_over_time(median, valid),
                                            'median depth and valid pixels over time')]
    return out
