"""Cameras: first and last frame, the video (or why there is none), brightness statistics."""
from typing import TYPE_CHECKING, Any, List, Optional, Tuple

from ....results import SensorResult
from .. import plots
from ..blocks import KV, Block, Heading, Image, Para, Row
from ..values import CameraValues, VideoInfo
from .fmt import num, spread

if TYPE_CHECKING:
    from ..page import View


def no_video_reason(video: VideoInfo) -> Optional[str]:
    """Why no video file was written, in words (None when there is a video)."""
    if video.recording_off:
        return 'recording is off for this run'
    if video.file:
        return None
    parts = []
    if video.error:
        parts.append(video.error)
    if not video.frames_received:
        parts.append('no frame reached the video writer')
    elif not video.frames_written:
        parts.append('none of the %d frames received could be written' % video.frames_received)
    parts += video.notes
    return '; '.join(parts) or 'the video writer produced no file'


def frames_and_video(r: SensorResult, cam: CameraValues, ctx: 'View', cells: List[Any]) -> List[Block]:
    """The 'Frames and video' row: `cells` (frame thumbnails, ...) plus the player, or the reason."""
    out: List[Block] = []
    video = cam.video
    reason = no_video_reason(video) if video else None
    if video and video.file:
        cells.append(ctx.files.media('video', video.file, 'video/mp4', video.codec))
    if cells:
        out += [Heading('Frames and video'), Row(cells)]
    if reason:
        out.append(Para(['No video written: ' + reason + '.'], cls='warn-text'))
    elif not cells and r.messages:
        out.append(Para(['no frames or video recorded (no frame could be converted)'], cls='warn-text'))
    return out


def frames(cam: CameraValues, ctx: 'View', extra: str = '') -> List[Any]:
    return [ctx.files.frame(name, caption + extra) for name, caption in cam.frames]


def video_row(video: Optional[VideoInfo]) -> Optional[Tuple[str, str]]:
    if video is None or not video.file:
        return None
    return ('video', '%s frames, %s fps, codec %s' % (num(video.frames_written), num(video.fps),
                                                       video.codec or 'unknown'))


def render(r: SensorResult, v: CameraValues, ctx: 'View') -> List[Block]:
    out = frames_and_video(r, v, ctx, frames(v, ctx))
    rows = []
    if v.width is not None:
        rows.append(('image', '%sx%s %s' % (v.width, v.height, v.encoding or '')))
    rows.append(('brightness (mean of a frame, 0-255)', spread(v.brightness_mean)))
    rows.append(('spread (std of a frame)', spread(v.brightness_spread)))
    for value, label in ((v.frames_black, 'black frames'), (v.frames_constant, 'constant frames'),
                         (v.longest_identical_run, 'longest run of identical frames (frozen)')):
        if value is not None:
            rows.append((label, num(value)))
    video = video_row(v.video)
    if video:
        rows.append(video)
    if v.stereo:
        st = v.stereo
        rows.append(('stereo', 'two views of %sx%s, identical views in %s frames'
                     % (num(st.get('view_width')), num(st.get('view_height')), num(st.get('identical_views')))))
    out += [Heading('Image statistics'), KV(rows)]
    if v.brightness:
        out.append(Image(plots.brightness(v.brightness), 'brightness over time of ' + r.name))
    return out
