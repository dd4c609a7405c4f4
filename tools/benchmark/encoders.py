"""The encoders alone: what sensorTest's video encoders cost with nothing else running, the
floor of a recording round above listening (a recording round's CPU is judged against the
listening round's plus this).

Every video stream of workload.STREAMS is encoded, all at once as in a round, by the package's
own VideoRecorder (media/recording.py: the same ffmpeg command, libx264 settings and pixel
formats), fed the publisher's frames (publisher.frames: the same RING frames, as many as the
round published, at the stream's rate): rgb8 as the raw rgb24 view sensorTest writes, 16UC1
through DepthCheck.prepare_frame, the colouring sensorTest's depth videos use (written as
yuv420p in this process's writer threads, not counted). The CPU counted is the encoders' own:
user + system of each ffmpeg from wait4 (VideoRecorder.encoder_cpu)."""
import os
from typing import Dict, List, Tuple

import numpy as np
from publisher import frames
from workload import STREAMS

from pepper_interface_tests.media.recording import VideoRecorder
from pepper_interface_tests.sensors.depth import DepthCheck

VIDEO_RANGE = (0.0, 5.0)     # m: the depth streams' video_range in workload.expectations()
# the recorders' queues take every frame at once (views of the RING frames: no memory of their own)
UNBOUNDED = 1 << 50


class _Depth(DepthCheck):
    """DepthCheck's colouring of a depth frame for its video, without a window to check."""

    def __init__(self) -> None:      # only what prepare_frame reads
        self.video_range = VIDEO_RANGE
        self._lut = None
        self._jet = None
        self._yuv = {}


def encoders_alone(published: Dict[str, int], folder: str) -> Tuple[float, List[str]]:
    """(CPU seconds of the encoders, errors) for `published` frames per stream (sensor name ->
    count; the microphone is a WAV written in-process: no encoder)."""
    recorders = []
    pixels: List[np.ndarray]
    for name, _topic, enc, w, h, rate in STREAMS:
        n = published.get(name, 0)
        if enc == 'audio' or not n:
            continue
        path = os.path.join(folder, name + '.mp4')
        if enc == 'rgb8':
            pixels = [np.frombuffer(f, np.uint8).reshape(h, w, 3) for f in frames(enc, w, h)]
            rec, kind = VideoRecorder(path, fallback_fps=rate, queue_bytes=UNBOUNDED), 'rgb24'
        else:
            pixels = [np.frombuffer(f, np.uint16).reshape(h, w) for f in frames(enc, w, h)]
            rec = VideoRecorder(path, fallback_fps=rate, queue_bytes=UNBOUNDED,
                                prepare=_Depth().prepare_frame)   # type: ignore[arg-type]
            kind = 'depth_mm'
        for i in range(n):
            rec.add(pixels[i % len(pixels)], i / rate, kind)
        recorders.append(rec)
    cpu, errors = 0.0, []
    for rec in recorders:
        summary = rec.close()
        cpu += rec.encoder_cpu or 0.0
        if rec.error or rec.written != rec.received:
            errors.append('%s: %s (%d of %d frames written)' % (rec.path, rec.error or summary, rec.written,
                                                                rec.received))
    return cpu, errors
