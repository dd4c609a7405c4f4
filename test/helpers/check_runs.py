"""A check's window fed with real serialized messages, at explicit times (no dependence on the
speed of the machine): the sensors' unit tests (sensors/test_*.py), the runner's and the result
files' tests."""
import os

import genpy

from fake_pepper import serialized
from pepper_interface_tests.plan import catalog, settings
from pepper_interface_tests.plan.settings import Options, SensorPlan
from pepper_interface_tests.sensors.base import RunContext
from pepper_interface_tests.sensors.window import SensorRun

PKG = settings.package_dir()
ROBOT = settings.read_expectations(os.path.join(PKG, 'config', 'sensorExpectations.yaml'), 'robot')
T0 = 5000.0            # the runner's clock when listening begins (monotonic seconds)
R0 = 1700000000.0      # ROS time at T0


def make_run(name, tmp_path, expect=None, topic='/t', quick=False, wait=2.0, duration=3.0):
    plan = SensorPlan(catalog.SENSORS[name], topic, ROBOT[name].but(**(expect or {})))
    ctx = RunContext(str(tmp_path), 'robot', Options())
    run = SensorRun(plan, ctx, T0, quick=quick, wait=wait, duration=duration)
    run.begin(T0)
    return run


def feed(run, msgs, rate=10.0, start=0.05, delay=0.01, stamp=None):
    """Feed messages at `rate` from `start` s; header stamps = ROS time - delay unless `stamp`
    (i, ros_time) -> seconds says otherwise. Returns the last receive time."""
    t = T0
    for i, m in enumerate(msgs):
        t = T0 + start + i / rate
        ros = R0 + (t - T0)
        if hasattr(m, 'header'):
            s = stamp(i, ros) if stamp else ros - delay
            m.header.stamp = genpy.Time.from_sec(s) if s else genpy.Time(0, 0)
        run.feed_raw(run.sensor.msg_type, serialized(m), t, ros)
    return t


def close(run, at=3.0, reason='window ended', lookup=None):
    return run.close(T0 + at, reason, lookup)


def judged(name, tmp_path, msgs, expect=None, **kw):
    """Messages fed at the sensor's nominal rate (unless rate=...), judged after a 3 s window."""
    kw.setdefault('rate', float(ROBOT[name].nominal))
    run = make_run(name, tmp_path, expect)
    feed(run, msgs, **kw)
    return close(run, at=3.0)


def one_reason_with(result, words):
    hits = [r for r in result.reasons if words in r]
    assert hits, 'no reason with %r in %r' % (words, result.reasons)
    return hits[0]


N = 25      # messages per window at 10 Hz (2.5 s of a 3 s window)
NJ = 125    # joint states: 2.5 s at their nominal 50 Hz
