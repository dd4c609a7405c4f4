"""The run folder's files as the page shows them: stills embedded, large media linked.

Size budget (docs/results.md, "sensorTestReport.html"): a JPEG still is always embedded (a
frame is 10-60 kB); a video or WAV is embedded only while it is at most `max_embed` bytes
(default 512 kB: 10 s of a 320x240 H.264 clip from the emulator is 50-270 kB, a
10 s 4-channel WAV 3.8 MB) AND the media embedded so far stay within
`budget` bytes (default 1 MB). Everything else is played from a relative link to the file,
which sits next to the report both in the run folder and in the output folder (history.py
links every run file there). Base64 adds a third, so media add at most 1.4 MB to a report,
whatever the run recorded; the plots add about 1 MB for all fourteen robot sensors.
"""
import base64
import os
from typing import List, Optional, Sequence, Union

from .blocks import Image, Media, Para, Span

MAX_EMBED_BYTES = 512 * 1024
EMBED_BUDGET_BYTES = 1024 * 1024
BROWSER_CODECS = ('avc1', 'avc3', 'vp09', 'av01')


def video_codec(data: bytes) -> Optional[str]:
    """The sample format of the first track of an mp4 (e.g. 'avc1', 'mp4v'), or None."""
    i = data.rfind(b'stsd')
    if i < 0 or i + 20 > len(data):
        return None
    tag = data[i + 16:i + 20]
    try:
        return tag.decode('ascii')
    except UnicodeDecodeError:
        return None


def _mb(size: int) -> str:
    return '%.2f MB' % (size / 1e6) if size >= 10000 else '%d kB' % max(1, round(size / 1e3))


class RunFiles:
    """Reads recordings from `folder`; counts what was embedded against the budget."""

    def __init__(self, folder: str, max_embed: int = MAX_EMBED_BYTES, budget: int = EMBED_BUDGET_BYTES) -> None:
        self.folder = folder
        self.max_embed = max_embed
        self.budget = budget
        self.embedded = 0          # bytes of media put inside the page so far
        self.problems: List[str] = []         # what could not be shown (said in the footer)

    def path(self, name: str) -> str:
        return os.path.join(self.folder, name)

    def exists(self, name: Optional[str]) -> bool:
        if not name:
            return False
        return os.path.exists(self.path(name))

    def read(self, name: str) -> Optional[bytes]:
        try:
            with open(self.path(name), 'rb') as f:
                return f.read()
        except OSError:
            return None

    def frame(self, name: str, caption: str) -> Union[Image, Para]:
        """A JPEG/PNG still, embedded, linking to its file."""
        data = self.read(name)
        if data is None:
            return Para(['%s: file %s not found' % (caption, name)], cls='warn-text')
        mime = 'image/png' if name.lower().endswith('.png') else 'image/jpeg'
        return Image('data:%s;base64,%s' % (mime, base64.b64encode(data).decode('ascii')), caption,
                     cls='frame', href=name, caption=caption)

    def _embed(self, name: str, size: int) -> Optional[bytes]:
        if size > self.max_embed or self.embedded + size > self.budget:
            return None
        data = self.read(name)
        if data is not None:
            self.embedded += size
        return data

    def media(self, tag: str, name: str, mime: str, codec: Optional[str] = None) -> Union[Media, Para]:
        """A <video>/<audio> block: inside the page within the budget, else linked."""
        if not self.exists(name):
            return Para(['recording %s not found next to the report' % name], cls='warn-text')
        size = os.path.getsize(self.path(name))
        if tag == 'video' and codec is None:
            with open(self.path(name), 'rb') as f:
                codec = video_codec(f.read())
        if tag == 'video' and codec and codec not in BROWSER_CODECS:
            return Para(['Video ', Span(name, href=name), ' (%s, %s): browsers cannot play this codec; '
                         'open it with a media player (VLC, mpv).' % (codec, _mb(size))])
        data = self._embed(name, size)
        if data is not None:
            src, how = 'data:%s;base64,%s' % (mime, base64.b64encode(data).decode('ascii')), 'embedded'
        else:
            src, how = name, 'linked, file next to the report'
        return Media(tag, src, [Span(name, href=name), ' (%s, %s)' % (_mb(size), how)])

    def links(self, names: Sequence[str]) -> List[Span]:
        """Links to the run's files that exist, e.g. the JSON and JUnit results."""
        return [Span(n, href=n) for n in names if self.exists(n)]
