"""Listen to each sensor for its window, sequentially or in parallel: scheduling only.

Data flow: TestPlan -> lanes (sequential: one lane of all sensors in input order; parallel: one
lane per sensor, except that simulator image streams share one lane) -> one window
(sensors/window.py SensorRun) at a time per lane -> SensorResult -> observers (output file,
terminal, diagnostics ...), which see running windows only as frozen Progress snapshots.

What a window judges is not here: the generic stream rules are sensors/stream.py, each family's
rules its module in sensors/, composed by sensors/window.py. Everything runs in the main thread
except subscriber callbacks, which touch only their own window under its lock, and the closing
of a window that has ended (finishing a video takes a moment), which runs in a thread of its
own. The main loop ticks every 50 ms; a window ends on time, on --quick once the verdict is
settled, when no message came within --wait, or on Ctrl-C.
"""
import threading
import time
from typing import Callable, Dict, Iterable, List, Optional, Tuple

from . import interrupts
from .motion import recorded
from .motion.record import Recording
from .observer import Observers, RunObserver, no_publisher_at_all
from .plan.settings import SensorPlan, TestPlan
from .progress import Snapshots
from .results import FAIL, SKIPPED, RunResult, SensorResult
from .sensors import cross, tree
from .sensors.base import RunContext
from .sensors.families import traits
from .sensors.stiffness import witnesses
from .sensors.stream import no_publisher_note
from .sensors.window import SensorRun, skipped_result
from .sources import Listener, Source, SourceLost

TICK = 0.05


def lanes_for(plan: TestPlan, live: bool = True) -> List[List[SensorPlan]]:
    """Which sensors run one after another: a list of lanes, each a list of SensorPlans.

    Gazebo fails when several cameras stream at once, so live simulator image streams
    (Traits.images) share one lane even in parallel mode; a bag replay has no such limit."""
    if plan.mode == 'sequential':
        return [list(plan.sensors)]
    lanes: List[List[SensorPlan]] = []
    cameras: List[SensorPlan] = []
    serial_cameras = live and plan.platform == 'simulator'
    for s in plan.sensors:
        if serial_cameras and traits(s.sensor).images and s.skip_reason is None:
            if not cameras:
                lanes.append(cameras)   # keeps the position of the first camera
            cameras.append(s)
        else:
            lanes.append([s])
    return lanes


class Runner:
    """Drives the lanes from the main thread. `source` subscribes (live) or feeds (bag)."""

    def __init__(self, plan: TestPlan, ctx: RunContext, source: Source, observers: Iterable[RunObserver] = (),
                 clock: Callable[[], float] = time.monotonic, wall: Callable[[], float] = time.time,
                 signals: Optional[interrupts.Policy] = None) -> None:
        self.plan = plan
        self.signals = signals if signals is not None else interrupts.Policy()
        self.ctx = ctx
        self.source = source
        self.observers = Observers(observers)
        self.clock = clock
        self.run = RunResult(platform=plan.platform, mode=plan.mode, start=wall(),
                             output_dir=plan.output_dir, files=dict(plan.files))
        self.wall = wall
        self.start = 0.0       # clock() when execute() began
        self.lanes: List[List[SensorPlan]] = []
        self.current: List[Optional[SensorRun]] = []   # per lane: the running SensorRun or None
        self.results: Dict[str, SensorResult] = {}     # sensor name -> SensorResult
        self.closing: List[Tuple[SensorRun, threading.Thread]] = []   # windows ended, writers still closing
        self.order = [s.name for s in plan.sensors]
        self.motion_rec: Optional[Recording] = None    # a recording's motion witnesses (bag runs)
        self.held: List[SensorResult] = []     # their rows, told to the observers once judged
        self.witnesses: List[Listener] = []    # listeners a check asks about the robot (sensors/stiffness.py)

    def _start_next(self, i, now):
        # a plan leaves its lane only once it is recorded as running (or done): an interrupt at
        # any point in here leaves it either in the lane ("not run") or in current (closed)
        lane = self.lanes[i]
        self.current[i] = None
        while lane:
            plan = lane[0]
            if plan.skip_reason is None and not traits(plan.sensor).leads and self._leading():
                return     # started by the main loop once the leading windows are done
            if plan.skip_reason is not None:
                self._done(skipped_result(plan, self.start, now))
                lane.pop(0)
                continue
            interrupts.pause('sensor-start')
            run = SensorRun(plan, self.ctx, self.start, quick=self.plan.quick,
                            wait=self.plan.wait, duration=self.plan.duration)
            run.begin(now)
            self.current[i] = run
            lane.pop(0)
            self.source.attach(run)
            self.observers.sensor_started(run.progress(now))
            return

    def _leading(self) -> bool:
        """A leading window (Traits.leads: the motion check) is still to run, running or
        closing: the other windows wait, so they neither watch the robot move nor are judged
        before its findings about them (RunContext.findings) exist."""
        if any(r is not None and traits(r.sensor).leads for r in self.current):
            return True
        if any(traits(r.sensor).leads for r, _ in self.closing):
            return True
        return any(traits(p.sensor).leads and p.skip_reason is None for ln in self.lanes for p in ln)

    def _done(self, result):
        self.results[result.name] = result
        if self.motion_rec is not None and result.name in recorded.ROLES:
            self.held.append(result)    # its verdict may change with the recorded motion (cross.py)
            return
        self.observers.sensor_done(result)

    def _finish(self, i, now, reason):
        """End lane i's window at `now` and close its check in the background (video files
        take a moment to finalise; other windows must not wait for that)."""
        run = self.current[i]
        run.stop(now, reason)
        self.source.detach(run)
        self.current[i] = None
        thread = threading.Thread(target=self._close_run, args=(run, now), daemon=True,
                                  name='close-' + run.sensor.name)
        thread.start()
        self.closing.append((run, thread))

    def _close_run(self, run, now):
        try:
            run.close(now, run.end_reason, self.source.lookup)
        except Exception as e:  # judging must not lose the sensor: report it as a failure
            run.result = SensorResult(name=run.sensor.name, title=run.sensor.title,
                                      topic=run.plan.topic, msg_type=run.sensor.msg_type,
                                      family=run.sensor.family, verdict=FAIL,
                                      reasons=['internal error while judging: %s' % e],
                                      messages=run.stats.count)

    def _collect(self, wait=False):
        """Report the sensors whose closing has finished (all of them with wait=True)."""
        for run, thread in list(self.closing):
            if wait:
                thread.join()
            if not thread.is_alive():
                self.closing.remove((run, thread))
                self._done(run.result)

    def execute(self) -> RunResult:
        """Run every lane to its end (or to an interrupt). Returns the RunResult."""
        self.start = self.clock()
        self.lanes = [list(ln) for ln in lanes_for(self.plan, live=self.source.live)]
        self.current = [None] * len(self.lanes)
        self.observers.run_started(self.run, self.plan)
        try:
            # every output exists now: an interrupt remembered during start-up ends the run here
            self.signals.phase = 'run'
            self.signals.raise_pending()
            interrupts.pause('run-started')
            self._nothing_published()
            # before the first window: a bag then reads their topics from its start
            self.witnesses = list(witnesses(self.plan, self.ctx)) + tree.witnesses(self.plan, self.ctx)
            if not self.source.live:   # a recording's own motion (sensors/cross.py)
                self.motion_rec = Recording()
                self.witnesses += recorded.listeners(self.ctx.topics, self.motion_rec,
                                                     [s.name for s in self.plan.active])
            for witness in self.witnesses:
                self.source.attach(witness)
            for i in range(len(self.lanes)):
                self._start_next(i, self.clock())
            while any(self.current) or self.closing or any(self.lanes):
                now = self.clock()
                for i, run in enumerate(self.current):
                    if run is None and self.lanes[i]:   # held while a leading window ran
                        self._start_next(i, now)
                due = []
                for i, run in enumerate(self.current):
                    if run is None:
                        continue
                    self.source.poll(run, now)
                    run.poll(now)
                    reason = run.due(now)
                    if reason:   # every window due now ends now; closing writers comes after
                        run.stop(now, reason)
                        due.append(i)
                for i in due:
                    self._finish(i, now, '')
                    self._start_next(i, self.clock())
                self._collect()
                # snapshots taken only when an observer reads them (progress.Snapshots)
                self.observers.tick(Snapshots([r.progress for r in self.current if r], now), now)
                # an interrupt whose exception was swallowed (by a C library, a broad except)
                self.signals.raise_pending()
                self.source.sleep(TICK)
        except interrupts.Terminated:
            self.interrupt(self.signals.reason() if self.signals.pending else 'terminated (SIGTERM)')
        except KeyboardInterrupt:
            self.interrupt(self.signals.reason() if self.signals.pending else 'interrupted by Ctrl-C')
        except SourceLost as e:
            self.interrupt(str(e))
        finally:
            self.signals.phase = 'closing'   # from here on, interrupts never cut the files short
            self._close_everything()
        return self.run

    def _nothing_published(self):
        """Live runs: when not one listened-to topic of the plan has a publisher on the master
        (robot off, wrong ROS_MASTER_URI, driver not started), say so once within --wait and fail
        those sensors with that reason, instead of waiting --wait per sensor in turn. Only other
        nodes count (Source.published_topics): this node publishes /diagnostics itself."""
        probe = self.source.published_topics
        plans = [p for lane in self.lanes for p in lane
                 if p.skip_reason is None and not traits(p.sensor).drives_itself]
        if not plans:
            return
        deadline = self.clock() + self.plan.wait
        while True:
            published = probe()
            if published is None or any(p.topic in published for p in plans):
                return        # a master problem is the master watch's job; something is there
            if self.clock() >= deadline:
                break
            self.signals.raise_pending()
            self.source.sleep(0.25)
        now = self.clock()
        self.observers.nothing_published([p.topic for p in plans if p.topic is not None], self.plan.wait,
                                       self.source.graph_words)
        for lane in self.lanes:
            for p in [p for p in lane if p in plans]:
                self._done(skipped_result(p, self.start, now, FAIL, [
                    'no publisher on %s: %s%s' % (p.topic, no_publisher_at_all(self.source.graph_words),
                                                   no_publisher_note(p.sensor.name))]))
                lane.remove(p)

    def interrupt(self, why: str) -> None:
        self.signals.phase = 'closing'
        self.run.interrupted = True
        self.run.interrupt_reason = why
        self.ctx.interrupted_by = why

    def _close_everything(self):
        """Close running windows and mark sensors that never ran; always completes."""
        now = self.clock()
        for i, run in enumerate(self.current):
            if run is not None:
                try:
                    self._finish(i, now, 'interrupted')
                except Exception as e:  # keep closing the others
                    self.run.interrupt_reason += '; %s: %s' % (run.sensor.name, e)
        self._collect(wait=True)
        for witness in self.witnesses:
            self.source.detach(witness)     # never waits for the master (sources/live.py)
        self.ctx.services.stiffness = None
        self.ctx.services.tree = None
        self.witnesses = []
        for lane in self.lanes:
            for plan in lane:
                if plan.name in self.results:   # interrupted between starting it and popping it
                    continue
                self._done(skipped_result(plan, self.start, now, SKIPPED,
                                          ['not run: the run was interrupted before it started']))
            del lane[:]
        self.run.sensors = [self.results[n] for n in self.order if n in self.results]
        cross.apply(self.run.sensors, self.motion_rec)     # findings that need two rows (sensors/cross.py)
        for result in self.held:
            self.observers.sensor_done(result)
        self.held = []
        self.run.end = self.wall()
        interrupts.pause('final-write')
        self.observers.run_ended(self.run)
