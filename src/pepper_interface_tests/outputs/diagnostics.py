"""Live /diagnostics: one diagnostic_msgs/DiagnosticStatus per sensor while sensorTest runs.

Published through diagnostic_updater (one task per sensor, `force_update()` at 1 Hz and for the
final statuses), so rqt_robot_monitor and diagnostic_aggregator show the run like any other
node's diagnostics:
  * topic /diagnostics, diagnostic_msgs/DiagnosticArray, published at 1 Hz (from the runner's
    50 ms tick), and once more with the final statuses when the run ends (also when interrupted);
  * status name "<node name>: <sensor>", i.e. "sensorTest: frontSonar" (the unique default
    name's _<pid>_<ms> suffix left out); hardware_id the topic;
  * level and message:
      STALE  "waiting to start" (not yet listened to), "waiting for the first message (2.1 s
             of 5.0 s)" (listening, nothing arrived yet), "not run: ..." (interrupted run),
             "INTERRUPTED: interrupted after ..." (a window cut short: not judged)
      OK     "listening, 35 msgs, 9.8 Hz" while nothing is wrong so far; "PASS: 98 msgs, 9.8 Hz"
             at the end; "SKIPPED: <reason>" (a skipped sensor does not fail the run)
      WARN   "listening, 35 msgs, 2.1 Hz; so far: rate 2.10 Hz outside the expected 4-16 Hz"
             (a problem seen during the window: the verdict is not final yet); "PASS with
             warnings: ..." at the end
      ERROR  "FAIL: <reasons>" at the end
  * key/values: verdict or state, topic, message type, messages, rate (Hz), header stamp rate
    (Hz), expected rate (Hz), nominal rate (Hz), elapsed / window (s), reasons, warnings.

What a status says is computed by pure functions (`waiting_status`, `live_status`,
`result_status` -> `Status`: level, message, key/values), unit-tested without ROS; the tasks
only copy the current `Status` into diagnostic_updater's wrapper. The period is kept on the
monotonic clock, not the updater's `update()`: that one counts ROS time, which stands still in a
run with /use_sim_time and a paused or absent /clock. The observer reads a running sensor's
counters under that sensor's lock (the subscriber thread writes them); it never fails the run:
a publishing error is printed once as a warning.
"""
import re
import sys
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Dict, Iterable, List, Optional, Sequence, TextIO, Tuple

from ..observer import RunObserver
from ..progress import Progress
from ..results import FAIL, INTERRUPTED, NOT_JUDGED, SKIPPED, RunResult, SensorResult, frame_line

if TYPE_CHECKING:
    from ..plan.settings import TestPlan

PERIOD = 1.0
TOPIC = '/diagnostics'      # where diagnostic_updater.Updater publishes
OK, WARN, ERROR, STALE = 0, 1, 2, 3    # diagnostic_msgs/DiagnosticStatus levels


@dataclass(frozen=True)
class Status:
    """One sensor's status, independent of ROS (copied into a DiagnosticStatus by its task)."""
    level: int
    message: str
    values: Tuple[Tuple[str, str], ...]


def _band(band: Optional[Sequence[float]]) -> str:
    return '%g-%g' % tuple(band) if band else ''


def _num(v: Optional[float], nd: int = 2) -> str:
    return '' if v is None else ('%.*f' % (nd, v))


def _values(pairs: Iterable[Tuple[str, Any]]) -> Tuple[Tuple[str, str], ...]:
    return tuple((k, '' if v is None else str(v)) for k, v in pairs)


def waiting_status(topic: Optional[str], msg_type: str) -> Status:
    """Before the sensor's window starts."""
    return Status(STALE, 'waiting to start',
                  _values([('state', 'waiting'), ('topic', topic or ''), ('message type', msg_type)]))


def live_status(p: Progress) -> Status:
    """The status of a running window (progress, provisional problems)."""
    band = p.rate_band
    count, rate, stamp_rate, elapsed = p.count, p.rate, p.stamp_rate, p.elapsed
    problems = list(p.problems)
    if band and rate is not None and count >= 3 and not (band[0] <= rate <= band[1]):
        problems.insert(0, 'rate %.2f Hz outside the expected %g-%g Hz' % (rate, band[0], band[1]))
    if p.drives_itself:
        state, text = 'running', 'running (%.0f s), %d sent' % (elapsed, count)
        level = OK
    elif count == 0 and not p.periodic:      # an event topic (touch): nothing until a touch
        state, text, level = 'listening', 'listening for events, none yet (%.0f s)' % elapsed, OK
    elif count == 0:
        state = 'waiting for data'
        text = 'waiting for the first message (%.1f s of %.1f s)' % (elapsed, p.wait)
        level = STALE
    else:
        state = 'listening'
        text = 'listening, %d msgs' % count + (', %.1f Hz' % rate if rate is not None else '')
        level = OK
    if problems:
        level = WARN
        text += '; so far: ' + '; '.join(problems)
    return Status(level, text, _values([
        ('state', state), ('topic', p.topic or ''), ('message type', p.msg_type),
        ('messages', count), ('rate (Hz)', _num(rate)), ('header stamp rate (Hz)', _num(stamp_rate)),
        ('expected rate (Hz)', _band(band)), ('nominal rate (Hz)', p.nominal),
        ('elapsed (s)', _num(elapsed, 1)), ('window (s)', _num(p.window, 1)),
        ('problems so far', '; '.join(problems))]))


def result_status(r: SensorResult) -> Status:
    """The final status of a SensorResult: FAIL -> ERROR; INTERRUPTED and "not run" -> STALE
    (not judged, like a sensor that never ran); SKIPPED -> OK (a skip does not fail the run);
    PASS with warnings -> WARN; PASS -> OK."""
    if r.verdict == FAIL:
        level, text = ERROR, 'FAIL: ' + '; '.join(r.reasons)
    elif r.verdict == INTERRUPTED:
        level, text = STALE, 'INTERRUPTED: ' + '; '.join(r.reasons)
    elif r.verdict == NOT_JUDGED:   # the PC was too busy to judge it: no fault of the robot's
        level, text = WARN, 'NOT JUDGED: ' + '; '.join(r.reasons)
    elif r.verdict == SKIPPED:
        not_run = any(x.startswith('not run') for x in r.reasons)
        level = STALE if not_run else OK
        text = ('' if not_run else 'SKIPPED: ') + '; '.join(r.reasons)
    elif r.warnings:
        level, text = WARN, 'PASS with warnings: ' + '; '.join(r.warnings)
    else:
        level = OK
        text = 'PASS: %d msgs' % r.messages + (', %.1f Hz' % r.rate_hz if r.rate_hz is not None else '')
    pairs: List[Tuple[str, Any]] = [
        ('verdict', r.verdict), ('topic', r.topic or ''), ('message type', r.msg_type),
        ('messages', r.messages), ('rate (Hz)', _num(r.rate_hz)),
        ('header stamp rate (Hz)', _num(r.stamp_rate_hz)),
        ('expected rate (Hz)', _band(r.expected_rate_hz)), ('nominal rate (Hz)', r.nominal_rate_hz),
        ('window (s)', _num(r.window_s, 1)), ('stopped because', r.stopped_because),
        ('reasons', '; '.join(r.reasons)), ('warnings', '; '.join(r.warnings))]
    if r.notes:     # what a check measured (the robot's battery and hottest joints, ...)
        pairs.append(('notes', '; '.join(r.notes)))
    if frame_line(r):   # its frame in the robot's tree (sensors/frames.py)
        pairs.append(('frame', frame_line(r)))
    pairs += [('file ' + kind, name) for kind, name in r.artifacts.items()]
    return Status(level, text, _values(pairs))


def base_node_name(name: str) -> str:
    """'/sensorTest_1234_1700000000000' -> 'sensorTest': the default node name is unique per run;
    status names stay "sensorTest: <sensor>" so monitors and aggregators see one status per sensor."""
    return re.sub(r'_\d+_\d+$', '', name.lstrip('/')) or 'sensorTest'


def make_updater(prefix: str) -> Any:
    """A diagnostic_updater.Updater (publisher on /diagnostics) with two changes, both for the
    monitors: status names are "<prefix>: <task>" (the updater would use the unique node name),
    and adding a task publishes nothing (the updater publishes "Node starting up" per task; the
    first force_update shows every sensor's "waiting to start" in one array instead)."""
    import rospy
    from diagnostic_msgs.msg import DiagnosticArray
    from diagnostic_updater import Updater

    class RunUpdater(Updater):
        def addedTaskCallback(self, task):
            pass

        def publish(self, msg):
            array = DiagnosticArray(status=msg if isinstance(msg, list) else [msg])
            for stat in array.status:
                stat.name = '%s: %s' % (prefix, stat.name)
            array.header.stamp = rospy.Time.now()
            self.publisher.publish(array)

    updater = RunUpdater()
    updater.setHardwareID('none')    # each task sets its topic; 'none' is the updater's convention
    return updater


class _Stat:
    """What a task fills (diagnostic_updater's DiagnosticStatusWrapper: summary, add,
    hardware_id), turned into a genpy DiagnosticStatus by Ros2Updater."""

    def __init__(self, name: str) -> None:
        self.name, self.level, self.message, self.hardware_id = name, 0, '', ''
        self.values: List[Tuple[str, str]] = []

    def summary(self, level: int, message: str) -> None:
        self.level, self.message = level, message

    def add(self, key: str, value: Any) -> None:
        self.values.append((key, str(value)))


class Ros2Updater:
    """The part of diagnostic_updater.Updater this observer uses, on ROS 2 (diagnostic_updater's
    Python package is rospy's): tasks filled and published as one DiagnosticArray on
    /diagnostics through the rclpy node of the run (sources/ros2wire.RawPublisher), statuses
    named "<prefix>: <task>" as on ROS 1."""

    def __init__(self, prefix: str) -> None:
        from ..sources import live2, messages, ros2wire
        graph = live2.current()
        if graph is None:
            raise RuntimeError('no ROS 2 node')
        self.prefix = prefix
        self.tasks: List[Tuple[str, Any]] = []
        self.classes = {n: messages.message_class('diagnostic_msgs/' + n)
                        for n in ('DiagnosticArray', 'DiagnosticStatus', 'KeyValue')}
        self.publisher = ros2wire.RawPublisher(graph.node, '/diagnostics', 'diagnostic_msgs/DiagnosticArray',
                                               10, remember=True, destroy=graph.destroy)
        self.now = graph.now

    def setHardwareID(self, hwid: str) -> None:  # noqa: N802  (diagnostic_updater's name)
        pass

    def add(self, name: str, fill: Any) -> None:
        self.tasks.append((name, fill))

    def force_update(self) -> None:
        import genpy
        statuses = []
        for name, fill in self.tasks:
            stat = _Stat(name)
            fill(stat)
            statuses.append(self.classes['DiagnosticStatus'](
                level=stat.level, name='%s: %s' % (self.prefix, name), message=stat.message,
                hardware_id=stat.hardware_id,
                values=[self.classes['KeyValue'](key=k, value=v) for k, v in stat.values]))
        array = self.classes['DiagnosticArray'](status=statuses)
        array.header.stamp = genpy.Time.from_sec(self.now())
        self.publisher.publish(array)


class LiveDiagnostics(RunObserver):
    """Runner observer publishing the run's per-sensor statuses on /diagnostics at 1 Hz."""

    def __init__(self, plan: 'TestPlan', prefix: Optional[str] = None, period: float = PERIOD,
                 out: Optional[TextIO] = None) -> None:
        self.period = period
        self.prefix = prefix
        self.out = out
        self.updater: Any = None     # diagnostic_updater.Updater once the run starts
        self.current: Dict[str, Status] = {}
        self.topics: Dict[str, Tuple[Optional[str], str]] = {}
        self.last: Optional[float] = None
        self.broken = False
        for s in plan.sensors:
            self._track(s.name, s.topic, s.sensor.msg_type)

    def _track(self, name: str, topic: Optional[str], msg_type: str) -> None:
        self.topics[name] = (topic, msg_type)
        self.current[name] = waiting_status(topic, msg_type)
        if self.updater is not None:
            self._add_task(name)

    def _add_task(self, name: str) -> None:
        topic = self.topics[name][0] or ''

        def fill(stat: Any) -> Any:
            status = self.current[name]
            stat.summary(status.level, status.message)
            stat.hardware_id = topic
            for k, v in status.values:
                stat.add(k, v)
            return stat
        self.updater.add(name, fill)

    def _warn(self, e: Exception) -> None:
        if not self.broken:
            self.broken = True
            stream = self.out or sys.stdout
            stream.write('sensorTest: warning: /diagnostics not published: %s\n' % e)
            stream.flush()

    def publish(self) -> None:
        if self.updater is None or self.broken:
            return
        try:
            self.updater.force_update()
            self.last = time.monotonic()
        except Exception as e:
            self._warn(e)

    # ---------------------------------------------------------------- observer methods
    def run_started(self, run: RunResult, plan: 'TestPlan') -> None:
        try:
            from ..sources.live2 import ros_version
            if ros_version() == 2:
                self.prefix = self.prefix or 'sensorTest'
                self.updater = Ros2Updater(self.prefix)
            else:
                if self.prefix is None:
                    import rospy
                    self.prefix = base_node_name(rospy.get_name())
                self.updater = make_updater(self.prefix)
            for name in self.current:
                self._add_task(name)
        except Exception as e:
            self._warn(e)
            return
        self.publish()

    def tick(self, progress: Sequence[Progress], now: float) -> None:
        if self.updater is None or (self.last is not None and time.monotonic() - self.last < self.period):
            return
        for p in progress:
            if p.name in self.current:
                name = p.name
                try:
                    self.current[name] = live_status(p)
                except Exception as e:   # a status must never stop the run
                    old = self.current[name]
                    self.current[name] = Status(old.level, 'status unavailable: %s' % e, old.values)
        self.publish()

    def sensor_done(self, result: SensorResult) -> None:
        if result.name not in self.current:
            self._track(result.name, result.topic, result.msg_type)
        self.current[result.name] = result_status(result)

    def run_ended(self, run: RunResult) -> None:
        for r in run.sensors:
            self.sensor_done(r)
        self.publish()
        if self.updater is None or self.broken:
            return
        try:   # let the publisher threads hand the final array to connected subscribers
            pub = self.updater.publisher
            if pub.get_num_connections():
                time.sleep(0.3)
            pub.unregister()
        except (Exception, KeyboardInterrupt):
            pass
