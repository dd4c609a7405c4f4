"""The clock a listening window is measured on: wall time, or simulation time under /use_sim_time.

Under /use_sim_time a window lasts `window` seconds of simulation time, so a simulator slower
than real time still delivers a full window of messages; a simulator slower than MIN_RTF (or
paused) ends the window after window / MIN_RTF seconds of wall time. --wait stays wall time.
"""
from typing import Callable, Optional

MIN_RTF = 0.25


class WindowClock:
    """When a window began and ended, on the runner's clock and, on sim time, on /clock."""

    def __init__(self) -> None:
        self.t0: Optional[float] = None                        # runner clock when listening began
        self.sim_clock: Optional[Callable[[], float]] = None   # simulation time (s) under /use_sim_time
        self.sim_t0: Optional[float] = None                    # simulation time when listening began
        self.sim_stopped_at: Optional[float] = None            # simulation time when the window ended

    @property
    def began(self) -> float:
        if self.t0 is None:
            raise RuntimeError('the window has not begun: call begin() first')
        return self.t0

    @property
    def on_sim_time(self) -> bool:
        return self.sim_clock is not None

    def sim_start(self) -> Optional[float]:
        """Simulation time when listening began, once /clock has started (None before)."""
        if self.sim_t0 is None and self.sim_clock is not None:
            t = self.sim_clock()
            if t > 0:
                self.sim_t0 = t
        return self.sim_t0

    def elapsed(self, now: float) -> float:
        """Seconds the window has run, on the clock windows are measured on (see MIN_RTF)."""
        wall = now - self.began
        if self.sim_clock is None:
            return wall
        start = self.sim_start()
        sim = self.sim_clock() - start if start is not None else 0.0
        return max(sim, wall * MIN_RTF)

    def stop(self) -> None:
        """The window ends now: remember the simulation time it ended at."""
        if self.sim_clock is not None:
            self.sim_stopped_at = self.sim_clock()

    def real_time_factor(self, elapsed: float) -> Optional[float]:
        """Simulation seconds per wall second over the window, when /clock ran."""
        if self.sim_t0 is None or self.sim_stopped_at is None or elapsed <= 0:
            return None
        return round((self.sim_stopped_at - self.sim_t0) / elapsed, 3)
