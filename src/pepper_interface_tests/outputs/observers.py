"""Observers that turn a run into files and shared services.

ResultFiles: sensorTestOutput.dat block by block as sensors finish (so an interrupted run still
has every finished block, then [INTERRUPTED] and END TIME), then the formats of
outputs/formats.py written whole at the end, in the table's order (JUnit, then the JSON).
A file that cannot be written (full disk, ...) is named on
stderr and recorded in run.write_errors, which makes the exit code 3; the run goes on.
SpeechHearing: while the speech check runs and the microphone is part of the run, a
microphone level monitor is offered to it (ctx.services.microphone_levels).
Guidance: in guided mode, an operator that prompts is offered to the touch checks
(ctx.services.operator).
"""
import os
import sys
import time
from typing import TYPE_CHECKING, List, Optional, Sequence, TextIO

from .. import results
from ..observer import RunObserver
from ..progress import Progress
from ..sensors.families import family, traits
from . import files, formats
from .atomicfile import write_error
from .terminal import fill, under_roslaunch

if TYPE_CHECKING:
    from ..media.viewer import Viewer
    from ..plan.settings import TestPlan
    from ..sensors.audio import LevelMonitor
    from ..sensors.base import RunContext
    from ..sensors.guide import Guide
    from .history import RunFolder


class ResultFiles(RunObserver):
    def __init__(self, output_dir: str, out: Optional[TextIO] = None) -> None:
        self.dir = output_dir
        self.dat: Optional[files.OutputFile] = None
        self.out = out
        self.run: Optional[results.RunResult] = None

    def _dat(self, method: str, *args: object) -> None:
        if self.dat is None or self.run is None:     # run is set before dat is opened
            return
        try:
            getattr(self.dat, method)(*args)
        except OSError as e:
            write_error(self.run, self.dat.path, e)
            self.dat.close()
            self.dat = None

    def run_started(self, run: results.RunResult, plan: 'TestPlan') -> None:
        self.run = run
        path = os.path.join(self.dir, results.OUTPUT_FILE)
        try:
            self.dat = files.OutputFile(path)
        except OSError as e:
            write_error(run, path, e)
            return
        self._dat('begin', run)

    def sensor_done(self, result: results.SensorResult) -> None:
        self._dat('sensor', result)

    def run_ended(self, run: results.RunResult) -> None:
        self.run = run
        self._dat('end', run)
        self._dat('close')
        for output in formats.written_at_end():
            path = os.path.join(self.dir, output.file)
            try:
                if output.render is not None:
                    output.render(run, path)
            except OSError as e:
                write_error(run, path, e)
        stream = self.out or sys.stdout
        stream.write(fill('results in %s: %s' % (self.dir, ', '.join(formats.results_files()))) + '\n')
        stream.flush()


class SpeechHearing(RunObserver):
    """Starts a microphone level monitor for the speech check when the microphone is in the run."""

    def __init__(self, plan: 'TestPlan', ctx: 'RunContext') -> None:
        self.ctx = ctx
        mics = [s for s in plan.active if traits(s.sensor).audio]
        self.mic_topic = mics[0].topic if mics else None
        self.hearing = {s.name for s in plan.active if traits(s.sensor).hears}
        self.monitor: Optional[LevelMonitor] = None

    def sensor_started(self, progress: Progress) -> None:
        if not family(progress.family).traits.hears or not self.mic_topic:
            return
        try:
            from ..sensors.audio import LevelMonitor
        except ImportError:
            return
        self.monitor = LevelMonitor(self.mic_topic)
        self.monitor.start()
        self.ctx.services.microphone_levels = self.monitor

    def sensor_done(self, result: results.SensorResult) -> None:
        if self.monitor is not None and result.name in self.hearing:
            self.monitor.stop()
            self.ctx.services.microphone_levels = None
            self.monitor = None

    def run_ended(self, run: results.RunResult) -> None:
        if self.monitor is not None:
            self.monitor.stop()


class Guidance(RunObserver):
    """Guided mode (a person is there: a terminal or --guided) in a live run with touch sensors:
    offers the touch checks an operator that prompts (sensors/guide.py), tells it which of them
    are still to ask (so that a zone given up says "next zone" or "no zone left"), and publishes
    "[done]" once every one of them has finished."""

    def __init__(self, plan: 'TestPlan', ctx: 'RunContext') -> None:
        self.plan, self.ctx = plan, ctx
        self.guided = {s.name for s in plan.active if traits(s.sensor).guided}
        self.guide: Optional[Guide] = None

    def run_started(self, run: results.RunResult, plan: 'TestPlan') -> None:
        from ..plan.settings import read_topics
        from ..sensors import guide, touch
        active = [s for s in plan.active if s.name in self.guided]
        try:
            speech: Optional[str] = read_topics(plan.files['topics']).get('speech')
        except Exception:   # the plan read it already; a speech topic is optional here
            speech = None
        wait = plan.options.touch_wait or touch.TOUCH_WAIT
        total = guide.budget([len(touch.asked_zones(s.sensor.msg_type)) for s in active], wait,
                             max(getattr(s.expect, 'max_press', 0.0) for s in active))
        self.guide = guide.Guide(total, speech, owners=[s.name for s in active])
        self.ctx.services.operator = self.guide

    def sensor_done(self, result: results.SensorResult) -> None:
        self.guided.discard(result.name)
        if self.guide is not None:
            self.guide.ended(result.name)
        if not self.guided and self.guide is not None and self.ctx.services.operator is not None:
            self.ctx.services.operator = None
            self.guide.done()

    def run_ended(self, run: results.RunResult) -> None:
        if self.guide is not None:
            if self.ctx.services.operator is not None:   # interrupted: the guided part ends too
                self.ctx.services.operator = None
                self.guide.done()
            time.sleep(0.3)         # let "[done]" reach the prompt's subscribers
            self.guide.close()
            self.guide = None


class LiveView(RunObserver):
    """One window per camera, drawn from the main thread (the runner's tick), when a display
    and OpenCV GUI support exist; otherwise one line says why and the run goes on."""

    def __init__(self, ctx: 'RunContext') -> None:
        self.ctx = ctx
        self.viewer: Optional[Viewer] = None

    def run_started(self, run: results.RunResult, plan: 'TestPlan') -> None:
        from ..media.viewer import Viewer
        self.viewer = Viewer.create(enabled=plan.options.show is not False)
        if self.viewer is not None:
            self.ctx.services.viewer = self.viewer

    def tick(self, progress: Sequence[Progress], now: float) -> None:
        if self.viewer is not None:
            self.viewer.pump()

    def run_ended(self, run: results.RunResult) -> None:
        if self.viewer is not None:
            self.ctx.services.viewer = None
            self.viewer.close()
            self.viewer = None


def observers_for(plan: 'TestPlan', ctx: 'RunContext', source_name: str,
                  folder: Optional['RunFolder'] = None) -> List[RunObserver]:
    """The run's observers, in the order they are called. `plan.output_dir` is where this run's
    files go; `folder` (history.RunFolder) says whether that is a run folder under
    <output_dir>/runs, whose files are then also published into the output folder."""
    opts = plan.options
    obs: List[RunObserver] = []
    if source_name == 'live':
        obs.append(SpeechHearing(plan, ctx))
        from ..sensors.guide import guided_mode
        if any(traits(s.sensor).guided for s in plan.active) and \
                guided_mode(opts.guided, launched=under_roslaunch()):
            obs.append(Guidance(plan, ctx))
        if any(traits(s.sensor).images for s in plan.active):
            obs.append(LiveView(ctx))
        if opts.diagnostics is not False:
            from .diagnostics import LiveDiagnostics
            obs.append(LiveDiagnostics(plan))
    obs.append(ResultFiles(plan.output_dir))
    if opts.report is not False:
        from .report import HtmlReport
        obs.append(HtmlReport(plan.output_dir))
    if folder is not None and folder.kept:
        from .history import LatestRun
        obs.append(LatestRun(folder))     # last: publishes the files the others wrote
    return obs
