"""Live view of the cameras: one OpenCV window per sensor, titled with the sensor's name.

GUI calls happen only in the thread that calls `pump()` (the runner's main thread);
checks call `post()` from their subscriber threads, which only stores the latest frame.
`Viewer.create(enabled)` returns None, after printing one line "live view off: <reason>",
when the view is disabled, there is no DISPLAY, OpenCV has no GUI support (headless build),
or no window can be opened on the display (probed in a child process first, because Qt
aborts the whole process when it cannot reach the display). Nothing fails for lack of a display.
"""
import os
import re
import subprocess
import sys
import tempfile
import threading
from typing import TYPE_CHECKING, Dict, List, Optional

if TYPE_CHECKING:
    import numpy

MAX_WIDTH = 1280   # wider frames (large stereo modes) are shown scaled down

_PROBE = ("import cv2, numpy; cv2.namedWindow('probe'); "
          "cv2.imshow('probe', numpy.zeros((8, 8, 3), numpy.uint8)); cv2.waitKey(1); "
          "cv2.destroyAllWindows(); cv2.waitKey(1)")


def gui_support() -> Optional[str]:
    """The GUI backend OpenCV was built with, or None for a headless build."""
    try:
        import cv2
    except ImportError:
        return None
    match = re.search(r'^\s*GUI:\s*(\S+)', cv2.getBuildInformation(), re.M)
    if match is None or match.group(1).upper() in ('NONE', 'NO'):
        return None
    return match.group(1)


def unavailable_reason(enabled: bool = True) -> Optional[str]:
    """Why there can be no live view, or None when there can be one."""
    if not enabled:
        return 'disabled'
    if not os.environ.get('DISPLAY'):
        return 'no DISPLAY'
    if gui_support() is None:
        return 'OpenCV has no GUI support (headless build)'
    try:
        probe = subprocess.run([sys.executable, '-c', _PROBE], capture_output=True, text=True, timeout=20)
    except subprocess.TimeoutExpired:
        return 'no window could be opened on DISPLAY=%s (timed out)' % os.environ['DISPLAY']
    if probe.returncode != 0:
        last = (probe.stderr.strip().splitlines() or ['exit code %d' % probe.returncode])[-1]
        return 'no window could be opened on DISPLAY=%s (%s)' % (os.environ['DISPLAY'], last[:120])
    return None


class Viewer:
    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._latest: Dict[str, numpy.ndarray] = {}      # window name -> newest frame not shown yet
        self._windows: List[str] = []
        self.shown: Dict[str, int] = {}        # window name -> frames shown
        self.posted: Dict[str, int] = {}       # window name -> frames posted
        self.failed: Optional[str] = None

    @classmethod
    def create(cls, enabled: bool = True) -> Optional['Viewer']:
        if not os.environ.get('XDG_RUNTIME_DIR'):   # Qt complains on every start without it
            runtime = os.path.join(tempfile.gettempdir(), 'runtime-%d' % os.getuid())
            os.makedirs(runtime, mode=0o700, exist_ok=True)
            os.environ['XDG_RUNTIME_DIR'] = runtime
        reason = unavailable_reason(enabled)
        if reason:
            print('live view off: ' + reason, flush=True)
            return None
        return cls()

    def post(self, name: str, image: 'numpy.ndarray') -> None:
        """Keep `image` (BGR) as the newest frame of window `name`. Any thread; never blocks long."""
        with self._lock:
            self._latest[name] = image
            self.posted[name] = self.posted.get(name, 0) + 1

    def pump(self) -> None:
        """Show the newest frames and let the GUI breathe. Call from one thread only, ~every 50 ms."""
        if self.failed:
            return
        with self._lock:
            frames, self._latest = self._latest, {}
        try:
            import cv2
            for name, image in frames.items():
                if name not in self._windows:
                    cv2.namedWindow(name, cv2.WINDOW_AUTOSIZE)
                    column, row = len(self._windows) % 3, len(self._windows) // 3
                    cv2.moveWindow(name, 20 + column * (MAX_WIDTH // 2 + 20), 20 + row * 300)
                    self._windows.append(name)
                if image.shape[1] > MAX_WIDTH:
                    scale = MAX_WIDTH / float(image.shape[1])
                    image = cv2.resize(image, (MAX_WIDTH, max(1, int(image.shape[0] * scale))))
                cv2.imshow(name, image)
                self.shown[name] = self.shown.get(name, 0) + 1
            cv2.waitKey(1)
        except Exception as e:   # a broken display must not break the run
            self.failed = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
            print('live view off: %s' % self.failed, flush=True)

    def close(self) -> None:
        if not self._windows:
            return
        try:
            import cv2
            for name in self._windows:
                cv2.destroyWindow(name)
            cv2.waitKey(1)
        except Exception:
            pass
        self._windows = []
