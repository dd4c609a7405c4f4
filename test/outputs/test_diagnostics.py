"""Unit: the pure mapping of a sensor's state or result to its /diagnostics status
(diagnostics.result_status / waiting_status / live_status), without a master."""
import os

from diagnostic_msgs.msg import DiagnosticStatus

import fake_pepper as fake
from pepper_interface_tests.outputs import diagnostics as D
from pepper_interface_tests.plan import catalog, settings
from pepper_interface_tests.plan.settings import Options, SensorPlan
from pepper_interface_tests.results import FAIL, INTERRUPTED, PASS, SKIPPED, SensorResult
from pepper_interface_tests.sensors.base import RunContext
from pepper_interface_tests.sensors.window import SensorRun


def result(verdict, **kw):
    base = dict(name='frontSonar', title='Front sonar', topic='/naoqi_driver/sonar/front',
                msg_type='sensor_msgs/Range', verdict=verdict, messages=50, rate_hz=9.8,
                expected_rate_hz=[4.0, 16.0], window_s=5.0)
    base.update(kw)
    return SensorResult(**base)


def test_levels_are_the_message_constants():
    assert (D.OK, D.WARN, D.ERROR, D.STALE) == (DiagnosticStatus.OK, DiagnosticStatus.WARN,
                                                DiagnosticStatus.ERROR, DiagnosticStatus.STALE)


def test_pass_is_ok_with_count_and_rate():
    s = D.result_status(result(PASS))
    assert s.level == D.OK and s.message == 'PASS: 50 msgs, 9.8 Hz'
    values = dict(s.values)
    assert values['verdict'] == 'PASS' and values['expected rate (Hz)'] == '4-16'
    assert values['topic'] == '/naoqi_driver/sonar/front' and values['nominal rate (Hz)'] == ''
    assert all(isinstance(v, str) for _, v in s.values)


def test_pass_with_warnings_is_warn():
    s = D.result_status(result(PASS, warnings=['frame_id "x" unusual', 'delay 0.3 s']))
    assert s.level == D.WARN
    assert s.message == 'PASS with warnings: frame_id "x" unusual; delay 0.3 s'


def test_fail_is_error_with_reasons():
    s = D.result_status(result(FAIL, reasons=['range is NaN in 50 of 50 messages']))
    assert s.level == D.ERROR and s.message == 'FAIL: range is NaN in 50 of 50 messages'
    assert dict(s.values)['reasons'] == 'range is NaN in 50 of 50 messages'


def test_interrupted_is_stale_not_error():
    s = D.result_status(result(INTERRUPTED, reasons=['interrupted after 2.1 s of 5.0 s']))
    assert s.level == D.STALE and s.message.startswith('INTERRUPTED: interrupted after')


def test_skipped_is_ok_but_not_run_is_stale():
    skipped = D.result_status(result(SKIPPED, reasons=['no stereo camera on this head']))
    assert skipped.level == D.OK and skipped.message == 'SKIPPED: no stereo camera on this head'
    not_run = D.result_status(result(SKIPPED, reasons=['not run: the run was interrupted']))
    assert not_run.level == D.STALE and not_run.message == 'not run: the run was interrupted'


def test_artifacts_listed_as_files():
    s = D.result_status(result(PASS, artifacts={'video': 'frontCamera.mp4'}))
    assert ('file video', 'frontCamera.mp4') in s.values


def test_waiting_and_node_name():
    s = D.waiting_status('/naoqi_driver/laser', 'sensor_msgs/LaserScan')
    assert s.level == D.STALE and s.message == 'waiting to start'
    assert D.base_node_name('/sensorTest_4242_1700000000123') == 'sensorTest'
    assert D.base_node_name('/my_tester') == 'my_tester'


def listening_back_sonar(tmp_path, rate, seconds=2.0):
    """A back-sonar SensorRun (robot expectations: 4-16 Hz) fed `rate` Hz for `seconds`."""
    t0, ros0 = 5000.0, 1.7e9
    path = os.path.join(settings.package_dir(), 'config', 'sensorExpectations.yaml')
    plan = SensorPlan(catalog.SENSORS['backSonar'], '/t', settings.read_expectations(path, 'robot')['backSonar'])
    run = SensorRun(plan, RunContext(str(tmp_path), 'robot', Options()), t0, wait=2.0, duration=3.0)
    run.begin(t0)
    waiting = D.live_status(run.progress(t0 + 1.0))
    for i in range(int(rate * seconds)):
        t = t0 + 0.05 + i / rate
        run.feed_raw('sensor_msgs/Range', fake.serialized(fake.sonar(i, ros0 + t - t0)), t, ros0 + t - t0)
    return waiting, D.live_status(run.progress(t0 + seconds + 0.1))


def test_live_status_waits_then_listens_and_warns_on_a_rate_outside_the_band(tmp_path):
    waiting, good = listening_back_sonar(tmp_path, 10.0)
    assert waiting.level == D.STALE and waiting.message == 'waiting for the first message (1.0 s of 2.0 s)'
    assert good.level == D.OK and good.message == 'listening, 20 msgs, 10.0 Hz'
    assert dict(good.values)['state'] == 'listening' and dict(good.values)['problems so far'] == ''
    _, slow = listening_back_sonar(tmp_path, 2.0)
    assert slow.level == D.WARN
    assert slow.message == 'listening, 4 msgs, 2.0 Hz; so far: rate 2.00 Hz outside the expected 4-16 Hz'
