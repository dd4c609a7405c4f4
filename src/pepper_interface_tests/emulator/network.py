"""The emulator's `network` condition: what a busy WiFi between the robot and the PC does to
what crosses it (launch arg `network`, ~network; docs/emulator.md).

On a real Pepper checked from a laptop, naoqi_driver runs on the laptop and fetches from the
robot over the network: each camera frame (ALVideoDevice.getImageRemote) and the ALMemory
values of the other sensors; the microphones' buffers reach the audio bridge the same way.
A busy WiFi holds what crosses it for a moment and then lets it through at once.

`wifi`: the network is held now and then, every HOLD_EVERY s (drawn between its bounds), for
HOLD s (drawn between its bounds); what waits for it goes out when the hold ends. Where the
values come from: the pauses a healthy 48 kHz stream showed on a busy laptop in issue 41
(three pauses of 0.30-0.42 s in a 10.26 s window, each followed by the held buffers at once),
and naoqi_driver's own reports of WiFi delivery (issues #115 and #139 of ros-naoqi/naoqi_driver,
as issue 41 cites them: the depth camera at 2 Hz over WiFi, a "significant improvement" on
Ethernet). A frame or value fetched during a hold is fetched when it ends (naoqi_driver stamps
it then: converters/camera.cpp stamps after getImageRemote), so the driver's streams slow down
unevenly; audio buffers held are delivered together, so the bridge's stream comes in bursts.
"""
import random
import threading
import time
from typing import Optional, Tuple

NETWORKS = ('none', 'wifi')
HOLD = (0.30, 0.45)          # s a hold lasts (issue 41: pauses of 0.30-0.42 s)
HOLD_EVERY = (1.5, 3.5)      # s from one hold's end to the next one's start (three in ~10 s)


class Network:
    """The holds of one process's network (every stream of the process waits for the same)."""

    def __init__(self, seed: int = 0, start: Optional[float] = None) -> None:
        self._rng = random.Random(seed)
        self._lock = threading.Lock()
        now = time.monotonic() if start is None else start
        self._hold = self._next(now)

    def _next(self, after: float) -> Tuple[float, float]:
        begin = after + self._rng.uniform(*HOLD_EVERY)
        return begin, begin + self._rng.uniform(*HOLD)

    def wait(self, now: float) -> float:
        """Seconds what wants to cross the network at `now` (monotonic) must wait (0.0: none)."""
        with self._lock:
            while now >= self._hold[1]:
                self._hold = self._next(self._hold[1])
            begin, end = self._hold
            return end - now if now >= begin else 0.0


def network_of(kind: str, seed: int = 0) -> Optional[Network]:
    """The Network of a `network` setting ('none': None)."""
    return Network(seed) if kind == 'wifi' else None
