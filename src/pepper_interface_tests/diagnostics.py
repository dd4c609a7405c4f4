"""Live /diagnostics: one diagnostic_msgs/DiagnosticStatus per sensor while sensorTest runs.

Follows diagnostic_updater's conventions so rqt_robot_monitor and diagnostic_aggregator show
the run like any other node's diagnostics:
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

The observer reads a running sensor's counters under that sensor's lock (the subscriber thread
writes them); it never fails the run: a publishing error is printed once as a warning.
"""
import sys
import time

from .results import FAIL, INTERRUPTED, SKIPPED

PERIOD = 1.0
TOPIC = '/diagnostics'


def _levels():
    from diagnostic_msgs.msg import DiagnosticStatus
    return DiagnosticStatus.OK, DiagnosticStatus.WARN, DiagnosticStatus.ERROR, DiagnosticStatus.STALE


def _band(band):
    return '%g-%g' % tuple(band) if band else ''


def _num(v, nd=2):
    return '' if v is None else ('%.*f' % (nd, v))


class Status:
    """One sensor's current status, independent of ROS (turned into a message on publish)."""

    def __init__(self, name, topic, msg_type):
        self.name = name
        self.topic = topic or ''
        self.msg_type = msg_type
        self.level = 3           # STALE
        self.message = 'waiting to start'
        self.values = [('state', 'waiting'), ('topic', self.topic), ('message type', msg_type)]

    def to_msg(self, prefix):
        from diagnostic_msgs.msg import DiagnosticStatus, KeyValue
        return DiagnosticStatus(level=self.level, name='%s: %s' % (prefix, self.name),
                                message=self.message, hardware_id=self.topic,
                                values=[KeyValue(key=k, value=str(v)) for k, v in self.values])


def live_status(status, sensor_run, now):
    """Fill `status` from a running SensorRun (progress, provisional problems)."""
    OK, WARN, ERROR, STALE = _levels()
    expect = sensor_run.expect
    band = expect.rate
    with sensor_run.lock:
        check = sensor_run.check
        stats = sensor_run.stats
        elapsed = now - sensor_run.t0
        count = check.count if check.active else stats.count
        rate = stats.rate if not check.active else None
        stamp_rate = stats.stamp_rate if not check.active else None
        problems = sensor_run.header_issues.reasons(count) + check.failure_reasons()
    window = sensor_run.window
    if band and rate is not None and count >= 3 and not (band[0] <= rate <= band[1]):
        problems.insert(0, 'rate %.2f Hz outside the expected %g-%g Hz' % (rate, band[0], band[1]))
    if check.active:
        state, text = 'running', 'running (%.0f s), %d sent' % (elapsed, count)
        level = OK
    elif count == 0:
        state = 'waiting for data'
        text = 'waiting for the first message (%.1f s of %.1f s)' % (elapsed, sensor_run.wait)
        level = STALE
    else:
        state = 'listening'
        text = 'listening, %d msgs' % count + (', %.1f Hz' % rate if rate is not None else '')
        level = OK
    if problems:
        level = WARN
        text += '; so far: ' + '; '.join(problems)
    status.level, status.message = level, text
    status.values = [('state', state), ('topic', status.topic), ('message type', status.msg_type),
                     ('messages', count), ('rate (Hz)', _num(rate)),
                     ('header stamp rate (Hz)', _num(stamp_rate)),
                     ('expected rate (Hz)', _band(band)), ('nominal rate (Hz)', expect.nominal if expect.nominal is not None else ''),
                     ('elapsed (s)', _num(elapsed, 1)), ('window (s)', _num(window, 1)),
                     ('problems so far', '; '.join(problems))]


def final_status(status, r):
    """Fill `status` from a SensorResult."""
    OK, WARN, ERROR, STALE = _levels()
    if r.verdict == FAIL:
        level, text = ERROR, 'FAIL: ' + '; '.join(r.reasons)
    elif r.verdict == INTERRUPTED:     # not judged: stale, like a sensor that never ran
        level, text = STALE, 'INTERRUPTED: ' + '; '.join(r.reasons)
    elif r.verdict == SKIPPED:
        not_run = any(x.startswith('not run') for x in r.reasons)
        level = STALE if not_run else OK
        text = ('' if not_run else 'SKIPPED: ') + '; '.join(r.reasons)
    elif r.warnings:
        level, text = WARN, 'PASS with warnings: ' + '; '.join(r.warnings)
    else:
        level = OK
        text = 'PASS: %d msgs' % r.messages + (', %.1f Hz' % r.rate_hz if r.rate_hz is not None else '')
    status.level, status.message = level, text
    status.values = [('verdict', r.verdict), ('topic', status.topic), ('message type', r.msg_type),
                     ('messages', r.messages), ('rate (Hz)', _num(r.rate_hz)),
                     ('header stamp rate (Hz)', _num(r.stamp_rate_hz)),
                     ('expected rate (Hz)', _band(r.expected_rate_hz)),
                     ('nominal rate (Hz)', '' if r.nominal_rate_hz is None else r.nominal_rate_hz),
                     ('window (s)', _num(r.window_s, 1)), ('stopped because', r.stopped_because),
                     ('reasons', '; '.join(r.reasons)), ('warnings', '; '.join(r.warnings))]
    for kind, name in r.artifacts.items():
        status.values.append(('file ' + kind, name))


class LiveDiagnostics:
    """Runner observer publishing the run's per-sensor statuses on /diagnostics at 1 Hz."""

    def __init__(self, plan, prefix=None, period=PERIOD, topic=TOPIC, out=None):
        self.period = period
        self.topic = topic
        self.prefix = prefix
        self.out = out
        self.pub = None
        self.statuses = {}
        self.order = []
        self.running = {}
        self.last = None
        self.broken = False
        for s in plan.sensors:
            self.statuses[s.name] = Status(s.name, s.topic, s.sensor.msg_type)
            self.order.append(s.name)

    def _warn(self, e):
        if not self.broken:
            self.broken = True
            stream = self.out or sys.stdout
            stream.write('sensorTest: warning: /diagnostics not published: %s\n' % e)
            stream.flush()

    def publish(self):
        if self.pub is None or self.broken:
            return
        try:
            import rospy
            from diagnostic_msgs.msg import DiagnosticArray
            msg = DiagnosticArray()
            msg.header.stamp = rospy.Time.now()
            msg.status = [self.statuses[n].to_msg(self.prefix) for n in self.order]
            self.pub.publish(msg)
            self.last = time.monotonic()
        except Exception as e:
            self._warn(e)

    # ---------------------------------------------------------------- observer methods
    def run_started(self, run, plan):
        try:
            import rospy
            from diagnostic_msgs.msg import DiagnosticArray
            if self.prefix is None:
                # the default node name is unique per run (sensorTest_<pid>_<ms>): status names
                # stay "sensorTest: <sensor>" so monitors and aggregators see one status per sensor
                import re
                self.prefix = re.sub(r'_\d+_\d+$', '', rospy.get_name().lstrip('/')) or 'sensorTest'
            self.pub = rospy.Publisher(self.topic, DiagnosticArray, queue_size=10)
        except Exception as e:
            self._warn(e)
            return
        self.publish()

    def sensor_started(self, sensor_run):
        self.running[sensor_run.plan.name] = sensor_run

    def tick(self, runs, now):
        if self.pub is None or (self.last is not None and time.monotonic() - self.last < self.period):
            return
        for sensor_run in runs:
            status = self.statuses.get(sensor_run.plan.name)
            if status is not None and sensor_run.t0 is not None:
                try:
                    live_status(status, sensor_run, now)
                except Exception as e:   # a status must never stop the run
                    status.message = 'status unavailable: %s' % e
        self.publish()

    def sensor_done(self, result):
        self.running.pop(result.name, None)
        status = self.statuses.get(result.name)
        if status is None:
            status = self.statuses[result.name] = Status(result.name, result.topic, result.msg_type)
            self.order.append(result.name)
        final_status(status, result)

    def run_ended(self, run):
        for r in run.sensors:
            self.sensor_done(r)
        self.publish()
        if self.pub is None or self.broken:
            return
        try:   # let the publisher threads hand the final array to connected subscribers
            if self.pub.get_num_connections():
                time.sleep(0.3)
            self.pub.unregister()
        except (Exception, KeyboardInterrupt):
            pass
