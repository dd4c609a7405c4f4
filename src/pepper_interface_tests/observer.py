"""The seam between the runner and everything that shows or keeps its results.

The runner calls these methods, in this order, on every observer it was given (outputs/:
the terminal, the results files, the history, /diagnostics, the report, the live view):

    run_started(run, plan)      once, before the first window; every output exists after it
    sensor_started(progress)    a sensor's window opens
    tick(progresses, now)       every 50 ms while windows are open
    nothing_published(...)      once, when no listened-to topic has any publisher
    sensor_done(result)         a sensor's verdict, as soon as it is known
    run_ended(run)              once, with every verdict (also after an interrupt)

Observers see a running window only as a frozen `Progress` snapshot taken by the runner (never
the window itself or its lock), and a finished one as its SensorResult.

An observer subclasses RunObserver and overrides what it needs; the others do nothing.
`Observers` calls one method on each in turn: an observer that raises is named on stderr and
the others still run (Ctrl-C, a KeyboardInterrupt, still ends the run).
"""
import sys
from typing import Callable, Iterable, List, Optional, Sequence

from .plan.model import TestPlan
from .progress import Progress
from .results import RunResult, SensorResult
from .sources import Graph, ros1_graph


def no_publisher_at_all(graph: Optional[Graph]) -> str:
    """The reason every listened-to sensor fails with when nothing at all is published (after
    "no publisher on <topic>: "); the terminal says it once, at the start, with the likely causes."""
    graph = graph or ros1_graph('')
    return 'no sensor topic of this run has a publisher %s (robot off, %s, driver not started?)' % (
        graph.place, graph.other)


class RunObserver:
    """No-op base: override the events an output needs."""

    def run_started(self, run: RunResult, plan: TestPlan) -> None:
        pass

    def sensor_started(self, progress: Progress) -> None:
        pass

    def tick(self, progress: Sequence[Progress], now: float) -> None:
        pass

    def nothing_published(self, topics: List[str], waited: float, graph: Optional[Graph]) -> None:
        pass

    def sensor_done(self, result: SensorResult) -> None:
        pass

    def run_ended(self, run: RunResult) -> None:
        pass


class Observers(RunObserver):
    """Every observer of a run, called in the order given."""

    def __init__(self, observers: Iterable[RunObserver] = ()) -> None:
        self.members: List[RunObserver] = list(observers)

    def _each(self, event: str, call: Callable[[RunObserver], None]) -> None:
        for o in self.members:
            try:
                call(o)
            except Exception as e:
                sys.stderr.write('sensorTest: %s.%s failed: %s: %s\n'
                                 % (type(o).__name__, event, type(e).__name__, e))

    def run_started(self, run: RunResult, plan: TestPlan) -> None:
        self._each('run_started', lambda o: o.run_started(run, plan))

    def sensor_started(self, progress: Progress) -> None:
        self._each('sensor_started', lambda o: o.sensor_started(progress))

    def tick(self, progress: Sequence[Progress], now: float) -> None:
        self._each('tick', lambda o: o.tick(progress, now))

    def nothing_published(self, topics: List[str], waited: float, graph: Optional[Graph]) -> None:
        self._each('nothing_published', lambda o: o.nothing_published(topics, waited, graph))

    def sensor_done(self, result: SensorResult) -> None:
        self._each('sensor_done', lambda o: o.sensor_done(result))

    def run_ended(self, run: RunResult) -> None:
        self._each('run_ended', lambda o: o.run_ended(run))
