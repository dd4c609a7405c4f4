"""robotHealth (sensors/health.py) on DiagnosticArrays as naoqi_driver builds them
(src/converters/diagnostics.cpp), and against the emulator's diagnostics on a real master:
each fault named in words, no driver statuses, and sensorTest's own /diagnostics never judged."""
import os

import pytest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue

from pepper_interface_tests.emulator.events import JOINTS, driver_array
from pepper_interface_tests.plan import settings
from pepper_interface_tests.results import FAIL, PASS
from pepper_interface_tests.sensors import check_class
from pepper_interface_tests.sensors.base import RunContext


def vals(check):
    """The values the check hands over, as the run's JSON holds them (keys and lists)."""
    from pepper_interface_tests import codec
    return codec.to_json(check.result_values())


def make(tmp_path, **expect):
    topics = os.path.join(str(tmp_path), 'healthTopics.dat')
    with open(topics, 'w') as f:
        f.write('robotHealth /diagnostics\n')
    plan = settings.load_plan(settings.Options(platform='robot', sensors=('robotHealth',), topics=topics,
                                               output_dir=str(tmp_path / 'out'), wait=2.0))
    sp = plan.sensors[0]
    if expect:
        sp = settings.SensorPlan(sp.sensor, sp.topic, sp.expect.but(**expect))
    return check_class(sp.sensor.family)(sp, RunContext(plan.output_dir, plan.platform, plan.options))


def temps(**hot):
    out = {j: 35.0 for j in JOINTS}
    out.update(hot)
    return out


def run(check, arrays, end=3.0):
    for i, a in enumerate(arrays):
        check.poll(i * 1.0)
        check.feed(a, i * 1.0)
    check.poll(end)
    check.close()
    return check.judgement()


def test_all_ok_passes_with_battery_and_hottest_joints_in_the_notes(tmp_path):
    c = make(tmp_path)
    j = run(c, [driver_array(temps(KneePitch=41.5), 85, False)] * 2)
    assert j.verdict == PASS and not j.warnings, j
    assert 'battery 85%, not charging (driver: OK)' in c.notes
    assert c.notes[-1].startswith('hottest joints: KneePitch 41.5°C, ')
    assert vals(c)['battery_percent'] == 85 and vals(c)['charging'] is False
    assert vals(c)['hottest'][0] == {'joint': 'KneePitch', 'temperature_c': 41.5, 'level': 'OK', 'message': 'OK'}
    assert c.done()


def test_hot_joints_warn_with_names_and_temperatures(tmp_path):
    c = make(tmp_path)
    j = run(c, [driver_array(temps(HipPitch=70.0, RElbowYaw=68.0), 85, False)] * 2)
    assert j.verdict == PASS
    assert j.warnings == ['hot (the driver\'s WARN, 68-74 °C): HipPitch 70°C, RElbowYaw 68°C']


def test_too_hot_fails_saying_what_to_do(tmp_path):
    c = make(tmp_path)
    j = run(c, [driver_array(temps(HipPitch=75.5), 85, False)] * 2)
    assert j.verdict == FAIL
    assert j.reasons[0].startswith('too hot (the driver\'s ERROR, 74 °C and above): HipPitch 75.5°C: '
                                   'let the robot cool down')


def test_the_worst_level_of_the_window_counts(tmp_path):
    c = make(tmp_path, arrays=3)
    j = run(c, [driver_array(temps(HipPitch=75.0), 85, False), driver_array(temps(), 85, False),
                driver_array(temps(), 85, False)])
    assert j.verdict == FAIL and 'HipPitch 75°C' in j.reasons[0]


@pytest.mark.parametrize('percent, charging, full, verdict, words', [
    (61, False, False, PASS, None),
    (60, False, False, PASS, 'battery discharging: 60% left (the driver warns at 60 % or less'),
    (31, False, False, PASS, 'battery discharging: 31% left'),
    (30, False, False, FAIL, 'battery almost empty: 30% left (the driver\'s ERROR, 30 % or less and not '
                             'charging): charge it before testing'),
    (12, True, False, PASS, None),           # charging: the driver says OK (diagnostics.cpp:240-244)
    (100, False, True, PASS, None),
])
def test_battery_follows_the_driver_levels(tmp_path, percent, charging, full, verdict, words):
    c = make(tmp_path)
    j = run(c, [driver_array(temps(), percent, charging, full)] * 2)
    assert j.verdict == verdict, j
    text = ' '.join(j.reasons + j.warnings)
    if words:
        assert words in text
    else:
        assert 'battery' not in text
    state = 'fully charged' if full else 'charging' if charging else 'not charging'
    assert c.notes[0].startswith('battery %d%%, %s' % (percent, state))


def own_status_array():
    """What sensorTest's own /diagnostics look like (outputs/diagnostics.py): never judged."""
    return DiagnosticArray(status=[DiagnosticStatus(level=2, name='sensorTest: laser', message='FAIL',
                                                    values=[KeyValue('verdict', 'FAIL')])])


def test_no_driver_status_fails_within_the_wait_and_other_nodes_statuses_are_ignored(tmp_path):
    c = make(tmp_path)
    c.feed(own_status_array(), 0.2)
    c.poll(1.0)
    assert not c.done()
    c.poll(2.1)
    assert c.done()
    c.close()
    j = c.judgement()
    assert j.verdict == FAIL
    assert j.reasons == ['no naoqi_driver diagnostics on /diagnostics within 2 s (1 array from other nodes '
                         'only): the driver\'s diagnostics are off (converters.diag.enabled in its '
                         'boot_config.json) or naoqi_driver is not running']


def test_the_report_shows_the_battery_and_the_hottest_joints(tmp_path):
    import json

    from pepper_interface_tests import codec
    from pepper_interface_tests.outputs.report import views
    from pepper_interface_tests.outputs.report.blocks import KV, Table
    from pepper_interface_tests.results import SensorResult
    from pepper_interface_tests.sensors.values.health import HealthValues
    c = make(tmp_path)
    run(c, [driver_array(temps(HipPitch=70.0), 45, False)] * 2)
    values = codec.from_json(HealthValues, json.loads(json.dumps(vals(c))))     # as the JSON file keeps them
    r = SensorResult('robotHealth', 'ROBOT HEALTH', '/diagnostics', 'diagnostic_msgs/DiagnosticArray', PASS,
                     values=values)
    blocks = views.render('health', r, r.values, None)
    kv = dict((k, getattr(v, 'text', v)) for k, v in [b for b in blocks if isinstance(b, KV)][0].rows)
    assert kv['charge'] == '45 %' and kv['charging'] == 'not charging' and kv['driver level'] == 'WARN'
    tables = [b for b in blocks if isinstance(b, Table)]
    assert tables[0].rows[0][0] == 'HipPitch' and tables[0].rows[0][1] == '70.0 °C'
    assert [row[0] for row in tables[1].rows] == ['HipPitch']     # the hot joints


def test_the_emulator_builds_the_array_as_diagnostics_cpp():
    """Names, levels, words and value formats of src/converters/diagnostics.cpp:159-305."""
    a = driver_array(temps(HipPitch=70.0, KneePitch=80.0), 45, False)
    names = [s.name for s in a.status]
    assert names[:len(JOINTS)] == ['naoqi_driver_joints:' + j for j in JOINTS]
    assert names[len(JOINTS):] == ['naoqi_driver_joints:Status', 'naoqi_driver_battery:Status',
                                   'naoqi_driver_battery:Current', 'naoqi_driver_computer:CPU']
    by = {s.name: s for s in a.status}
    assert (by['naoqi_driver_joints:HipPitch'].level, by['naoqi_driver_joints:HipPitch'].message) == (1, 'Hot')
    assert (by['naoqi_driver_joints:KneePitch'].level, by['naoqi_driver_joints:KneePitch'].message) == (2, 'Too hot')
    joints = by['naoqi_driver_joints:Status']
    assert (joints.level, joints.message) == (2, 'ERROR')
    assert {kv.key: kv.value for kv in joints.values}['Hot Joints'] == '\nHipPitch: 70°C\nKneePitch: 80°C'
    battery = by['naoqi_driver_battery:Status']
    assert (battery.level, battery.message) == (1, 'Battery discharging (  45% left)')
    assert [(kv.key, kv.value) for kv in battery.values] == [('Percentage', '45'), ('Charging', 'False'),
                                                              ('Fully Charged', 'False')]
    assert driver_array(temps(), 20, True).status[-3].message == 'Charging (  20%)'


def stop_this_process(seconds):
    """A real SIGSTOP of this process for `seconds` (a child sends the SIGCONT): what a PC too busy
    to run sensorTest does; the stall probe (sensors/lag.py) sees it."""
    import signal
    import subprocess
    import time

    from pepper_interface_tests.sensors.lag import StallProbe
    StallProbe.shared()
    time.sleep(0.2)
    child = subprocess.Popen(['sh', '-c', 'sleep %s; kill -CONT %d' % (seconds, os.getpid())])
    os.kill(os.getpid(), signal.SIGSTOP)
    child.wait()


def live_poll(check, until, step=0.1):
    """The runner's polls of a live window, on this process's clock, until `until` s or done()."""
    import time
    t0 = time.monotonic()
    while not check.done() and time.monotonic() - t0 < until:
        check.poll(time.monotonic() - t0)
        time.sleep(step)
    return time.monotonic() - t0


@pytest.mark.integration
def test_nothing_heard_while_this_process_was_stopped_is_not_judged_after_a_longer_wait(tmp_path):
    """Issue 41 on ROS 2: a healthy driver's arrays held unhandled while sensorTest did not run.
    The window waits BUSY_EXTRA s more than --wait, then names the PC: NOT JUDGED, never FAIL."""
    from pepper_interface_tests.results import NOT_JUDGED
    from pepper_interface_tests.sensors.health import BUSY_EXTRA
    c = make(tmp_path)
    c.observe_connections(1)                # the driver's publisher is on the topic
    c.poll(0.0)
    stop_this_process(1.5)
    took = live_poll(c, 20)
    assert c.done() and took >= 2.0 + BUSY_EXTRA - 0.5, took
    c.close()
    j = c.judgement()
    assert j.verdict == NOT_JUDGED and not j.reasons, j
    assert j.unjudged[0].startswith('PC busy: no naoqi_driver diagnostics on /diagnostics within 8 s although '
                                    'the topic has a publisher, but this PC was busy (load average '), j
    assert 'sensorTest did not run for' in j.unjudged[0], j


@pytest.mark.integration
@pytest.mark.parametrize('publishers, other', [(0, False), (1, True)], ids=['no publisher', 'other nodes heard'])
def test_a_busy_pc_explains_nothing_when_no_one_publishes_or_other_arrays_were_handled(tmp_path, publishers, other):
    """The driver's diagnostics off (no publisher but sensorTest), or other nodes' arrays handled
    meanwhile (the PC did take the topic): FAIL within --wait, however busy the PC."""
    c = make(tmp_path)
    c.observe_connections(publishers)
    if other:
        c.feed(own_status_array(), 0.1)
    c.poll(0.0)
    stop_this_process(1.5)
    took = live_poll(c, 20)
    assert c.done() and took < 2.0 + 1.0, took
    c.close()
    assert c.judgement().verdict == FAIL and c.judgement().reasons[0].startswith(
        'no naoqi_driver diagnostics on /diagnostics within 2 s'), c.judgement()
