"""Recordings: camera videos (H.264 mp4, one ffmpeg process per video fed raw frames through a
pipe) and microphone audio (WAV, soundfile).

VideoRecorder
  * `add(frame, t, pix_fmt)` is called from a subscriber thread and only queues the frame (a
    numpy view over the message's bytes: nothing is copied or converted there); a writer
    thread per recorder feeds the frames to its ffmpeg, so a slow encoder never holds up
    reception; it writes them in bursts (BATCH_WAIT). The queue is bounded (about 32 MB of
    frames, at least 8); a frame that does not fit is not recorded and counted (`dropped`),
    never lost silently.
  * Encoding: `ffmpeg -f rawvideo -pix_fmt <rgb24|bgr24|gray|bgra|rgba|bgr0|yuv420p> -s WxH -r <rate>
    -i pipe:0 -c:v libx264 -preset ultrafast -crf 28 -threads 1 -sws_flags neighbor
    -pix_fmt yuv420p -movflags +faststart`:
    H.264 that plays in browsers, every frame written, colour conversion done by ffmpeg
    (swscale), no intermediate file and no second encoding pass. ffmpeg runs in its own
    session, so a Ctrl-C sent to sensorTest's process group does not cut the file short:
    sensorTest closes the pipe once every queued frame is written and ffmpeg finishes the file.
    `prepare(frame, pix_fmt)` (optional, e.g. the depth colour map) turns a queued frame into
    (uint8 array, pix_fmt) in the writer thread; `preview` (default: `prepare`) does the same
    for the first and last frame (the JPEG artifacts).
  * Frame rate: the writer buffers the first second of frames (at least 3 frames, at most
    16 frames or 3 s) and starts ffmpeg at the rate measured from their receive times (the
    mean of the middle half of the intervals: a late first frame or a burst at start-up does
    not count). When
    the recording ends, the rate over the whole recording is measured again; if it differs from
    the file's rate by more than 5 %, the file is remuxed with ffmpeg (`-itsscale`, stream copy,
    no re-encoding) so that it plays at the measured rate.
  * Frames of another size or pixel format than the first are converted (OpenCV) and resized
    to the first one (counted).
  * The file is written under a temporary name (".<name>.writing.mp4") and renamed to its
    final name on close; close() is idempotent, and frames added after close are ignored and
    counted (`late`), so a late callback can never reopen or truncate a finished file.
    Without ffmpeg there is no video (an error says so); the checks are not affected.

WavWriter
  * Incremental PCM_16 WAV through soundfile, also written under a temporary name and renamed
    on close. Opened on the first write (no data, no file).
"""
import fcntl
import os
import queue
import shutil
import subprocess
import tempfile
import threading
import time
from typing import IO, Any, Callable, Dict, List, Optional, Tuple

import numpy as np

from ..stats import _rate

QUEUE_BYTES = 32 * 1024 * 1024
RATE_SPAN = 1.0          # seconds of frames buffered to measure the rate
RATE_MIN_FRAMES = 3
RATE_MAX_WAIT = 3.0      # open after this long even with fewer frames
RATE_MAX_FRAMES = 16     # or once this many frames are buffered (memory)
REMUX_TOLERANCE = 0.05
# s the writer thread waits when its queue is empty, so that frames reach ffmpeg in bursts
# (9 frames at 30 Hz) instead of one wake-up of both processes per frame: in the benchmark's
# recording round (docs/benchmark.md) the writer threads went from 0.67 s to 0.43-0.44 s of CPU
# and the encoders from 3.43 s to 2.97-3.10 s for the same 1,500 frames; at most 0.3 s more of
# frames waits in each queue (QUEUE_BYTES bounds it)
BATCH_WAIT = 0.3
# libx264 settings: the least CPU per frame that still shows what a camera sees. Measured on
# 640x480 rgb24 with sensor-like noise (docs/media.md, "Video files"): ultrafast 2.8 ms/frame;
# crf 28 instead of 23 saves 8 %, point-sampled chroma (swscale 'neighbor' when RGB becomes
# 4:2:0) 16 %; one thread per encoder (x264's threads only add overhead at this size)
PRESET = 'ultrafast'
CRF = '28'
F_SETPIPE_SZ = 1031       # fcntl.F_SETPIPE_SZ (Python >= 3.10 names it)
PIPE_BYTES = 1 << 20      # at most /proc/sys/fs/pipe-max-size (1 MB by default)
CHANNELS = {'gray': 1, 'rgb24': 3, 'bgr24': 3, 'bgra': 4, 'rgba': 4, 'bgr0': 4}
# planar 4:2:0 frames (the video's own format: ffmpeg converts nothing) are 2-D uint8 arrays of
# shape (h * 3 / 2, w), even w and h: the Y plane, then U and V (w/2 x h/2 each), as OpenCV's I420
YUV420P = 'yuv420p'
# (frame, pix_fmt) -> (uint8 frame, ffmpeg pix_fmt): VideoRecorder's `prepare` and `preview`
Prepare = Callable[[np.ndarray, Optional[str]], Tuple[np.ndarray, str]]


def _cv2():
    import cv2
    return cv2


def _pix_fmt(frame):
    """The pixel format of a uint8 frame by its shape: grey, BGR or BGRA (OpenCV's orders)."""
    if frame.ndim == 2 or frame.shape[2] == 1:
        return 'gray'
    return 'bgr24' if frame.shape[2] == 3 else 'bgra'


def frame_size(frame: np.ndarray, pix_fmt: Optional[str]) -> Tuple[int, int]:
    """(width, height) of a frame in one of CHANNELS' formats or yuv420p."""
    if pix_fmt == YUV420P:
        return frame.shape[1], frame.shape[0] * 2 // 3
    return frame.shape[1], frame.shape[0]


def _yuv420p_to_rgb(frame):
    """RGB of a yuv420p frame (BT.601, limited range, as swscale writes it; chroma repeated);
    numpy only, for the few frames that need it (JPEGs, a resize)."""
    w, h = frame_size(frame, YUV420P)
    flat = frame.reshape(-1)
    y = flat[:w * h].reshape(h, w).astype(np.float32) - 16.0
    chroma = flat[w * h:].reshape(2, h // 2, w // 2).astype(np.float32) - 128.0
    u, v = (np.repeat(np.repeat(c, 2, axis=0), 2, axis=1) for c in chroma)
    y *= 255.0 / 219.0
    rgb = np.dstack([y + 1.596027 * v, y - 0.391762 * u - 0.812968 * v, y + 2.017232 * u])
    return np.clip(np.rint(rgb), 0, 255).astype(np.uint8)


def to_rgb(frame: np.ndarray, pix_fmt: Optional[str]) -> np.ndarray:
    """An RGB view (numpy only: no OpenCV import) of a frame in one of CHANNELS' formats
    (a new array for gray and yuv420p)."""
    frame = np.asarray(frame)
    if pix_fmt == YUV420P:
        return _yuv420p_to_rgb(frame)
    if pix_fmt == 'gray':
        grey = frame.reshape(frame.shape[:2])
        return np.dstack([grey, grey, grey])
    if pix_fmt in ('rgb24', 'rgba'):
        return frame[:, :, :3]
    return frame[:, :, 2::-1]        # bgr24, bgra, bgr0


def to_bgr(frame: np.ndarray, pix_fmt: Optional[str]) -> np.ndarray:
    """A contiguous BGR copy of a frame (JPEGs, the live view, resizing); numpy only."""
    return np.ascontiguousarray(to_rgb(frame, pix_fmt)[:, :, ::-1])


def _from_bgr(bgr, pix_fmt):
    cv2 = _cv2()
    code = {'gray': cv2.COLOR_BGR2GRAY, 'rgb24': cv2.COLOR_BGR2RGB, 'rgba': cv2.COLOR_BGR2RGBA,
            'bgra': cv2.COLOR_BGR2BGRA, 'bgr0': cv2.COLOR_BGR2BGRA,
            YUV420P: cv2.COLOR_BGR2YUV_I420}.get(pix_fmt)
    return bgr if code is None else cv2.cvtColor(bgr, code)


def ffprobe_frames(path: str) -> Optional[int]:
    """Number of video frames in `path`, counted by decoding with ffprobe (None if unknown)."""
    if not shutil.which('ffprobe'):
        return None
    out = subprocess.run(['ffprobe', '-v', 'error', '-count_frames', '-select_streams', 'v:0',
                          '-show_entries', 'stream=nb_read_frames', '-of', 'csv=p=0', path],
                         capture_output=True, text=True, timeout=120)
    try:
        return int(out.stdout.strip().split(',')[0])
    except ValueError:
        return None


def _start_rate(times):
    """Frame rate from the first frames' receive times: the mean of the middle half of the
    intervals. At start-up the first frames often arrive late and then in a burst (the
    subscriber's connection and the process's first callbacks), which made (n - 1) / span
    read 32-33 fps for a 30 fps stream in the benchmark (more than REMUX_TOLERANCE: an
    extra ffmpeg pass per video at the end); the middle half ignores such outliers and is
    the plain mean for a regular stream."""
    gaps = sorted(b - a for a, b in zip(times, times[1:]))
    if len(gaps) >= 4:
        gaps = gaps[len(gaps) // 4:len(gaps) - len(gaps) // 4]
    mean = sum(gaps) / len(gaps) if gaps else 0.0
    return 1.0 / mean if mean > 0 else None


def exit_code(status: int) -> int:
    """A wait status as a return code (os.waitstatus_to_exitcode, which Python 3.8 lacks): the
    exit code, or -N for a process ended by signal N, as subprocess's returncode."""
    if os.WIFSIGNALED(status):
        return -os.WTERMSIG(status)
    return os.WEXITSTATUS(status)


def _wait_cpu(proc, timeout):
    """(exit code, CPU seconds) of a child process, killed after `timeout` s."""
    deadline = time.monotonic() + timeout
    while True:
        try:
            pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
        except ChildProcessError:       # already reaped
            return proc.wait(), None
        if pid:
            proc.returncode = exit_code(status)
            return proc.returncode, usage.ru_utime + usage.ru_stime
        if time.monotonic() > deadline:
            proc.kill()
            deadline = float('inf')
        time.sleep(0.01)


class VideoRecorder:
    """One H.264 mp4 file per camera, encoded by one ffmpeg process; see the module docstring."""

    def __init__(self, path: str, fallback_fps: float = 10.0, max_fps: float = 240.0,
                 queue_bytes: int = QUEUE_BYTES, prepare: Optional[Prepare] = None,
                 preview: Optional[Prepare] = None) -> None:
        self.path = path
        self.tmp_path = os.path.join(os.path.dirname(path) or '.',
                                     '.' + os.path.basename(path)[:-4] + '.writing.mp4')
        self.fallback_fps = float(fallback_fps)
        self.max_fps = float(max_fps)     # a burst at the start must not pass for the rate
        self.queue_bytes = queue_bytes
        self.prepare = prepare
        self.preview = preview or prepare
        self._queue: Any = None       # queue.Queue of frames, made on the first frame
        self._thread: Optional[threading.Thread] = None
        self._lock = threading.Lock()
        self._closed = False
        self._proc: Any = None       # the ffmpeg process (subprocess.Popen)
        self._stderr: Optional[IO[str]] = None     # its error output (a temporary file)
        # (frame, t, pix_fmt) before ffmpeg is started
        self._buffer: List[Tuple[np.ndarray, float, Optional[str]]] = []
        self._times: List[float] = []              # receive times of the written frames
        self.size: Optional[Tuple[int, int]] = None    # (width, height) of the file
        self.pix_fmt: Optional[str] = None         # pixel format fed to ffmpeg
        self.codec: Optional[str] = None
        self.fps: Any = None         # rate the file was opened with (float)
        self.final_fps: Optional[float] = None     # rate of the finished file
        self.received = 0
        self.written = 0
        self.dropped = 0
        self.resized = 0
        self.late = 0
        self.error: Optional[str] = None
        self.notes: List[str] = []
        self.encode_seconds: Optional[float] = None    # end of the recording -> file finished (wall)
        self.encoder_cpu: Optional[float] = None       # CPU seconds ffmpeg used (user + system)
        self.writer_cpu: Optional[float] = None        # CPU seconds of the writer thread (this process)
        # (frame, pix_fmt) of the first and last frame queued
        self._first: Optional[Tuple[np.ndarray, Optional[str]]] = None
        self._last: Optional[Tuple[np.ndarray, Optional[str]]] = None

    # ---- subscriber side -------------------------------------------------------------
    def add(self, frame: np.ndarray, t: float, pix_fmt: Optional[str] = None) -> None:
        """Queue one uint8 frame (h, w[, c]) received at `t` seconds; `pix_fmt` one of CHANNELS
        (default: grey, BGR or BGRA by shape), or anything `prepare` understands.
        The frame must not change afterwards (views over message bytes never do).
        Never blocks or raises."""
        with self._lock:
            if self._closed:
                self.late += 1
                return
            if pix_fmt is None and self.prepare is None:
                pix_fmt = _pix_fmt(frame)
            if self._thread is None:
                per_frame = max(1, frame.nbytes)
                self._queue = queue.Queue(maxsize=max(8, self.queue_bytes // per_frame))
                self._thread = threading.Thread(target=self._run, name='video:' + os.path.basename(self.path),
                                                daemon=True)
                self._thread.start()
            self.received += 1
            if self._first is None:
                self._first = (frame, pix_fmt)
            self._last = (frame, pix_fmt)
            try:
                self._queue.put_nowait((frame, t, pix_fmt))
            except queue.Full:
                self.dropped += 1

    def close(self, timeout: float = 60.0) -> Dict[str, Any]:
        """Finish the file (drain the queue, end ffmpeg, fix the rate, rename). Idempotent."""
        with self._lock:
            if self._closed:
                return self.summary()
            self._closed = True
            thread = self._thread
        if thread is not None:
            try:
                self._queue.put(None, timeout=timeout)
            except queue.Full:
                pass
            thread.join(timeout)
            if thread.is_alive():
                self.error = 'video writer did not finish within %.0f s' % timeout
        return self.summary()

    @property
    def closed(self) -> bool:
        return self._closed

    @property
    def first_frame(self) -> Optional[Tuple[np.ndarray, Optional[str]]]:
        """(frame, pix_fmt) of the first frame queued (for the JPEG artifact), or None."""
        return self._prepared_item(self._first)

    @property
    def last_frame(self) -> Optional[Tuple[np.ndarray, Optional[str]]]:
        return self._prepared_item(self._last)

    def _prepared_item(self, item):
        if item is None:
            return None
        return self.preview(*item) if self.preview is not None else item

    # ---- writer thread -----------------------------------------------------------------
    def _run(self):
        while True:
            item = self._queue.get()
            if item is None:
                break
            self._step(item)
            if self._proc is not None and self._queue.empty():
                time.sleep(BATCH_WAIT)
        if self._proc is None and self._buffer and not self.error:
            self._step(None)
        self._finish()
        self.writer_cpu = time.thread_time()

    def _step(self, item):
        """Buffer, open or write; after an error the remaining frames are counted as dropped."""
        if self.error:
            self._count_dropped(1)
            return
        opening = self._proc is None
        try:
            if opening:
                if item is not None:
                    self._buffer.append(item)
                if item is None or self._ready():
                    self._open()
            else:
                self._write(*item)
        except Exception as e:  # an encoder error must not kill the run
            self.error = 'video writer failed: %s' % (self._ffmpeg_error() or e)
            self._count_dropped(len(self._buffer) if opening else 1)   # the frames not written
            self._buffer = []

    def _count_dropped(self, n):
        with self._lock:
            self.dropped += n

    def _ready(self):
        span = self._buffer[-1][1] - self._buffer[0][1]
        n = len(self._buffer)
        return (span >= RATE_SPAN and n >= RATE_MIN_FRAMES) or span >= RATE_MAX_WAIT or n >= RATE_MAX_FRAMES

    def _prepared(self, frame, pix_fmt):
        if self.prepare is not None:
            return self.prepare(frame, pix_fmt)
        return frame, pix_fmt

    def _open(self):
        first, pix_fmt = self._prepared(self._buffer[0][0], self._buffer[0][2])
        self.size = frame_size(first, pix_fmt)
        self.pix_fmt = pix_fmt
        fps = _start_rate([t for _, t, _ in self._buffer]) or self.fallback_fps
        self.fps = round(min(max(fps, 0.5), self.max_fps), 3)
        os.makedirs(os.path.dirname(self.path) or '.', exist_ok=True)
        for stale in (self.path, self.tmp_path):
            if os.path.exists(stale):
                os.unlink(stale)
        if not shutil.which('ffmpeg'):
            self.error = 'ffmpeg not found: no video (install ffmpeg)'
            self._count_dropped(len(self._buffer))
            self._buffer = []
            return
        self._stderr = tempfile.TemporaryFile('w+')
        # yuv420p needs even sides: an odd one gets a black line (the summary keeps the real size)
        odd = self.size[0] % 2 or self.size[1] % 2
        pad = ['-vf', 'pad=ceil(iw/2)*2:ceil(ih/2)*2'] if odd else []
        # own session: a Ctrl-C to sensorTest's process group must not end ffmpeg before the
        # queued frames are in; it ends when its input pipe is closed. Niced (nice 10, `nice`
        # then execs ffmpeg: the same process): an encoder starts with the frames of its first
        # seconds queued, and six such bursts at once took both cores of a 2-core machine from
        # the audio chain for 0.29 s, a gap this node then reported in the microphones' stream;
        # the encoders' work waits in their queues instead
        nice = ['nice', '-n', '10'] if shutil.which('nice') else []
        self._proc = subprocess.Popen(
            nice + ['ffmpeg', '-v', 'error', '-y', '-f', 'rawvideo', '-pix_fmt', pix_fmt,
             '-s', '%dx%d' % self.size, '-r', '%.6f' % self.fps, '-i', 'pipe:0', '-an'] + pad +
            ['-c:v', 'libx264', '-preset', PRESET, '-crf', CRF, '-threads', '1', '-sws_flags', 'neighbor',
             '-pix_fmt', 'yuv420p',
             '-movflags', '+faststart', '-f', 'mp4', self.tmp_path],
            stdin=subprocess.PIPE, stdout=subprocess.DEVNULL, stderr=self._stderr, start_new_session=True)
        try:    # a 1 MB pipe (Linux F_SETPIPE_SZ): a whole frame per write, fewer switches to ffmpeg
            fcntl.fcntl(self._proc.stdin.fileno(), F_SETPIPE_SZ, PIPE_BYTES)
        except OSError:
            pass
        self.codec = 'avc1'
        while self._buffer:              # a frame leaves the buffer once it is written
            self._write(*self._buffer[0])
            self._buffer.pop(0)

    def _fit(self, frame, pix_fmt):
        """(frame in the file's size and pixel format, whether it was resized)."""
        frame, pix_fmt = self._prepared(frame, pix_fmt)
        same_size = frame_size(frame, pix_fmt) == self.size
        if same_size and pix_fmt == self.pix_fmt:
            return frame, False
        bgr = to_bgr(frame, pix_fmt)
        if not same_size:
            bgr = _cv2().resize(bgr, self.size, interpolation=_cv2().INTER_AREA)
        return _from_bgr(bgr, self.pix_fmt), not same_size

    def _write(self, frame, t, pix_fmt):
        fitted, resized = self._fit(frame, pix_fmt)
        if resized:
            self.resized += 1
        data = fitted if fitted.flags.c_contiguous else np.ascontiguousarray(fitted)
        self._proc.stdin.write(data.data.cast('B'))   # the array's own memoryview: no copy
        self.written += 1
        self._times.append(t)

    def _ffmpeg_error(self):
        log = self._stderr
        if log is None or log.closed:
            return ''
        try:
            log.flush()
            log.seek(0)
            return ' '.join(log.read().split())[:200]
        except (OSError, ValueError):
            return ''

    def _finish(self):
        started = time.monotonic()
        try:
            self._finalise()
        except Exception as e:   # e.g. the disk is full: report, never raise from the writer thread
            self.error = self.error or 'cannot finish %s: %s' % (os.path.basename(self.path), e)
        finally:
            log = self._stderr
            if log is not None:
                log.close()
        self.encode_seconds = round(time.monotonic() - started, 3)

    def _finalise(self):
        if self._proc is not None:
            try:
                self._proc.stdin.close()
            except OSError:          # ffmpeg already gone: its error is reported below
                pass
            code, self.encoder_cpu = _wait_cpu(self._proc, 120.0)
            self._proc = None
            if code != 0:       # the mp4 is not finished (no index): not a file anyone can play
                self.error = 'ffmpeg failed (exit %d): %s; no video' % (code, self._ffmpeg_error() or self.error)
        if not os.path.exists(self.tmp_path):
            return
        if not self.written or (self.error and 'ffmpeg failed' in self.error):
            os.unlink(self.tmp_path)
            return
        self.final_fps = self.fps
        measured = _rate(self._times)
        if measured and abs(measured - self.fps) / measured > REMUX_TOLERANCE:
            if self._ffmpeg(['-itsscale', '%.6f' % (self.fps / measured)], ['-c', 'copy'], 'rate correction'):
                self.notes.append('frame rate corrected from %.2f (first second) to %.2f fps '
                                  '(whole recording)' % (self.fps, measured))
                self.final_fps = round(measured, 3)
        os.replace(self.tmp_path, self.path)

    def _ffmpeg(self, input_args, codec_args, what):
        """Rewrite the temporary file with ffmpeg (input options, codec options). True when
        done; on failure the file stays as it was and a note says why."""
        fixed = self.tmp_path[:-4] + '.ffmpeg.mp4'
        cmd = ['ffmpeg', '-v', 'error', '-y'] + input_args + ['-i', self.tmp_path] + codec_args + \
            ['-an', '-movflags', '+faststart', fixed]
        try:
            done = subprocess.run(cmd, capture_output=True, text=True, timeout=120, start_new_session=True)
        except (OSError, subprocess.SubprocessError) as e:
            self.notes.append('%s failed: %s' % (what, e))
            return False
        if done.returncode != 0 or not os.path.exists(fixed):
            self.notes.append('%s failed: %s' % (what, done.stderr.strip()[:200]))
            if os.path.exists(fixed):
                os.unlink(fixed)
            return False
        os.replace(fixed, self.tmp_path)
        return True

    # ---- results ------------------------------------------------------------------------
    def summary(self) -> Dict[str, Any]:
        return {'file': os.path.basename(self.path) if os.path.exists(self.path) and self.written else None,
                'codec': self.codec, 'fps': self.final_fps or self.fps,
                'width': self.size[0] if self.size else None,
                'height': self.size[1] if self.size else None,
                'frames_received': self.received, 'frames_written': self.written,
                'frames_dropped': self.dropped, 'frames_resized': self.resized,
                'late_frames': self.late, 'error': self.error, 'finish_s': self.encode_seconds,
                'encoder_cpu_s': round(self.encoder_cpu, 3) if self.encoder_cpu is not None else None,
                'writer_cpu_s': round(self.writer_cpu, 3) if self.writer_cpu is not None else None}


def save_jpeg(path: str, image: np.ndarray, pix_fmt: Optional[str] = 'bgr24', quality: int = 90) -> bool:
    """Write one image (BGR by default, or any of CHANNELS' formats) as JPEG; True on success
    (never raises). Pillow (which matplotlib needs anyway) is used when present: importing it
    costs 4 MB, importing OpenCV about 100 MB of memory."""
    try:
        from PIL import Image
    except ImportError:
        Image = None
    try:
        if Image is not None:
            Image.fromarray(np.ascontiguousarray(to_rgb(image, pix_fmt))).save(path, 'JPEG', quality=quality)
            return True
        cv2 = _cv2()
        return bool(cv2.imwrite(path, to_bgr(image, pix_fmt), [cv2.IMWRITE_JPEG_QUALITY, quality]))
    except Exception:
        return False


class WavWriter:
    """Incremental PCM WAV file (soundfile), opened on the first write, renamed on close."""

    def __init__(self, path: str, samplerate: float, channels: int, subtype: str = 'PCM_16') -> None:
        self.path = path
        self.tmp_path = os.path.join(os.path.dirname(path) or '.',
                                     '.' + os.path.basename(path)[:-4] + '.writing.wav')
        self.samplerate = int(samplerate)
        self.channels = int(channels)
        self.subtype = subtype
        self.frames = 0
        self.error: Optional[str] = None
        self._file: Any = None       # soundfile.SoundFile (no type information), opened on the first write
        self._closed = False
        self._lock = threading.Lock()

    def write(self, samples: np.ndarray) -> None:
        """Append int16 samples, shape (n, channels) or (n,) for one channel."""
        with self._lock:
            if self._closed or self.error:
                return
            try:
                if self._file is None:
                    import soundfile
                    os.makedirs(os.path.dirname(self.path) or '.', exist_ok=True)
                    if os.path.exists(self.path):
                        os.unlink(self.path)
                    self._file = soundfile.SoundFile(self.tmp_path, 'w', samplerate=self.samplerate,
                                                     channels=self.channels, subtype=self.subtype,
                                                     format='WAV')
                self._file.write(samples)
                self.frames += len(samples)
            except Exception as e:
                self.error = 'cannot write %s: %s' % (os.path.basename(self.path), e)

    def close(self) -> None:
        with self._lock:
            if self._closed:
                return
            self._closed = True
            if self._file is not None:
                try:
                    self._file.close()
                    os.replace(self.tmp_path, self.path)
                except Exception as e:
                    self.error = 'cannot finish %s: %s' % (os.path.basename(self.path), e)

    @property
    def written(self) -> bool:
        return self._closed and self._file is not None and self.error is None

    @property
    def seconds(self) -> float:
        return self.frames / float(self.samplerate)
