"""Depth cameras: colour-mapped frames with their scale, the video, depth statistics, the
histogram when the check recorded one, median depth and valid pixels over time."""
from typing import TYPE_CHECKING, List

from ....results import SensorResult
from .. import plots
from ..blocks import KV, Block, Heading, Image
from ..values import DepthValues
from .camera import frames, frames_and_video, video_row
from .fmt import num, spread

if TYPE_CHECKING:
    from ..page import View


def render(r: SensorResult, v: DepthValues, ctx: 'View') -> List[Block]:
    cam = v.camera
    cells = frames(cam, ctx, ' (colour-mapped)')
    if cells:
        lo, hi = v.video_range_m
        cells.append(Image(plots.colour_scale(lo, hi), 'depth colour scale', caption='black: no depth'))
    out = frames_and_video(r, cam, ctx, cells)
    rows = []
    if cam.width is not None:
        rows.append(('image', '%sx%s %s' % (cam.width, cam.height, cam.encoding or '')))
    rows.append(('depth', spread(v.depth_m, 3, 'median', 'm')))
    rows.append(('valid pixels (share)', spread(v.valid_share, 3)))
    if v.frames_all_zero is not None:
        rows.append(('frames without a valid pixel', num(v.frames_all_zero)))
    video = video_row(cam.video)
    if video:
        rows.append(video)
    out += [Heading('Depth statistics'), KV(rows)]
    if v.histogram:
        out += [Heading('Depth histogram'), Image(plots.histogram(v.histogram), 'depth histogram')]
    if v.median_depth_m or v.valid:
        out += [Heading('Over time'), Image(plots.depth_over_time(v.median_depth_m, v.valid),
                                            'median depth and valid pixels over time')]
    return out
