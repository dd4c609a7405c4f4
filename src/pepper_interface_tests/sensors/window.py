"""One sensor's listening window: raw messages in, one SensorResult out.

A source (sources/) feeds the window through the `sources.Listener` protocol: (type name,
serialized bytes, receive time, ROS time, connection header, and from a live source how this
process handled it, for sensorTest's own lag: sensors/lag.py). The window decodes each message
once and hands it to two checks, composed as diagnostic_updater composes a TopicDiagnostic:
the generic StreamCheck (stream.py: arrival, type, rate, stamps, publishers) and the family's
own Check (its module in sensors/). At the end it merges their judgements by the worse verdict.
Subscriber callbacks call `feed_raw` from their own threads; everything else runs in the
runner's thread; `lock` guards what both touch. Observers see the window only through the
frozen `progress()` snapshot.
"""
import dataclasses
import math
import threading
import time
from typing import Any, Callable, Dict, List, Optional, Type

from ..plan.settings import SensorPlan
from ..progress import Progress
from ..results import INTERRUPTED, NOT_JUDGED, SKIPPED, SensorResult, Verdict
from ..sources import messages
from ..sources.handling import Handling
from .base import Check, RunContext, fmt
from .clock import WindowClock
from .families import Traits, of, traits
from .frames import FramePlacer
from .lag import OwnLag
from .stream import Lookup, StreamCheck


class SensorRun:
    """A sensor's window: the composition of its StreamCheck and its family's Check."""

    def __init__(self, plan: SensorPlan, ctx: RunContext, run_start: float, quick: bool = False,
                 wait: float = 5.0, duration: float = 10.0) -> None:
        self.plan = plan
        self.sensor = plan.sensor
        self.expect = plan.expect
        self.traits: Traits = traits(plan.sensor)
        self.check: Check = of(plan.sensor).check_class()(plan, ctx)
        self.ctx = ctx
        self.run_start = run_start
        self.quick = quick
        self.wait = wait
        self.window = self.check.window(duration)
        self.lock = threading.Lock()
        self.clock = WindowClock()
        self.stream = StreamCheck(plan.sensor, plan.topic, plan.expect, self.traits, self.clock)
        # how late this process handles the topic (a live source measures it: sensors/lag.py)
        self.own_lag = OwnLag()
        self.stream.own_lag = self.check.own_lag = self.own_lag
        # its messages' frame in the run's transform tree (sensors/frames.py)
        self.frames = FramePlacer(ctx.services.tree)
        # type name -> class (audio: several)
        self.classes: Dict[str, Type[Any]] = {self.sensor.msg_type: messages.message_class(self.sensor.msg_type)}
        # a check may decode its messages itself (images: no copy of the pixels)
        self.decode: Optional[Callable[[bytes], Any]] = getattr(self.check, 'decode', None)
        self.stopped_at: Optional[float] = None   # end of the window (set by stop(); no feeding after it)
        self.closed = False
        self.result: Optional[SensorResult] = None
        self.end_reason = ''

    # ---------------------------------------------------------------- what a source asks (Listener)
    @property
    def topic(self) -> str:
        """The topic this window listens to (every sensor that is run has one: settings.load_plan)."""
        if self.plan.topic is None:
            raise ValueError('%s has no topic to listen to' % self.sensor.name)
        return self.plan.topic

    @property
    def listens(self) -> bool:
        return not self.traits.drives_itself

    @property
    def queue_size(self) -> int:
        return self.check.queue_size

    @property
    def buff_size(self) -> int:
        return self.check.buff_size

    def use_sim_clock(self, sim_clock: Callable[[], float]) -> None:
        """The source runs on simulation time (/use_sim_time): windows and rates on `sim_clock`
        (a callable returning the simulation time in seconds). Call before the first message."""
        with self.lock:
            self.clock.sim_clock = sim_clock
            self.stream.use_sim_clock()
            self.stream.sync_sim_start()

    def use_record_clock(self) -> None:
        self.stream.use_record_clock()

    def observe_connections(self, n: int, now: float) -> None:
        self.stream.observe_connections(n, now)
        self.check.observe_connections(n)

    def feed_raw(self, type_name: str, buff: bytes, t_recv: float, ros_now: float,
                 conn: Optional[Dict[str, Any]] = None, own: Optional[Handling] = None) -> None:
        """One message as it came off the wire (or out of a bag); `conn` is its connection
        header (type, message_definition, callerid) where known; `own`: how this process
        handled it (a live source: sources/handling.py), kept in the topic's OwnLag."""
        if own is None:
            self._feed(type_name, buff, t_recv, ros_now, conn, None)
            return
        self.own_lag.start(own)
        try:
            self._feed(type_name, buff, t_recv, ros_now, conn, own.since)
        finally:
            self.own_lag.end(own, time.monotonic())

    def _feed(self, type_name: str, buff: bytes, t_recv: float, ros_now: float,
              conn: Optional[Dict[str, Any]], own_since: Optional[float]) -> None:
        with self.lock:
            if self.stopped_at is not None or self.clock.t0 is None:
                return
            if not self.stream.accept(type_name, conn):
                return
            try:
                msg = self.decode(buff) if self.decode else self._message(type_name, conn, buff)
            except Exception as e:  # a corrupt message is a finding, not a crash
                self.stream.issues.add('deser', 'message could not be decoded (%s)' % type(e).__name__)
                return
            header = getattr(msg, 'header', None)
            self.stream.add(t_recv, ros_now, header, own_since)
            if header is not None:
                self.frames.add(header.frame_id, header.stamp.to_sec(), t_recv)
            try:
                self.check.feed(msg, t_recv - self.clock.began)
            except Exception as e:  # a message the check cannot handle fails the sensor, by name
                self.stream.issues.add('check', 'a message could not be checked (%s: %s)'
                                       % (type(e).__name__, str(e)[:120]))
            debug = self.ctx.services.debug
            if debug is not None:
                stamp = header.stamp.to_sec() if header is not None else None
                debug('%s #%d t=%.3f s%s' % (
                    self.sensor.name, self.stream.stats.count, t_recv - self.clock.began,
                    ' stamp %.3f frame "%s"' % (stamp or 0.0, header.frame_id) if header is not None else ''))

    def _message(self, type_name: str, conn: Optional[Dict[str, Any]], buff: bytes) -> Any:
        msg = self._class_for(type_name, conn)()
        if self.check.numpy_arrays:
            import numpy
            return msg.deserialize_numpy(bytes(buff), numpy)
        return msg.deserialize(bytes(buff))   # bytes: a Ros2Image's ROS 1 bytes (cdr_fast.py)

    def _class_for(self, type_name: str, conn: Optional[Dict[str, Any]]) -> Type[Any]:
        cls = self.classes.get(type_name)
        if cls is None:
            cls = self.classes[type_name] = messages.message_class(
                type_name, (conn or {}).get('message_definition'))
        return cls

    # ---------------------------------------------------------------- what the runner asks
    @property
    def began(self) -> float:
        """When listening began (set by begin(), on the runner's clock)."""
        return self.clock.began

    @property
    def t0(self) -> Optional[float]:
        return self.clock.t0

    @property
    def stats(self) -> Any:
        return self.stream.stats

    @property
    def count(self) -> int:
        """Messages so far: a check that drives itself (speech) counts its own, others their topic's."""
        return self.check.count if self.traits.drives_itself else self.stream.stats.count

    def begin(self, now: float) -> None:
        self.clock.t0 = now
        self.stream.begin(now)
        self.check.start()

    def problems_so_far(self) -> List[str]:
        """A running window's provisional problems (bad headers, its check's failures so far);
        the caller holds `lock`."""
        return self.stream.provisional(self.count) + self.check.failure_reasons()

    def progress(self, now: float) -> Progress:
        """A frozen snapshot for the observers (terminal, /diagnostics)."""
        drives = self.traits.drives_itself
        with self.lock:
            stats = self.stream.stats
            band = self.expect.rate
            return Progress(
                name=self.sensor.name, family=self.sensor.family, topic=self.plan.topic,
                msg_type=self.sensor.msg_type, drives_itself=drives, window=self.window,
                wait=self.wait, elapsed=now - self.began, count=self.count, received=stats.count,
                rate=None if drives else stats.rate, stamp_rate=None if drives else stats.stamp_rate,
                rate_band=(float(band[0]), float(band[1])) if band else None, nominal=self.expect.nominal,
                problems=tuple(self.problems_so_far()), wrong_type=bool(self.stream.wrong_types),
                periodic=self.traits.periodic, asking=bool(self.check.waits_for_answer))

    def due(self, now: float) -> str:
        """Why the window should end now, or '' to keep listening."""
        elapsed = self.clock.elapsed(now)
        with self.lock:
            done = self.check.done()
        if done:                   # a check that paces itself (speech, a guided touch check)
            return 'finished'
        if self.traits.drives_itself:
            return 'window ended' if elapsed >= max(self.window, self.wait) + 5.0 else ''
        stats = self.stream.stats
        if stats.count == 0:   # --wait is wall time, also on sim time: a paused simulator sends nothing
            if not self.traits.periodic:
                return 'window ended' if elapsed >= self.window else ''
            return 'no message within %.1f s' % self.wait if now - self.began >= self.wait else ''
        if self.clock.on_sim_time and self.clock.sim_t0 is not None:
            # a message before the first /clock tick came at the start of the window
            first = stats.clock_recv[0] - self.clock.sim_t0 if stats.clock_recv else 0.0
        else:
            first = stats.recv[0] - self.began
        end = self.window if first <= self.window else first + min(self.window, 2.0)
        if elapsed >= end:
            return 'window ended'
        if self.quick and self._settled():
            return 'verdict settled (--quick)'
        return ''

    def _settled(self) -> bool:
        stats = self.stream.stats
        return stats.count >= self.expect.quick_messages and (stats.recv[-1] - stats.recv[0]) >= 0.8 \
            and self.check.settled()

    def poll(self, now: float) -> None:
        """The check's own pace (speech publishes, a guided check prompts), under the lock the
        subscriber callbacks take: the check sees one thread at a time."""
        with self.lock:
            if self.stopped_at is None:
                self.frames.resolve(now)
                try:
                    self.check.poll(now - self.began)
                except Exception as e:  # a check that cannot go on fails its sensor, by name
                    self.stream.issues.add('poll', 'the check could not go on (%s: %s)'
                                           % (type(e).__name__, str(e)[:120]))

    # ---------------------------------------------------------------- closing
    def stop(self, now: float, reason: str) -> None:
        """End the window at `now`: nothing is fed after this. Cheap; close() does the rest."""
        with self.lock:
            if self.stopped_at is None:
                self.stopped_at, self.end_reason = now, reason
                self.clock.stop()

    def close(self, now: float, reason: str, lookup: Optional[Lookup] = None) -> Optional[SensorResult]:
        """End the window (if stop() has not), close the check, build the result.
        `lookup(topic)` asks the master about a silent topic. Closing twice returns the same result
        (None while another thread is still closing it)."""
        self.stop(now, reason)
        with self.lock:
            if self.closed:
                return self.result
            self.closed = True
        try:
            self.check.close()
        except Exception as e:  # a writer failing must not lose the verdict
            self.check.fail('could not finish the check: %s' % e)
        with self.lock:
            self.frames.close()
        assert self.stopped_at is not None
        self.result = self._judge(self.stopped_at, self.end_reason, lookup)
        return self.result

    def _judge(self, now: float, reason: str, lookup: Optional[Lookup]) -> SensorResult:
        check, stats = self.check, self.stream.stats
        elapsed = now - self.began
        messages = self.count
        band = check.rate_band()
        drives = self.traits.drives_itself
        judgement = self.stream.judge(elapsed, band, None if reason == 'interrupted' else lookup,
                                      drives).merged(check.judgement())
        # what another check found about this sensor (the motion check: RunContext.findings)
        judgement = judgement.merged(self.ctx.findings.of(self.sensor.name))
        if reason != 'interrupted':
            judgement = judgement.merged(self.frames.judgement())
        reasons, warnings, verdict = judgement.reasons, judgement.warnings, judgement.verdict
        if verdict == SKIPPED:
            reasons = [judgement.skip or 'not judged']
        elif verdict == NOT_JUDGED:   # the PC was too busy: its load and lag named (sensors/lag.py)
            reasons = list(judgement.unjudged)
        if reason == 'interrupted':
            # a window cut short is not judged: what it found so far is reported as warnings,
            # never as a failure of the robot ("no message within 0.0 s", "only 2 messages")
            warnings = ['before the interrupt: ' + r for r in judgement.reasons] + warnings
            said = check.said_on_interrupt()
            reasons = ['interrupted after %.1f s of the %.1f s window (%d message%s)'
                       % (elapsed, self.window, messages, '' if messages == 1 else 's')] + said
            warnings = [w for w in warnings if w not in said]
            verdict = INTERRUPTED
        summary = stats.summary()
        values = check.result_values()
        notes = list(check.notes)
        if self.own_lag.probe is not None:     # listened live: sensorTest's own lag (sensors/lag.py)
            notes.append('sensorTest\'s own lag: ' + self.own_lag.describe())
        clock_end: Optional[float] = now
        if self.clock.on_sim_time:
            clock_end = self.clock.sim_stopped_at
            rtf = self.clock.real_time_factor(elapsed)
            # NaN: on sim time, factor unknown (written as null)
            summary = dataclasses.replace(summary, real_time_factor=math.nan if rtf is None else rtf)
            notes.append('rates measured on the simulation clock (/use_sim_time); real-time '
                         'factor %s' % (fmt(rtf, 2) if rtf is not None else 'unknown: /clock not running'))
        return SensorResult(
            name=self.sensor.name, title=self.sensor.title, topic=self.plan.topic,
            msg_type=self.sensor.msg_type, verdict=verdict, reasons=reasons, warnings=warnings,
            notes=notes, messages=messages,
            # an event topic (Traits.periodic False) has no rate: one message per change
            rate_hz=summary.rate_hz if self.traits.periodic else None,
            stamp_rate_hz=summary.stamp_rate_hz if self.traits.periodic else None,
            expected_rate_hz=list(band) if band and not drives else None,
            nominal_rate_hz=self.expect.nominal,
            received_type=next(iter(self.stream.wrong_types), None)
            or (self.stream.received_type if stats.count else None),
            window_s=round(elapsed, 3), stopped_because=reason,
            started_at=round(self.began - self.run_start, 3), ended_at=round(now - self.run_start, 3),
            fields=[[str(k), str(v)] for k, v in (check.first_fields or [])],
            stats=summary, values=values, family=self.sensor.family,
            rate_series=stats.rate_series(end=clock_end), artifacts=dict(check.artifacts),
            frame=self.frames.placement())

def skipped_result(plan: SensorPlan, run_start: float, now: float, verdict: Verdict = SKIPPED,
                   reasons: Optional[List[str]] = None) -> SensorResult:
    """The result of a sensor that never listened: skipped by the plan (its skip reason), or
    ended before its window by `verdict` with `reasons`."""
    if reasons is None:
        reasons = [plan.skip_reason] if plan.skip_reason else []
    return SensorResult(name=plan.sensor.name, title=plan.sensor.title, topic=plan.topic,
                        msg_type=plan.sensor.msg_type, family=plan.sensor.family, verdict=verdict, reasons=reasons,
                        started_at=round(now - run_start, 3), ended_at=round(now - run_start, 3))
