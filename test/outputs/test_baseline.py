"""Unit: outputs/baseline.py and `sensorTestHistory baseline`: a run is pinned by id, folder or
JSON; a run that cannot serve (failed, interrupted, another platform, another robot, another
results version, unreadable) is refused with its reason; `compare` shows the drift table; the
Compare observer puts the drift on each result and the run names its baseline. Real files in a
temporary output folder; no ROS."""
import io
import json
import os

import pytest

from pepper_interface_tests import history_cli, results
from pepper_interface_tests.outputs import baseline
from pepper_interface_tests.outputs.history import HistoryError
from pepper_interface_tests.results import FAIL, PASS, RunResult, SensorResult
from pepper_interface_tests.sensors.values.audio import AudioValues, ChannelLevel


def mics(*levels):
    return AudioValues(channels={c: ChannelLevel(rms_dbfs=v) for c, v in
                                 zip(('rearLeft', 'rearRight', 'frontLeft', 'frontRight'), levels)})


def write_run(base, run_id, levels=(-29, -30, -29, -30), verdict=PASS, platform='robot', **extra):
    run = RunResult(platform=platform, mode='parallel', start=1795000000.0, end=1795000010.0, run_id=run_id)
    run.sensors.append(SensorResult(name='microphone', title='Microphones', topic='/mic', msg_type='x',
                                    verdict=verdict, family='audio', values=mics(*levels), rate_hz=10.0,
                                    messages=100))
    for k, v in extra.items():
        setattr(run, k, v)
    folder = os.path.join(base, 'runs', run_id)
    os.makedirs(folder)
    data = run.to_dict()
    with open(os.path.join(folder, results.JSON_FILE), 'w') as f:
        json.dump(data, f)
    return folder


def cli(base, *args):
    out = io.StringIO()
    code = history_cli.main(['--output-dir', str(base)] + list(args), out=out)
    return code, out.getvalue()


def test_set_show_and_clear(tmp_path, capsys):
    write_run(str(tmp_path), '20261120-101500')
    code, text = cli(tmp_path, 'baseline', 'set', '20261120-101500')
    assert code == 0 and 'baseline: run 20261120-101500' in text
    pointer = json.loads((tmp_path / baseline.POINTER).read_text())
    assert pointer['run_id'] == '20261120-101500' and pointer['path'].endswith('runs/20261120-101500')
    code, text = cli(tmp_path, 'baseline', 'show')
    assert code == 0 and '20261120-101500' in text and 'not used' not in text
    assert cli(tmp_path, 'baseline', 'clear')[0] == 0
    assert not (tmp_path / baseline.POINTER).exists()
    code, text = cli(tmp_path, 'baseline', 'show')
    assert code == 1 and 'no baseline pinned' in text


def test_a_run_is_named_by_folder_or_json_too(tmp_path):
    folder = write_run(str(tmp_path), '20261120-101500')
    assert baseline.find(str(tmp_path), folder).run_id == '20261120-101500'
    assert baseline.find(str(tmp_path), os.path.join(folder, results.JSON_FILE)).run_id == '20261120-101500'
    with pytest.raises(HistoryError, match='unknown run id'):
        baseline.find(str(tmp_path), '2025')


@pytest.mark.parametrize('extra, why', [
    ({'verdict': FAIL}, '1 sensor failed in it (microphone)'),
    ({'interrupted': True, 'interrupt_reason': 'Ctrl-C'}, 'it was interrupted (Ctrl-C)'),
])
def test_a_run_that_failed_or_was_interrupted_is_refused(tmp_path, capsys, extra, why):
    write_run(str(tmp_path), '20261120-101500', **extra)
    code, _ = cli(tmp_path, 'baseline', 'set', '20261120-101500')
    err = capsys.readouterr().err
    assert code == 2 and why in err and 'cannot be the baseline' in err
    assert not (tmp_path / baseline.POINTER).exists()


def test_another_results_version_another_platform_and_another_robot_are_refused(tmp_path):
    folder = write_run(str(tmp_path), '20261120-101500', platform='simulator')
    run = baseline.find(str(tmp_path), folder)
    assert baseline.why_not(run, 'robot') == 'it ran on the simulator, this run is on the robot'
    assert baseline.why_not(run, 'simulator') == ''
    run.data['robot'] = 'pepper-7'
    assert baseline.why_not(run, 'simulator', robot='pepper-3') == (
        'baseline from robot pepper-7, this run is robot pepper-3: pin a baseline of this robot')
    run.data['schema_version'] = 99
    assert 'results version 99' in baseline.why_not(run, 'simulator')
    with open(os.path.join(folder, results.JSON_FILE), 'w') as f:
        f.write('{"sensors": ')
    assert 'cannot be read' in baseline.why_not(baseline.find(str(tmp_path), folder))


def test_for_run_refuses_an_explicit_baseline_and_notes_a_pinned_one_that_is_gone(tmp_path):
    write_run(str(tmp_path), '20261120-101500', verdict=FAIL)
    with pytest.raises(HistoryError, match='failed in it'):
        baseline.for_run(str(tmp_path), '20261120-101500', 'robot')
    assert baseline.for_run(str(tmp_path), False, 'robot') == (None, '')
    assert baseline.for_run(str(tmp_path), 'none', 'robot') == (None, '')
    assert baseline.for_run(str(tmp_path), None, 'robot') == (None, '')      # none pinned
    (tmp_path / baseline.POINTER).write_text(json.dumps({'run_id': 'x', 'path': str(tmp_path / 'gone')}))
    compare, note = baseline.for_run(str(tmp_path), None, 'robot')
    assert compare is None and 'the pinned baseline x is gone' in note


def test_the_observer_puts_drift_on_each_result_and_the_run_names_its_baseline(tmp_path):
    write_run(str(tmp_path), '20261120-101500')
    cli(tmp_path, 'baseline', 'set', '20261120-101500')
    compare, note = baseline.for_run(str(tmp_path), None, 'robot')
    assert compare is not None and note == ''
    compare.out = io.StringIO()
    run = RunResult(platform='robot', mode='parallel', start=1795100000.0)
    compare.run_started(run, None)
    assert run.baseline['run_id'] == '20261120-101500' and run.baseline['pinned'] is True
    now = SensorResult(name='microphone', title='Microphones', topic='/mic', msg_type='x', verdict=PASS,
                       family='audio', values=mics(-41, -30, -29, -31), rate_hz=10.0, messages=100)
    compare.sensor_done(now)
    assert now.verdict == PASS and [d.measure for d in now.drift] == ['level:rearLeft']
    assert now.warnings[0].startswith('rearLeft level -41 dBFS, was -29 dBFS on')
    data = run.to_dict()
    assert data['baseline']['run_id'] == '20261120-101500'
    back = results.sensor_dict(now)
    assert back['drift'][0]['then'] == -29 and back['drift'][0]['now'] == -41
    read = results.read_run(json.loads(json.dumps(dict(data, sensors=[back]))))
    assert read.baseline['run_id'] == '20261120-101500' and read.sensors[0].drift == now.drift


def test_a_pinned_baseline_of_another_platform_is_noted_and_not_used(tmp_path):
    write_run(str(tmp_path), '20261120-101500', platform='simulator')
    cli(tmp_path, 'baseline', 'set', '20261120-101500')
    compare, _ = baseline.for_run(str(tmp_path), None, 'robot')
    compare.out = io.StringIO()
    run = RunResult(platform='robot', mode='parallel', start=1795100000.0)
    compare.run_started(run, None)
    assert run.baseline == {} and 'not used: it ran on the simulator' in compare.out.getvalue()


def test_compare_shows_the_drift_between_any_two_runs(tmp_path):
    write_run(str(tmp_path), '20261120-101500')
    write_run(str(tmp_path), '20261127-090000', levels=(-41, -30, -29, -31))
    code, text = cli(tmp_path, 'compare', '20261120-101500', '20261127-090000')
    assert code == 0 and '1 value drifted beyond its margin' in text
    assert 'microphone: rearLeft level -41 dBFS, was -29 dBFS' in text
    assert all(len(line) <= 80 for line in text.splitlines())
    code, text = cli(tmp_path, 'compare', '20261120-101500', '20261120-101500')
    assert 'no value drifted beyond its margin (5 values compared' in text


def test_a_hand_edited_pointer_is_a_note_not_a_traceback(tmp_path, capsys):
    (tmp_path / baseline.POINTER).write_text('{"run_id": ')
    compare, note = baseline.for_run(str(tmp_path), None, 'robot')
    assert compare is None and 'cannot read' in note and 'baseline clear' in note
    (tmp_path / baseline.POINTER).write_text('[1, 2]')
    assert 'names no run' in baseline.for_run(str(tmp_path), None, 'robot')[1]
    code, _ = cli(tmp_path, 'baseline', 'show')
    assert code == 2 and 'names no run' in capsys.readouterr().err
    assert cli(tmp_path, 'baseline', 'clear')[0] == 0 and not (tmp_path / baseline.POINTER).exists()


@pytest.mark.parametrize('columns', [80, 50])
def test_the_terminal_summary_has_a_drift_section_that_fits(tmp_path, monkeypatch, columns):
    from pepper_interface_tests.outputs.terminal import Terminal
    monkeypatch.setenv('COLUMNS', str(columns))
    write_run(str(tmp_path), '20261120-101500')
    compare, _ = baseline.for_run(str(tmp_path), '20261120-101500', 'robot')
    compare.out = io.StringIO()
    run = RunResult(platform='robot', mode='parallel', start=1795100000.0, end=1795100010.0)
    compare.run_started(run, None)
    now = SensorResult(name='microphone', title='Microphones', topic='/mic', msg_type='x', verdict=PASS,
                       family='audio', values=mics(-41, -30, -29, -31), rate_hz=10.0, messages=100)
    compare.sensor_done(now)
    run.sensors.append(now)
    out = io.StringIO()
    Terminal(stream=out).run_ended(run)
    text = out.getvalue() + compare.out.getvalue()
    flat = ' '.join(text.split())
    assert 'drift since the baseline run 20261120-101500 (1 value, warnings, not failures):' in flat
    assert 'drifted since the baseline: rearLeft level (below)' in flat and 'grille' in text
    drift_part = text[text.index('drift since'):text.index('PASS* =')] + compare.out.getvalue()
    assert all(len(line) <= columns for line in drift_part.splitlines()), drift_part
    run.sensors[0].drift, run.sensors[0].warnings = [], []
    out = io.StringIO()
    Terminal(stream=out).run_ended(run)
    assert 'no drift since the baseline run 20261120-101500' in out.getvalue()


A, B = 'AP990370B0000000', 'AP990370B0000001'
OTHER = 'baseline from robot %s, this run is robot %s: pin a baseline of this robot' % (A, B)


def test_a_pinned_baseline_of_another_robot_is_noted_and_not_used(tmp_path):
    write_run(str(tmp_path), '20261120-101500', robot=A)
    cli(tmp_path, 'baseline', 'set', '20261120-101500')
    for robot, used in ((B, False), (A, True), ('', True)):     # '': this run does not know its robot
        compare, _ = baseline.for_run(str(tmp_path), None, 'robot', robot)
        compare.out = io.StringIO()
        run = RunResult(platform='robot', mode='parallel', start=1795100000.0, robot=robot)
        compare.run_started(run, None)
        assert compare.active is used and bool(run.baseline) is used
        assert (OTHER in ' '.join(compare.out.getvalue().split())) is not used, compare.out.getvalue()


def test_dash_dash_baseline_of_another_robot_is_refused_and_a_baseline_without_one_serves(tmp_path):
    folder = write_run(str(tmp_path), '20261120-101500', robot=A)
    with pytest.raises(HistoryError, match=OTHER):
        baseline.for_run(str(tmp_path), folder, 'robot', B)
    assert baseline.for_run(str(tmp_path), folder, 'robot', A)[0] is not None
    unnamed = write_run(str(tmp_path), '20261120-111500')       # a run that did not know its robot
    assert baseline.for_run(str(tmp_path), unnamed, 'robot', B)[0] is not None
