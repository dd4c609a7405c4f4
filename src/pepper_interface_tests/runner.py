"""Listen to each sensor for its window, sequentially or in parallel, and judge it.

Data flow: TestPlan -> lanes (sequential: one lane of all sensors in input order; parallel: one
lane per sensor, except that simulator cameras share one lane) -> one SensorRun at a time per
lane -> SensorResult -> observers (output file, terminal, diagnostics ...).

A SensorRun is fed raw messages (type name, serialized bytes, receive time, ROS time) by a live
rospy.AnyMsg subscription or by a bag reader; it checks the type, deserializes, runs the
generic stream checks (stats.StreamStats) and hands the message to the sensor's Check.
Everything runs in the main thread except subscriber callbacks, which touch only their own
SensorRun under its lock, and the closing of a check whose window has ended (finishing a video
takes a moment), which runs in a thread of its own. The main loop ticks every 50 ms; a window
ends on time, on --quick once the verdict is settled, when no message came within --wait, or on
Ctrl-C.
"""
import threading
import time
from typing import TYPE_CHECKING, Any, Callable, Dict, Iterable, List, Optional, Tuple, Type

from . import interrupts
from .observer import Observers, RunObserver
from .plan import catalog
from .plan.settings import SensorPlan, TestPlan
from .results import FAIL, INTERRUPTED, PASS, SKIPPED, RunResult, SensorResult, Verdict
from .sensors import check_class
from .sensors.base import Check, RunContext, Tally, fmt
from .sources import Source, SourceLost, TopicInfo
from .stats import StreamStats

if TYPE_CHECKING:
    import genpy

TICK = 0.05
# Under /use_sim_time a window lasts `window` seconds of simulation time, so a simulator slower
# than real time still delivers a full window of messages; a simulator slower than this
# real-time factor (or paused) ends the window after window / MIN_RTF seconds of wall time.
MIN_RTF = 0.25


def message_class(type_name: str, definition: Optional[str] = None) -> Type['genpy.Message']:
    """The Python class of a ROS message type, e.g. 'sensor_msgs/Range'.

    A type whose package is not installed (naoqi_bridge_msgs/AudioBuffer from stock
    naoqi_driver) is built from `definition`, the full text every ROS 1 connection header and
    every bag connection carries (naoqi_msgs.message_class_from_definition)."""
    if type_name.startswith('naoqi_driver/AudioCustomMsg'):
        type_name = 'pepper_interface_tests/AudioCustomMsg'
    pkg, name = type_name.split('/')
    try:
        module = __import__(pkg + '.msg', fromlist=[name])
        return getattr(module, name)
    except (ImportError, AttributeError):
        from .sources import naoqi_msgs
        if definition:
            return naoqi_msgs.message_class_from_definition(type_name, definition)
        if type_name == naoqi_msgs.AUDIO_BUFFER_TYPE:
            return naoqi_msgs.audio_buffer_class()
        raise


class SensorRun:
    """One sensor's listening window: raw messages in, one SensorResult out."""

    def __init__(self, plan: SensorPlan, ctx: RunContext, run_start: float, quick: bool = False,
                 wait: float = 5.0, duration: float = 10.0) -> None:
        self.plan = plan
        self.sensor = plan.sensor
        self.expect = plan.expect
        self.check: Check = check_class(self.sensor.family)(plan, ctx)
        self.ctx = ctx
        self.run_start = run_start
        self.quick = quick
        self.wait = wait
        self.window = self.check.window(duration)
        self.lock = threading.Lock()
        # type name -> class (audio: several)
        self.classes = {self.sensor.msg_type: message_class(self.sensor.msg_type)}
        self.publishers: List[str] = []   # caller ids of the nodes whose messages arrived, in order
        self.received_type: Optional[str] = None
        self.sim_clock: Optional[Callable[[], float]] = None   # simulation time (s) under /use_sim_time
        self.sim_t0: Optional[float] = None                    # simulation time when listening began
        self.sim_stopped_at: Optional[float] = None
        # a check may decode its messages itself (images: no copy of the pixels)
        self.decode = getattr(self.check, 'decode', None)
        self.stats = StreamStats()   # its start is set by begin()
        self.t0: Optional[float] = None
        self.stopped_at: Optional[float] = None   # end of the window (set by stop(); no feeding after it)
        self.closed = False
        self.result: Optional[SensorResult] = None
        self.header_issues = Tally()
        self.wrong_types: Dict[str, int] = {}   # type name -> count
        self.connections_seen = 0
        self.publisher_lost_at: Optional[float] = None
        self.end_reason = ''

    @property
    def began(self) -> float:
        """When listening began (set by begin(), on the runner's clock)."""
        if self.t0 is None:
            raise RuntimeError('the window of %s has not begun: call begin() first' % self.sensor.name)
        return self.t0

    @property
    def count(self) -> int:
        """Messages so far: an active check (speech) counts its own, a listening one its topic's."""
        return self.check.count if self.check.active else self.stats.count

    def problems_so_far(self) -> List[str]:
        """A running window's provisional problems (bad headers, its check's failures so far),
        as the terminal and /diagnostics show them; the caller holds `lock`."""
        return self.header_issues.reasons(self.count) + self.check.failure_reasons()

    @property
    def topic(self) -> str:
        """The topic this window listens to (every sensor that is run has one: settings.load_plan)."""
        if self.plan.topic is None:
            raise ValueError('%s has no topic to listen to' % self.sensor.name)
        return self.plan.topic

    # ---------------------------------------------------------------- feeding
    def begin(self, now: float) -> None:
        self.t0 = self.stats.start = now
        self.check.start()

    def use_sim_clock(self, sim_clock: Callable[[], float]) -> None:
        """The source runs on simulation time (/use_sim_time): windows and rates on `sim_clock`
        (a callable returning the simulation time in seconds). Call before the first message."""
        with self.lock:
            self.sim_clock = sim_clock
            self.stats = StreamStats(start=self.t0, clock='sim')
            self._sim_start()

    def _sim_start(self):
        """Simulation time when listening began, once /clock has started (0 before)."""
        if self.sim_t0 is None and self.sim_clock is not None:
            t = self.sim_clock()
            if t > 0:
                self.sim_t0 = self.stats.clock_start = t
        return self.sim_t0

    def _elapsed(self, now):
        """Seconds the window has run, on the clock windows are measured on (see MIN_RTF)."""
        wall = now - self.t0
        if self.sim_clock is None:
            return wall
        start = self._sim_start()
        sim = self.sim_clock() - start if start is not None else 0.0
        return max(sim, wall * MIN_RTF)

    def _class_for(self, type_name, conn):
        cls = self.classes.get(type_name)
        if cls is None:
            cls = self.classes[type_name] = message_class(
                type_name, (conn or {}).get('message_definition'))
        return cls

    def feed_raw(self, type_name: str, buff: bytes, t_recv: float, ros_now: float,
                 conn: Optional[Dict[str, Any]] = None) -> None:
        """One message as it came off the wire (or out of a bag); `conn` is its connection
        header (type, message_definition, callerid) where known."""
        with self.lock:
            if self.stopped_at is not None or self.t0 is None:
                return
            if not catalog.accepts_type(self.sensor, type_name):
                self.wrong_types[type_name] = self.wrong_types.get(type_name, 0) + 1
                return
            self.received_type = type_name
            caller = (conn or {}).get('callerid')
            if caller and caller not in self.publishers:
                self.publishers.append(caller)
            try:
                decode = self.decode or self._class_for(type_name, conn)().deserialize
                msg = decode(buff)
            except Exception as e:  # a corrupt message is a finding, not a crash
                self.header_issues.add('deser', 'message could not be decoded (%s)' % type(e).__name__)
                return
            header = getattr(msg, 'header', None)
            stamp = header.stamp.to_sec() if header is not None else None
            self.stats.add(t_recv, stamp, ros_now if header is not None else None, ros_now)
            if header is not None:
                want = self.expect.frame_id
                if want and header.frame_id != want:
                    self.header_issues.add('frame', 'frame_id is "%s", expected "%s"'
                                           % (header.frame_id, want))
            try:
                self.check.feed(msg, t_recv - self.t0)
            except Exception as e:  # a message the check cannot handle fails the sensor, by name
                self.header_issues.add('check', 'a message could not be checked (%s: %s)'
                                       % (type(e).__name__, str(e)[:120]))
            debug = self.ctx.services.get('debug')
            if debug is not None:
                debug('%s #%d t=%.3f s%s' % (
                    self.sensor.name, self.stats.count, t_recv - (self.t0 or 0.0),
                    ' stamp %.3f frame "%s"' % (stamp or 0.0, header.frame_id) if header is not None else ''))

    # ---------------------------------------------------------------- deciding when to stop
    def due(self, now: float) -> str:
        """Why the window should end now, or '' to keep listening."""
        elapsed = self._elapsed(now)
        if self.check.active:
            if self.check.done():
                return 'finished'
            return 'window ended' if elapsed >= max(self.window, self.wait) + 5.0 else ''
        count = self.stats.count
        if count == 0:   # --wait is wall time, also on sim time: a paused simulator sends nothing
            return 'no message within %.1f s' % self.wait if now - self.began >= self.wait else ''
        if self.sim_clock is not None and self.sim_t0 is not None:
            first = self.stats.clock_recv[0] - self.sim_t0
        else:
            first = self.stats.recv[0] - self.began
        end = self.window if first <= self.window else first + min(self.window, 2.0)
        if elapsed >= end:
            return 'window ended'
        if self.quick and self._settled(elapsed):
            return 'verdict settled (--quick)'
        return ''

    def _settled(self, elapsed):
        n = self.expect.quick_messages
        return self.stats.count >= n and (self.stats.recv[-1] - self.stats.recv[0]) >= 0.8 \
            and self.check.settled()

    def poll(self, now: float) -> None:
        if self.check.active:
            self.check.poll(now - self.began)

    def observe_connections(self, n: int, now: float) -> None:
        if n > 0:
            self.connections_seen = max(self.connections_seen, n)
        elif self.connections_seen and self.publisher_lost_at is None:
            self.publisher_lost_at = now - self.began

    # ---------------------------------------------------------------- closing
    def stop(self, now: float, reason: str) -> None:
        """End the window at `now`: nothing is fed after this. Cheap; close() does the rest."""
        with self.lock:
            if self.stopped_at is None:
                self.stopped_at, self.end_reason = now, reason
                if self.sim_clock is not None:
                    self.sim_stopped_at = self.sim_clock()

    def close(self, now: float, reason: str,
              lookup: Optional[Callable[[str], Optional[TopicInfo]]] = None) -> Optional[SensorResult]:
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
        self.result = self._judge(self.stopped_at, self.end_reason, lookup)
        return self.result

    def _judge(self, now, reason, lookup):
        s, check, e = self.stats, self.check, self.expect
        elapsed = now - self.t0
        messages = self.count
        reasons: List[str] = []
        warnings: List[str] = []
        topic = self.plan.topic
        if not check.active:
            reasons += self._arrival_reasons(elapsed, None if reason == 'interrupted' else lookup)
            if s.count:
                reasons += self._stream_reasons(elapsed, warnings)
        reasons += self.header_issues.reasons(s.count)
        self._publisher_reasons(reasons, warnings)
        reasons += check.failure_reasons()
        warnings += check.warning_reasons()
        verdict = FAIL if reasons else PASS
        if reason == 'interrupted':
            # a window cut short is not judged: what it found so far is reported as warnings,
            # never as a failure of the robot ("no message within 0.0 s", "only 2 messages")
            warnings = ['before the interrupt: ' + r for r in reasons] + warnings
            reasons = ['interrupted after %.1f s of the %.1f s window (%d message%s)'
                       % (elapsed, self.window, messages, '' if messages == 1 else 's')]
            verdict = INTERRUPTED
        band = check.rate_band()
        summary = s.summary()
        notes = list(check.notes)
        clock_end = now
        if self.sim_clock is not None:
            clock_end = self.sim_stopped_at
            rtf = None
            if self.sim_t0 is not None and self.sim_stopped_at is not None and elapsed > 0:
                rtf = round((self.sim_stopped_at - self.sim_t0) / elapsed, 3)
            summary['real_time_factor'] = rtf
            notes.append('rates measured on the simulation clock (/use_sim_time); real-time '
                         'factor %s' % (fmt(rtf, 2) if rtf is not None else 'unknown: /clock not running'))
        return SensorResult(
            name=self.sensor.name, title=self.sensor.title, topic=topic,
            msg_type=self.sensor.msg_type, verdict=verdict, reasons=reasons, warnings=warnings,
            notes=notes, messages=messages, rate_hz=summary['rate_hz'],
            stamp_rate_hz=summary['stamp_rate_hz'],
            expected_rate_hz=list(band) if band and not check.active else None,
            nominal_rate_hz=e.nominal,
            received_type=next(iter(self.wrong_types), None) or (self.received_type if s.count else None),
            window_s=round(elapsed, 3), stopped_because=reason,
            started_at=round(self.began - self.run_start, 3), ended_at=round(now - self.run_start, 3),
            fields=[[str(k), str(v)] for k, v in (check.first_fields or [])],
            stats=summary, values=dict(check.values),
            series=dict(check.series, rate_hz=s.rate_series(end=clock_end)),
            artifacts=dict(check.artifacts))

    def _publisher_reasons(self, reasons, warnings):
        """More than one node delivering on the topic (from the connection headers' callerid).
        Two audio bridges interleave their buffers: the recording and the sample rate are
        wrong, so on the microphone it fails; elsewhere a warning."""
        if len(self.publishers) < 2:
            return
        text = '%d publishers deliver on %s: %s' % (len(self.publishers), self.plan.topic,
                                                    ', '.join(self.publishers))
        if self.sensor.family == 'audio':
            reasons.append(text + ' (two audio bridges running? start only one: '
                                  'launch_audio:=false for the CSSR naoqi_driver, or stop the other node)')
        else:
            warnings.append(text)

    def _arrival_reasons(self, elapsed, lookup):
        s, topic = self.stats, self.plan.topic
        out = []
        if self.wrong_types:
            types = ', '.join(sorted(self.wrong_types))
            out.append('topic %s carries %s, expected %s' % (topic, types, catalog.expected_types(self.sensor)))
            return out
        if s.count:
            return out
        info = lookup(topic) if lookup else None
        if info is not None:
            advertised, publishers = info
            if advertised and not catalog.accepts_type(self.sensor, advertised):
                out.append('topic %s is advertised as %s, expected %s'
                           % (topic, advertised, catalog.expected_types(self.sensor)))
            elif publishers is None:
                out.append('topic %s is not in the bag' % topic)
            elif not publishers:
                out.append('no publisher on %s (is the driver running, and is the topic name right?%s)'
                           % (topic, no_publisher_note(self.sensor.name)))
            else:
                out.append('no message on %s within %.1f s although %s publishes it'
                           % (topic, elapsed, ', '.join(publishers)))
        else:
            out.append('no message on %s within %.1f s' % (topic, elapsed))
        return out

    def _stream_reasons(self, elapsed, warnings):
        s, e = self.stats, self.expect
        out = []
        band = self.check.rate_band()
        min_messages = e.min_messages
        if s.count < min_messages:
            out.append('only %d message%s in %.1f s (at least %d expected)'
                       % (s.count, '' if s.count == 1 else 's', elapsed, min_messages))
        if self.sim_clock is not None and self.sim_t0 is None:
            # rospy keeps ROS time at 0 until /clock ticks: stamps, sim rates and windows
            # cannot be measured, and "1.8e9 s in the future" would blame the robot
            out.append(NO_CLOCK)
            return out
        if band and s.count >= 3:
            lo, hi = band
            rate_label = 'rate (sim clock)' if s.clock == 'sim' else 'rate'
            for label, rate in ((rate_label, s.rate), ('header stamp rate', s.stamp_rate)):
                if rate is not None and not (lo <= rate <= hi):
                    out.append('%s %.2f Hz outside the expected %g-%g Hz' % (label, rate, lo, hi))
                elif rate is not None and label == rate_label and (rate < 1.1 * lo or rate > 0.9 * hi):
                    # inside the band but within 10 % of an edge: possible, worth a look
                    warnings.append('%s %.2f Hz near the edge of the expected %g-%g Hz'
                                    % (label, rate, lo, hi))
        if s.zero_stamps:
            out.append('%d message%s with a zero header stamp'
                       % (s.zero_stamps, '' if s.zero_stamps == 1 else 's'))
        if s.backwards:
            out.append('header stamps went backwards %d time%s'
                       % (s.backwards, '' if s.backwards == 1 else 's'))
        if s.repeated:
            warnings.append('%d repeated header stamp%s' % (s.repeated, '' if s.repeated == 1 else 's'))
        delay = s.delay_summary()
        offset = clock_offset(delay, e.max_delay, e.max_future)
        if offset:
            out.append(offset)
        elif delay and delay['max'] - delay['min'] <= OFFSET_SPREAD and abs(delay['mean']) >= 1.0:
            # a constant offset inside the limits: possible (clocks a second apart), worth a look
            warnings.append('clock offset: header stamps a constant %.1f s %s this computer\'s clock '
                            '(within max_delay %g s / max_future %g s; sync both clocks with chrony)'
                            % (abs(delay['mean']), 'behind' if delay['mean'] > 0 else 'ahead of',
                               e.max_delay, e.max_future))
        if delay and not offset:
            if delay['max'] > e.max_delay:
                out.append('stale data: header stamps up to %.2f s behind ROS time (at most %g s)'
                           % (delay['max'], e.max_delay))
            if -delay['min'] > e.max_future:
                out.append('header stamps up to %.2f s in the future (clock skew?)' % -delay['min'])
        # a publisher that stopped: the last message long before the end of the window
        if s.clock == 'sim' and self.sim_stopped_at is not None and s.clock_recv[-1] is not None:
            silence = self.sim_stopped_at - s.clock_recv[-1]
            span = s.clock_recv[-1] - s.clock_recv[0]
        else:
            silence = (self.t0 + elapsed) - s.recv[-1]
            span = s.recv[-1] - s.recv[0]
        lo_rate = band[0] if band else None
        threshold = max(1.0, e.max_gap_factor / lo_rate) if lo_rate else 2.0
        if silence > threshold:
            lost = ' (publisher left at %.1f s)' % self.publisher_lost_at \
                if self.publisher_lost_at is not None else ''
            out.append('messages stopped %.1f s after the first one; nothing for the last %.1f s%s'
                       % (span, silence, lost))
        gaps = s.gaps(threshold)
        if gaps:
            longest = max(gaps, key=lambda g: g[1])
            warnings.append('%d pause%s longer than %.2f s (longest %.2f s at %.1f s)'
                            % (len(gaps), '' if len(gaps) == 1 else 's', threshold,
                               longest[1], longest[0]))
        return out


# Spread (max - min) of "ROS time at reception - header stamp" below which a delay beyond the
# limits is one constant offset between two clocks, not data getting old: network and driver
# latency vary by milliseconds to a few hundred ms, a stale or stuck stream's delay grows.
OFFSET_SPREAD = 1.0


def clock_offset(delay: Optional[Dict[str, float]], max_delay: float, max_future: float) -> str:
    """The reason for header stamps a constant offset away from this computer's clock (the
    robot's clock not synchronised, e.g. an hour off after a time-zone mistake), or ''."""
    if not delay or delay['max'] - delay['min'] > OFFSET_SPREAD:
        return ''
    mean = delay['mean']
    if mean > max_delay:
        side = 'behind'
    elif -mean > max_future:
        side = 'ahead of'
    else:
        return ''
    return ('clock offset: header stamps are a constant %.1f s %s this computer\'s clock (spread %.2f s): '
            'the robot\'s clock is not synchronised with this one; sync both with chrony or ntp%s'
            % (abs(mean), side, delay['max'] - delay['min'],
               ' (or the driver stamps its data that late)' if side == 'behind' else ''))


NO_CLOCK = ('/use_sim_time is true but nothing publishes /clock, so ROS time stands at 0 and no '
            'stamp or simulation-time rate can be judged: start the simulator (it publishes /clock), '
            'or clear a leftover setting with "rosparam set /use_sim_time false" and start again')


def skipped_result(plan: SensorPlan, run_start: float, now: float, verdict: Verdict = SKIPPED,
                   reasons: Optional[List[str]] = None) -> SensorResult:
    """The result of a sensor that never listened: skipped by the plan (its skip reason), or
    ended before its window by `verdict` with `reasons`."""
    if reasons is None:
        reasons = [plan.skip_reason] if plan.skip_reason else []
    return SensorResult(name=plan.sensor.name, title=plan.sensor.title, topic=plan.topic,
                        msg_type=plan.sensor.msg_type, verdict=verdict, reasons=reasons,
                        started_at=round(now - run_start, 3), ended_at=round(now - run_start, 3))


def no_publisher_note(name: str) -> str:
    """' Note: ...' for a sensor whose missing publisher has a known cause, else ''."""
    hint = catalog.NO_PUBLISHER_HINTS.get(name)
    return ' Note: ' + hint if hint else ''


def lanes_for(plan: TestPlan, live: bool = True) -> List[List[SensorPlan]]:
    """Which sensors run one after another: a list of lanes, each a list of SensorPlans.

    Gazebo fails when several cameras stream at once, so live simulator cameras share one lane
    even in parallel mode; a bag replay has no such limit."""
    if plan.mode == 'sequential':
        return [list(plan.sensors)]
    lanes: List[List[SensorPlan]] = []
    cameras: List[SensorPlan] = []
    serial_cameras = live and plan.platform == 'simulator'
    for s in plan.sensors:
        if serial_cameras and s.sensor.family in ('camera', 'depth') and s.skip_reason is None:
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

    def _start_next(self, i, now):
        # a plan leaves its lane only once it is recorded as running (or done): an interrupt at
        # any point in here leaves it either in the lane ("not run") or in current (closed)
        lane = self.lanes[i]
        self.current[i] = None
        while lane:
            plan = lane[0]
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
            self.observers.sensor_started(run)
            return

    def _done(self, result):
        self.results[result.name] = result
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
                                      verdict=FAIL, reasons=['internal error while judging: %s' % e],
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
            for i in range(len(self.lanes)):
                self._start_next(i, self.clock())
            while any(self.current) or self.closing:
                now = self.clock()
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
                self.observers.tick([r for r in self.current if r], now)
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
        those sensors with that reason, instead of waiting --wait per sensor in turn."""
        probe = self.source.published_topics
        plans = [p for lane in self.lanes for p in lane
                 if p.skip_reason is None and p.sensor.family != 'speech']
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
                            self.source.master_uri)
        for lane in self.lanes:
            for p in [p for p in lane if p in plans]:
                self._done(skipped_result(p, self.start, now, FAIL, [
                    'no publisher on %s: no sensor topic of this run has a publisher on the ROS master '
                    '(robot off, another master, driver not started?)%s'
                    % (p.topic, no_publisher_note(p.sensor.name))]))
                lane.remove(p)

    def interrupt(self, why: str) -> None:
        self.signals.phase = 'closing'
        self.run.interrupted = True
        self.run.interrupt_reason = why

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
        for lane in self.lanes:
            for plan in lane:
                if plan.name in self.results:   # interrupted between starting it and popping it
                    continue
                self._done(skipped_result(plan, self.start, now, SKIPPED,
                                          ['not run: the run was interrupted before it started']))
            del lane[:]
        self.run.sensors = [self.results[n] for n in self.order if n in self.results]
        self.run.end = self.wall()
        interrupts.pause('final-write')
        self.observers.run_ended(self.run)
