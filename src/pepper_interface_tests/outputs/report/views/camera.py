"""Cameras: first and last frame, the video (or why there is none), brightness statistics."""
from typing import Any, List, Optional, Tuple

from ....results import SensorResult
from ....sensors.values.camera import CameraValues, VideoSummary
from .. import plots
from ..blocks import KV, Block, Heading, Image, Para, Row
from ..context import View
from ..values import Series, VideoInfo
from .fmt import num, spread


def video_info(r: SensorResult, summary: Optional[VideoSummary]) -> Optional[VideoInfo]:
    """The recorder's summary with the sensor's video file and notes; None when nothing was
    to be recorded."""
    art = r.artifacts if isinstance(r.artifacts, dict) else {}
    if summary is None:
        if art.get('video'):
            return VideoInfo(file=art['video'])
        return VideoInfo(recording_off=True) if 'recording off' in (r.notes or []) else None
    return VideoInfo(file=art.get('video') or summary.file, codec=summary.codec, fps=summary.fps,
                     frames_received=summary.frames_received, frames_written=summary.frames_written,
                     error=summary.error,
                     notes=[n[len('video: '):] for n in r.notes or [] if n.startswith('video: ')])


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


def frames_and_video(r: SensorResult, video: Optional[VideoInfo], ctx: View, cells: List[Any]) -> List[Block]:
    """The 'Frames and video' row: `cells` (frame thumbnails, ...) plus the player, or the reason."""
    out: List[Block] = []
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


def frames(r: SensorResult, ctx: View, extra: str = '') -> List[Any]:
    """The first and last frame's thumbnails (the sensor's JPEG artifacts)."""
    art = r.artifacts if isinstance(r.artifacts, dict) else {}
    return [ctx.files.frame(art[k], caption + extra)
            for k, caption in (('first_frame', 'first frame'), ('last_frame', 'last frame')) if art.get(k)]


def video_row(video: Optional[VideoInfo]) -> Optional[Tuple[str, str]]:
    if video is None or not video.file:
        return None
    return ('video', '%s frames, %s fps, codec %s' % (num(video.frames_written), num(video.fps),
                                                       video.codec or 'unknown'))


def render(r: SensorResult, v: CameraValues, ctx: View) -> List[Block]:
    video_file = video_info(r, v.video)
    out = frames_and_video(r, video_file, ctx, frames(r, ctx))
    rows = []
    if v.width is not None:
        rows.append(('image', '%sx%s %s' % (v.width, v.height, v.encoding or '')))
    rows.append(('brightness (mean of a frame, 0-255)', spread(v.brightness_mean)))
    rows.append(('spread (std of a frame)', spread(v.brightness_spread)))
    for value, label in ((v.frames_black, 'black frames'), (v.frames_constant, 'constant frames'),
                         (v.longest_identical_run, 'longest run of identical frames (frozen)')):
        if value is not None:
            rows.append((label, num(value)))
    video = video_row(video_file)
    if video:
        rows.append(video)
    if v.stereo:
        st = v.stereo
        rows.append(('stereo', 'two views of %sx%s, identical views in %s frames'
                     % (num(st.view_width), num(st.view_height), num(st.identical_views))))
    out += [Heading('Image statistics'), KV(rows)]
    brightness = Series.of(v.brightness)
    if brightness:
        out.append(Image(plots.brightness(brightness), 'brightness over time of ' + r.name))
    return out
