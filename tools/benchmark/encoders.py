"""The recorders alone: what sensorTest's videos cost with nothing else running, the floor of
a recording round above listening (a recording round's CPU is judged against the listening
round's plus this).

Every video stream of workload.STREAMS is recorded, all at once as in a round, by the package's
own VideoRecorder (media/recording.py: the same writer threads, ffmpeg command, libx264 settings
and pixel formats), fed the publisher's frames (publisher.frames: the same RING frames, as many
as the round published) at the times the publisher sent them (frame i of a stream at i / rate
s: an encoder fed live wakes per burst and costs more than one fed a whole queue at once, 5-7 %
alone and 12-19 % for the five of a round, docs/benchmark.md):
rgb8 as the raw rgb24 view sensorTest writes, 16UC1 through DepthCheck.prepare_frame, the
colouring sensorTest's depth videos use. The CPU counted is the recorders' own: user + system of
each ffmpeg from wait4 (VideoRecorder.encoder_cpu) and each writer thread's CPU (its colouring
and pipe writes, VideoRecorder.writer_cpu), as the round counts them in sensorTest."""
import heapq
import os
import time
from typing import Dict, List, Tuple

import numpy as np
from publisher import frames
from workload import STREAMS

from pepper_interface_tests.media.recording import VideoRecorder
from pepper_interface_tests.sensors.depth import DepthCheck

VIDEO_RANGE = (0.0, 5.0)     # m: the depth streams' video_range in workload.expectations()
# the recorders' queues take every frame given (views of the RING frames: no memory of their own)
UNBOUNDED = 1 << 50


class _Depth(DepthCheck):
    """DepthCheck's colouring of a depth frame for its video, without a window to check."""

    def __init__(self) -> None:      # only what prepare_frame reads
        self.video_range = VIDEO_RANGE
        self._lut = None
        self._jet = None
        self._yuv = {}


def recorders_alone(published: Dict[str, int], folder: str) -> Tuple[float, float, List[str]]:
    """(CPU seconds of the encoders, of the writer threads, errors) for `published` frames per
    stream (sensor name -> count; the microphone is a WAV written in-process: no encoder)."""
    feeds: List[Tuple[VideoRecorder, List[np.ndarray], str]] = []   # recorder, its frames, their kind
    schedule: List[List[Tuple[float, int, int]]] = []                 # per stream: (t, feed, frame)
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
        schedule.append([(i / rate, len(feeds), i) for i in range(n)])
        feeds.append((rec, pixels, kind))
    start = time.monotonic()
    for t, which, i in heapq.merge(*schedule):
        time.sleep(max(0.0, start + t - time.monotonic()))
        rec, pixels, kind = feeds[which]
        rec.add(pixels[i % len(pixels)], t, kind)
    encoders, writers, errors = 0.0, 0.0, []
    for rec, _pixels, _kind in feeds:
        summary = rec.close()
        encoders += rec.encoder_cpu or 0.0
        writers += rec.writer_cpu or 0.0
        if rec.error or rec.written != rec.received:
            errors.append('%s: %s (%d of %d frames written)' % (rec.path, rec.error or summary, rec.written,
                                                                rec.received))
    return encoders, writers, errors
