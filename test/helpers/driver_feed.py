"""A window fed with the messages the real drivers build, with their connection header (type,
definition) as the live subscription and the bag reader pass it: the driver-semantics tests of
the laser (sensors/test_laser.py) and of the other families (sensors/test_driver_semantics.py)."""
import os

import genpy

from fake_pepper import serialized
from pepper_interface_tests.plan import catalog, settings
from pepper_interface_tests.plan.settings import Options, SensorPlan
from pepper_interface_tests.sensors.base import RunContext
from pepper_interface_tests.sensors.window import SensorRun

PKG = settings.package_dir()
EXPECT = os.path.join(PKG, 'config', 'sensorExpectations.yaml')
ROBOT = settings.read_expectations(EXPECT, 'robot')
SIM = settings.read_expectations(EXPECT, 'simulator')
T0, R0 = 5000.0, 1700000000.0


def run_of(name, tmp_path, platform_expect, expect=None, record=False):
    plan = SensorPlan(catalog.SENSORS[name], '/t', platform_expect[name].but(**(expect or {})))
    ctx = RunContext(str(tmp_path), 'robot', Options(record=record))
    run = SensorRun(plan, ctx, T0, duration=3.0)
    run.begin(T0)
    return run


def feed(run, msgs, rate, type_name=None, conn=None):
    for i, m in enumerate(msgs):
        t = T0 + 0.05 + i / rate
        if hasattr(m, 'header'):
            m.header.stamp = genpy.Time.from_sec(R0 + (t - T0) - 0.01)
        run.feed_raw(type_name or run.sensor.msg_type, serialized(m), t, R0 + (t - T0), conn)
    return run.close(T0 + 3.0, 'window ended')
