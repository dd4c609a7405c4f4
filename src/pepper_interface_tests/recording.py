"""Recordings: camera videos (mp4, cv2.VideoWriter) and microphone audio (WAV, soundfile).

VideoRecorder
  * `add(frame, t)` is called from a subscriber thread and only queues the frame; a writer
    thread per recorder does the encoding, so a slow encoder never holds up reception.
    The queue is bounded (about 32 MB of frames, at least 8); a frame that does not fit is not recorded
    and counted (`dropped`), never lost silently.
  * Frame rate: the writer buffers the first second of frames (at least 3 frames, at most
    16 frames or 3 s) and opens the file at the rate measured from their receive times. When the recording
    ends, the rate over the whole recording is measured again; if it differs from the file's
    rate by more than 5 %, the file is remuxed with ffmpeg (`-itsscale`, stream copy, no
    re-encoding) so that it plays at the measured rate.
  * Codec: H.264 ('avc1', plays in browsers) when this OpenCV build can encode it, else
    'mp4v' (MPEG-4 part 2). H.264 costs 10-30 times more CPU than mp4v (docs/media.md): in
    'auto' mode each recorder first encodes a few of its buffered frames with avc1 to measure
    the cost per frame on the real images, and uses avc1 only while the avc1 streams of the
    whole process together stay within a budget of wall-clock encoding time (default 0.5:
    encoding may take half of real time). Other streams get mp4v. The environment variables
    SENSORTEST_VIDEO_CODEC (auto|avc1|mp4v) and SENSORTEST_VIDEO_BUDGET override this.
    A file written as mp4v is transcoded to H.264 once the recording has ended (ffmpeg's
    libx264, preset ultrafast; rate correction in the same pass), so every video plays in a
    browser, at a cost paid after the listening window, not during it. The original mp4v file
    is kept when ffmpeg is missing or fails (said in the notes). SENSORTEST_VIDEO_TRANSCODE=0
    turns this off.
  * Frames of another size than the first are resized to the first size (counted); grey
    frames are converted to BGR.
  * The file is written under a temporary name (".<name>.writing.mp4") and renamed to its
    final name on close; close() is idempotent, and frames added after close are ignored and
    counted (`late`), so a late callback can never reopen or truncate a finished file.

WavWriter
  * Incremental PCM_16 WAV through soundfile, also written under a temporary name and renamed
    on close. Opened on the first write (no data, no file).
"""
import os
import queue
import shutil
import subprocess
import tempfile
import threading
import time

import numpy as np

from .stats import _rate

CODEC_CHOICES = ('auto', 'avc1', 'mp4v')
DEFAULT_BUDGET = 0.5
QUEUE_BYTES = 32 * 1024 * 1024
RATE_SPAN = 1.0          # seconds of frames buffered to measure the rate
RATE_MIN_FRAMES = 3
RATE_MAX_WAIT = 3.0      # open after this long even with fewer frames
RATE_MAX_FRAMES = 16     # or once this many frames are buffered (memory)
CALIBRATE_FRAMES = 4     # frames encoded with avc1 to measure its cost ('auto')
REMUX_TOLERANCE = 0.05


def _cv2():
    import cv2
    return cv2


def codec_preference():
    """The codec policy: SENSORTEST_VIDEO_CODEC (auto, avc1 or mp4v), default auto."""
    value = os.environ.get('SENSORTEST_VIDEO_CODEC', 'auto').strip().lower()
    return value if value in CODEC_CHOICES else 'auto'


def encoding_budget():
    try:
        return max(0.0, float(os.environ.get('SENSORTEST_VIDEO_BUDGET', DEFAULT_BUDGET)))
    except ValueError:
        return DEFAULT_BUDGET


_avc1_lock = threading.Lock()
_avc1_ok = None


def avc1_available():
    """True when this OpenCV build writes H.264 mp4 files (probed once per process)."""
    global _avc1_ok
    with _avc1_lock:
        if _avc1_ok is None:
            _avc1_ok = False
            cv2 = _cv2()
            fd, path = tempfile.mkstemp(suffix='.mp4')
            os.close(fd)
            try:
                writer = cv2.VideoWriter(path, cv2.VideoWriter_fourcc(*'avc1'), 10, (64, 48))
                if writer.isOpened():
                    for i in range(3):
                        writer.write(np.full((48, 64, 3), 40 * i, np.uint8))
                    writer.release()
                    _avc1_ok = os.path.getsize(path) > 0
            except Exception:
                _avc1_ok = False
            finally:
                os.unlink(path)
        return _avc1_ok


class _Budget:
    """Share of wall-clock time the process's avc1 encoders may use together.

    Calibrations run one at a time (`calibrating`): measured alone they are not inflated by
    each other, and only one H.264 encoder's buffers exist at once. `per_pixel` keeps the cost
    per pixel of the last measurement, so a stream that clearly cannot fit is given mp4v
    without being measured."""

    def __init__(self):
        self.lock = threading.Lock()
        self.calibrating = threading.Lock()
        self.committed = 0.0
        self.per_pixel = None

    def take(self, load, limit):
        with self.lock:
            if self.committed + load <= limit:
                self.committed += load
                return True
            return False

    def give(self, load):
        with self.lock:
            self.committed = max(0.0, self.committed - load)

    def left(self, limit):
        with self.lock:
            return max(0.0, limit - self.committed)


BUDGET = _Budget()


def ffprobe_frames(path):
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


class VideoRecorder:
    """One mp4 file per camera; see the module docstring for the rules."""

    def __init__(self, path, codec=None, fallback_fps=10.0, max_fps=240.0, queue_bytes=QUEUE_BYTES):
        self.path = path
        self.tmp_path = os.path.join(os.path.dirname(path) or '.',
                                     '.' + os.path.basename(path)[:-4] + '.writing.mp4')
        self.preference = codec or codec_preference()
        self.fallback_fps = float(fallback_fps)
        self.max_fps = float(max_fps)     # a burst at the start must not pass for the rate
        self.queue_bytes = queue_bytes
        self._queue = None
        self._thread = None
        self._lock = threading.Lock()
        self._closed = False
        self._writer = None
        self._buffer = []            # (frame, t) before the file is open
        self._times = []             # receive times of the written frames
        self._load = 0.0             # budget share taken by this recorder (avc1)
        self.size = None             # (width, height) of the file
        self.codec = None
        self.fps = None              # rate the file was opened with
        self.final_fps = None        # rate of the finished file
        self.received = 0
        self.written = 0
        self.dropped = 0
        self.resized = 0
        self.late = 0
        self.error = None
        self.notes = []
        self.first_frame = None
        self.last_frame = None

    # ---- subscriber side -------------------------------------------------------------
    def add(self, frame, t):
        """Queue one BGR (or grey) uint8 frame received at `t` seconds. Never blocks or raises."""
        with self._lock:
            if self._closed:
                self.late += 1
                return
            if self._thread is None:
                per_frame = max(1, frame.nbytes)
                self._queue = queue.Queue(maxsize=max(8, self.queue_bytes // per_frame))
                self._thread = threading.Thread(target=self._run, name='video:' + os.path.basename(self.path),
                                                daemon=True)
                self._thread.start()
            self.received += 1
            if self.first_frame is None:
                self.first_frame = frame
            self.last_frame = frame
            try:
                self._queue.put_nowait((frame, t))
            except queue.Full:
                self.dropped += 1

    def close(self, timeout=60.0):
        """Finish the file (drain the queue, release, fix the rate, rename). Idempotent."""
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
    def closed(self):
        return self._closed

    # ---- writer thread -----------------------------------------------------------------
    def _run(self):
        while True:
            item = self._queue.get()
            if item is None:
                break
            self._step(item)
        if self._writer is None and self._buffer and not self.error:
            self._step(None)
        self._finish()

    def _step(self, item):
        """Buffer, open or write; after an error the remaining frames are counted as dropped."""
        if self.error:
            self._count_dropped(1)
            return
        try:
            if self._writer is None:
                if item is not None:
                    self._buffer.append(item)
                if item is None or self._ready():
                    self._open()
            else:
                self._write(*item)
        except Exception as e:  # an encoder error must not kill the run
            self.error = 'video writer failed: %s' % e
            self._count_dropped(len(self._buffer) + (1 if self._writer is not None else 0))
            self._buffer = []

    def _count_dropped(self, n):
        with self._lock:
            self.dropped += n

    def _ready(self):
        span = self._buffer[-1][1] - self._buffer[0][1]
        n = len(self._buffer)
        return (span >= RATE_SPAN and n >= RATE_MIN_FRAMES) or span >= RATE_MAX_WAIT or n >= RATE_MAX_FRAMES

    def _open(self):
        cv2 = _cv2()
        first = self._buffer[0][0]
        self.size = (first.shape[1], first.shape[0])
        fps = _rate([t for _, t in self._buffer]) or self.fallback_fps
        self.fps = round(min(max(fps, 0.5), self.max_fps), 3)
        os.makedirs(os.path.dirname(self.path) or '.', exist_ok=True)
        for stale in (self.path, self.tmp_path):
            if os.path.exists(stale):
                os.unlink(stale)
        self.codec = self._choose_codec()
        writer = cv2.VideoWriter(self.tmp_path, cv2.VideoWriter_fourcc(*self.codec), self.fps, self.size)
        if not writer.isOpened() and self.codec == 'avc1':
            BUDGET.give(self._load)
            self._load = 0.0
            self.notes.append('avc1 writer did not open; using mp4v')
            self.codec = 'mp4v'
            writer = cv2.VideoWriter(self.tmp_path, cv2.VideoWriter_fourcc(*'mp4v'), self.fps, self.size)
        if not writer.isOpened():
            self.error = 'cannot open a video writer for %s' % self.path
            self._count_dropped(len(self._buffer))
            self._buffer = []
            return
        self._writer = writer
        buffered, self._buffer = self._buffer, []
        for frame, t in buffered:
            self._write(frame, t)

    def _choose_codec(self):
        if self.preference == 'mp4v' or not avc1_available():
            if self.preference == 'avc1':
                self.notes.append('this OpenCV build cannot write H.264 (avc1): mp4v used')
            return 'mp4v'
        if self.preference == 'avc1':
            return 'avc1'
        limit = encoding_budget()
        pixels = self.size[0] * self.size[1]
        with BUDGET.calibrating:
            if BUDGET.per_pixel is not None:
                guess = BUDGET.per_pixel * pixels * self.fps
                if guess > 1.5 * BUDGET.left(limit):
                    self.notes.append('mp4v chosen: avc1 would take about %.0f%% of real time at %.1f fps '
                                      '(from an earlier measurement), over the %.0f%% left for avc1 streams'
                                      % (100 * guess, self.fps, 100 * BUDGET.left(limit)))
                    return 'mp4v'
            cost = self._measure_avc1()
            if cost is not None:
                BUDGET.per_pixel = cost / pixels
        if cost is None:
            return 'mp4v'
        load = cost * self.fps
        if BUDGET.take(load, limit):
            self._load = load
            self.notes.append('avc1 chosen: %.1f ms/frame at %.1f fps = %.0f%% of real time '
                              '(budget %.0f%% for all avc1 streams)'
                              % (1000 * cost, self.fps, 100 * load, 100 * limit))
            return 'avc1'
        self.notes.append('mp4v chosen: avc1 would take %.1f ms/frame at %.1f fps = %.0f%% of real '
                          'time, over the %.0f%% left for avc1 streams'
                          % (1000 * cost, self.fps, 100 * load, 100 * BUDGET.left(limit)))
        return 'mp4v'

    def _measure_avc1(self):
        """Seconds per frame to encode some of the buffered frames with avc1 (into a scratch file)."""
        cv2 = _cv2()
        frames = [self._fit(f)[0] for f, _ in self._buffer[:CALIBRATE_FRAMES]]
        if len(frames) < 2:
            frames = frames * 3
        scratch = self.tmp_path[:-4] + '.calibrate.mp4'
        try:
            start = time.perf_counter()
            writer = cv2.VideoWriter(scratch, cv2.VideoWriter_fourcc(*'avc1'), self.fps, self.size)
            if not writer.isOpened():
                return None
            for frame in frames:
                writer.write(frame)
            writer.release()
            return (time.perf_counter() - start) / len(frames)
        finally:
            if os.path.exists(scratch):
                os.unlink(scratch)

    def _fit(self, frame):
        """(BGR frame of the file's size, whether it was resized)."""
        cv2 = _cv2()
        if frame.ndim == 2 or (frame.ndim == 3 and frame.shape[2] == 1):
            frame = cv2.cvtColor(frame, cv2.COLOR_GRAY2BGR)
        elif frame.shape[2] == 4:
            frame = cv2.cvtColor(frame, cv2.COLOR_BGRA2BGR)
        if (frame.shape[1], frame.shape[0]) != self.size:
            frame = cv2.resize(frame, self.size, interpolation=cv2.INTER_AREA)
            return frame, True
        return frame, False

    def _write(self, frame, t):
        fitted, resized = self._fit(frame)
        if resized:
            self.resized += 1
        self._writer.write(np.ascontiguousarray(fitted))
        self.written += 1
        self._times.append(t)

    def _finish(self):
        BUDGET.give(self._load)
        self._load = 0.0
        try:
            self._finalise()
        except Exception as e:   # e.g. the disk is full: report, never raise from the writer thread
            self.error = self.error or 'cannot finish %s: %s' % (os.path.basename(self.path), e)

    def _finalise(self):
        if self._writer is not None:
            self._writer.release()
            self._writer = None
        if not os.path.exists(self.tmp_path):
            return
        if not self.written:
            os.unlink(self.tmp_path)
            return
        # after an encoder error the frames written so far are kept
        self.final_fps = self.fps
        measured = _rate(self._times)
        scale = None
        if measured and abs(measured - self.fps) / measured > REMUX_TOLERANCE:
            scale = self.fps / measured
        transcode = self.codec == 'mp4v' and os.environ.get('SENSORTEST_VIDEO_TRANSCODE', '1') != '0'
        if transcode:
            # -r before -i re-times every frame at the final rate (none dropped or repeated)
            started = time.monotonic()
            rate = measured if scale is not None else self.fps
            if self._ffmpeg(['-r', '%.6f' % rate], ['-c:v', 'libx264', '-preset', 'ultrafast',
                                                    '-pix_fmt', 'yuv420p', '-movflags', '+faststart'],
                            'transcoding to H.264'):
                self.notes.append('written as mp4v, transcoded to H.264 after the window (%.1f s)'
                                  % (time.monotonic() - started))
                self.codec = 'avc1'
            else:
                transcode = False
        if scale is not None and not transcode:
            transcode = self._ffmpeg(['-itsscale', '%.6f' % scale], ['-c', 'copy'], 'rate correction')
        if scale is not None and transcode:
            self.notes.append('frame rate corrected from %.2f (first second) to %.2f fps '
                              '(whole recording)' % (self.fps, measured))
            self.final_fps = round(measured, 3)
        os.replace(self.tmp_path, self.path)

    def _ffmpeg(self, input_args, codec_args, what):
        """Rewrite the temporary file with ffmpeg (input options, codec options). True when
        done; on failure the file stays as it was and a note says why."""
        if not shutil.which('ffmpeg'):
            self.notes.append('ffmpeg not found: no %s' % what)
            return False
        fixed = self.tmp_path[:-4] + '.ffmpeg.mp4'
        cmd = ['ffmpeg', '-v', 'error', '-y'] + input_args + ['-i', self.tmp_path] + codec_args + ['-an', fixed]
        try:
            done = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
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
    def summary(self):
        return {'file': os.path.basename(self.path) if os.path.exists(self.path) and self.written else None,
                'codec': self.codec, 'fps': self.final_fps or self.fps,
                'width': self.size[0] if self.size else None,
                'height': self.size[1] if self.size else None,
                'frames_received': self.received, 'frames_written': self.written,
                'frames_dropped': self.dropped, 'frames_resized': self.resized,
                'late_frames': self.late, 'error': self.error}


def save_jpeg(path, image, quality=90):
    """Write one image as JPEG; True on success (never raises)."""
    try:
        cv2 = _cv2()
        return bool(cv2.imwrite(path, image, [cv2.IMWRITE_JPEG_QUALITY, quality]))
    except Exception:
        return False


class WavWriter:
    """Incremental PCM WAV file (soundfile), opened on the first write, renamed on close."""

    def __init__(self, path, samplerate, channels, subtype='PCM_16'):
        self.path = path
        self.tmp_path = os.path.join(os.path.dirname(path) or '.',
                                     '.' + os.path.basename(path)[:-4] + '.writing.wav')
        self.samplerate = int(samplerate)
        self.channels = int(channels)
        self.subtype = subtype
        self.frames = 0
        self.error = None
        self._file = None
        self._closed = False
        self._lock = threading.Lock()

    def write(self, samples):
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

    def close(self):
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
    def written(self):
        return self._closed and self._file is not None and self.error is None

    @property
    def seconds(self):
        return self.frames / float(self.samplerate)
