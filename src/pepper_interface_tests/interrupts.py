"""How a run answers Ctrl-C, SIGTERM and SIGHUP: one policy for the whole process.

Phases (set by cli and runner):
  start    before the plan is final: the first signal raises KeyboardInterrupt at once
           (nothing written yet; exit 130).
  defer    from the plan to the first tick of the runner (run folder, observers, the files'
           headers): signals are only remembered; the runner raises them once every output
           exists, so every selected sensor still appears in every output.
  run      while listening: the first signal raises KeyboardInterrupt (or Terminated for
           SIGTERM/SIGHUP) in the main thread AND is remembered, so that code which swallows the
           exception (a C library's import, a broad except) cannot hide it: the runner looks at
           `pending` on every tick.
  closing  while the result files are written: signals are only counted. The second interrupt
           never cuts the final write short; the third quits at once (os._exit(130), files may
           be incomplete).

Test hook (harmless in production, used by test/test_interrupts.py): with the environment
variable SENSORTEST_TEST_PAUSE=<point>:<seconds>[:swallow], `pause(point)` prints
"[test-pause] <point>" on stderr and sleeps there; with `:swallow` it also swallows a
KeyboardInterrupt raised during that sleep, as a C extension that clears Python errors does.
"""
import os
import signal
import time
from typing import Dict, Optional

NAMES: Dict[int, str] = {signal.SIGINT: 'interrupted by Ctrl-C', signal.SIGTERM: 'terminated (SIGTERM)',
         signal.SIGHUP: 'hung up (SIGHUP: terminal or ssh session closed)'}
SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


class Terminated(KeyboardInterrupt):
    """Raised in the main thread for SIGTERM/SIGHUP: ends the run like Ctrl-C."""


class Policy:
    def __init__(self) -> None:
        self._reset()

    def _reset(self):
        self.phase = 'start'
        self.count = 0
        self.first: Optional[int] = None    # the first signal's number

    @property
    def pending(self) -> bool:
        return self.first is not None

    def reason(self) -> str:
        return NAMES.get(self.first, 'interrupted') if self.first is not None else 'interrupted'

    def install(self) -> None:
        """Handle SIGINT, SIGTERM and SIGHUP from now on, starting afresh (phase 'start')."""
        self._reset()
        for sig in SIGNALS:
            signal.signal(sig, self._handle)

    def raise_pending(self) -> None:
        """Raise the remembered interrupt (for code that polls)."""
        if self.first is not None:
            raise (KeyboardInterrupt if self.first == signal.SIGINT else Terminated)()

    def _handle(self, signum, frame):
        self.count += 1
        if self.first is None:
            self.first = signum
        if self.count >= 3:
            _say('sensorTest: third interrupt: quitting now; result files may be incomplete\n')
            os._exit(130)
        if self.phase == 'closing':
            more = 3 - self.count
            _say('sensorTest: %s while writing the results: finishing them first (interrupt %s '
                 'more to quit at once)\n' % (NAMES.get(signum, 'signal'), 'once' if more == 1 else 'twice'))
            return
        if self.count == 1 and self.phase in ('start', 'run'):
            self.raise_pending()


def _say(text):
    try:
        os.write(2, text.encode('utf-8', 'replace'))
    except OSError:
        pass


POLICY = Policy()


def pause(point: str) -> None:
    """Test hook: see the module docstring. Does nothing unless SENSORTEST_TEST_PAUSE names `point`."""
    spec = os.environ.get('SENSORTEST_TEST_PAUSE', '')
    parts = spec.split(':')
    if len(parts) < 2 or parts[0] != point:
        return
    _say('[test-pause] %s\n' % point)
    try:
        time.sleep(float(parts[1]))
    except KeyboardInterrupt:
        if parts[2:] != ['swallow']:
            raise
