"""Run history (history.py, scripts/sensorTestHistory): every run in its own folder, the latest
run at the spec's paths, listing and comparing runs. sensorTest runs as a subprocess against a
real master and test/nodes/core_publisher.py publishers."""
import json
import os
import re
import signal
import subprocess
import time

import pytest

from report_helpers import printed_path, sensor_test, start_publishers, stop
from rosmaster import kill_group, script, spawn, wait_until

BACK, LASER = '/naoqi_driver/sonar/back', '/naoqi_driver/laser'


def history(*args, env=None):
    environment = dict(os.environ)
    environment.pop('COLUMNS', None)          # 80 columns unless the test says otherwise
    environment.update(env or {})
    return subprocess.run(script('sensorTestHistory') + list(args), capture_output=True, text=True,
                          timeout=60, env=environment)


def load(path):
    with open(path, encoding='utf-8') as f:
        return json.load(f)


@pytest.fixture(scope='module')
def two_runs(module_master, tmp_path_factory):
    """Run 1: back sonar at 10 Hz and the laser; run 2: back sonar at 5 Hz, laser gone."""
    out = tmp_path_factory.mktemp('history') / 'out'
    args = ['--sensors', 'backSonar,laser', '--mode', 'parallel', '--duration', '2.5', '--wait', '1.5',
            '--output-dir', str(out)]
    pubs = start_publishers(module_master, [('range', BACK), ('laser', LASER)])
    try:
        first = sensor_test(module_master, args)
    finally:
        stop(pubs)
    snapshot = {n: open(os.path.join(out, n), 'rb').read() for n in ('sensorTestResults.json',)}
    pubs = start_publishers(module_master, [('range', BACK, '--rate', '5')])
    try:
        second = sensor_test(module_master, args)
    finally:
        stop(pubs)
    return out, first, second, snapshot


def test_each_run_has_its_folder_and_the_latest_is_in_the_output_dir(two_runs):
    out, first, second, snapshot = two_runs
    assert first.returncode == 0, first.stdout + first.stderr
    assert second.returncode == 1, second.stdout + second.stderr
    runs = sorted(os.listdir(out / 'runs'))
    assert len(runs) == 2 and runs[0] < runs[1]
    for run_id in runs:
        folder = out / 'runs' / run_id
        for name in ('sensorTestResults.json', 'sensorTestResults.xml', 'sensorTestOutput.dat',
                     'sensorTestReport.html'):
            assert (folder / name).exists(), (run_id, name)
        data = load(folder / 'sensorTestResults.json')
        assert data['run_id'] == run_id and data['output_dir'] == str(folder)
        assert (folder / 'sensorTestOutput.dat').read_text().count('[START TIME]') == 1
    # run 1's own files were not touched by run 2
    assert (out / 'runs' / runs[0] / 'sensorTestResults.json').read_bytes() == snapshot['sensorTestResults.json']
    # the spec's paths hold the latest run; the output file is appended by both runs
    latest = load(out / 'sensorTestResults.json')
    assert latest['run_id'] == runs[1]
    xml = 'sensorTestResults.xml'
    assert (out / xml).read_bytes() == (out / 'runs' / runs[1] / xml).read_bytes()
    assert 'run <b>%s</b>' % runs[1] in (out / 'sensorTestReport.html').read_text()
    dat = (out / 'sensorTestOutput.dat').read_text()
    assert dat.count('[START TIME]') == 2
    assert dat.count('run id ' + runs[0]) == 1 and dat.count('run id ' + runs[1]) == 1
    # the printed paths point into the run folder
    assert printed_path(second.stdout, 'report') == str(out / 'runs' / runs[1] / 'sensorTestReport.html')
    assert 'run %s kept in' % runs[1] in ' '.join(second.stdout.split())


def test_list_shows_every_run(two_runs):
    out, *_ = two_runs
    runs = sorted(os.listdir(out / 'runs'))
    p = history('--output-dir', str(out), 'list')
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert lines[0].split()[:5] == ['run', 'id', 'start', 'platform', 'mode']
    row1 = next(line for line in lines if line.startswith(runs[0]))
    row2 = next(line for line in lines if line.startswith(runs[1]))
    assert 'robot' in row1 and 'parallel' in row1 and 'live' in row1
    assert row1.split()[-4:] == ['2', '0', '0', '-']                  # pass fail skip, no failed sensor
    assert row2.split()[-4:] == ['1', '1', '0', 'laser']
    data = json.loads(history('--output-dir', str(out), 'list', '--json').stdout)
    assert [d['run_id'] for d in data] == runs and data[1]['failed'] == ['laser']


def test_compare_shows_verdict_and_rate_changes(two_runs):
    out, *_ = two_runs
    runs = sorted(os.listdir(out / 'runs'))
    p = history('--output-dir', str(out), 'compare')            # default: the last two
    assert p.returncode == 0, p.stderr
    assert p.stdout.startswith('compare %s (A) -> %s (B)' % (runs[0], runs[1]))
    laser = next(line for line in p.stdout.splitlines() if line.startswith('laser '))
    assert laser.split()[1:4] == ['PASS', 'FAIL', '*']
    back = next(line for line in p.stdout.splitlines() if line.startswith('backSonar '))
    change = float(re.search(r'(-?\d+\.\d)%', back).group(1))
    assert back.endswith('!') and change < -20.0                   # 10 Hz -> 5 Hz: beyond the 20 % flag
    assert '1 verdict change:' in p.stdout
    assert re.search(r'^  laser +PASS +FAIL +no publisher on /naoqi_driver/laser', p.stdout, re.M), p.stdout
    assert '2 rate changes over 20%:' in p.stdout and re.search(r'backSonar +\d+\.\d\d Hz +-> +\d', p.stdout)
    explicit = history('--output-dir', str(out), 'compare', runs[0], runs[1], '--json')
    rows = {r['sensor']: r for r in json.loads(explicit.stdout)['sensors']}
    assert rows['laser']['verdict_changed'] and rows['backSonar']['rate_flag']
    # the change is what the two runs measured (each over 2.5 s on a shared machine: about
    # -50 %, not its digits), and the text shows the same number
    back_rates = rows['backSonar']
    assert back_rates['rate_change'] == pytest.approx((back_rates['rate_b'] - back_rates['rate_a'])
                                                      / back_rates['rate_a'])
    assert back_rates['rate_change'] < -0.2 and float('%.1f' % (100 * back_rates['rate_change'])) == change
    same = json.loads(history('--output-dir', str(out), 'compare', runs[1], runs[1], '--json').stdout)
    assert not any(r['verdict_changed'] or r['rate_flag'] for r in same['sensors'])


def test_unknown_run_ids_exit_2(two_runs, tmp_path):
    out, *_ = two_runs
    p = history('--output-dir', str(out), 'compare', '19990101-000000')
    assert p.returncode == 2 and 'unknown run id "19990101-000000"' in p.stderr, p.stderr
    assert history('--output-dir', str(out), 'path', 'nope').returncode == 2
    empty = history('--output-dir', str(tmp_path), 'compare')
    assert empty.returncode == 2 and 'needs two runs' in empty.stderr
    assert history('--output-dir', str(out), 'frobnicate').returncode == 2


def test_interrupted_run_is_kept_and_published(module_master, tmp_path):
    out = tmp_path / 'out'
    pubs = start_publishers(module_master, [('range', BACK)])
    try:
        proc = spawn(script('sensorTest') + ['--no-show', '--sensors', 'backSonar,laser', '--duration', '30',
                                             '--output-dir', str(out)],
                     module_master.env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        line = ''
        deadline = time.monotonic() + 30
        while 'start  backSonar' not in line and time.monotonic() < deadline:
            line = proc.stdout.readline()
        time.sleep(2.0)    # 2 s into the run, then Ctrl-C
        rc = kill_group(proc, signal.SIGINT, timeout=60)
        stdout = line + proc.stdout.read()
        proc.stdout.close()
        proc.stderr.close()
    finally:
        stop(pubs)
    assert rc == 130, stdout
    (run_id,) = os.listdir(out / 'runs')
    data = load(out / 'runs' / run_id / 'sensorTestResults.json')
    assert data['interrupted'] and data['run_id'] == run_id
    assert load(out / 'sensorTestResults.json')['run_id'] == run_id
    assert 'Interrupted' in (out / 'sensorTestReport.html').read_text()
    assert '[INTERRUPTED]' in (out / 'sensorTestOutput.dat').read_text()
    p = history('--output-dir', str(out), 'list')
    assert 'INTERRUPTED' in p.stdout


def test_no_history_writes_straight_into_the_output_dir(module_master, tmp_path):
    pubs = start_publishers(module_master, [('range', BACK)])
    try:
        proc = sensor_test(module_master, ['--sensors', 'backSonar', '--duration', '1.5', '--no-history',
                                           '--no-report', '--output-dir', str(tmp_path)])
    finally:
        stop(pubs)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert not (tmp_path / 'runs').exists()
    data = load(tmp_path / 'sensorTestResults.json')
    assert data['run_id'] and data['output_dir'] == str(tmp_path)
    assert not (tmp_path / 'sensorTestReport.html').exists()


def test_run_ids_are_unique_within_a_second(tmp_path):
    from pepper_interface_tests.outputs.history import RunFolder, list_runs
    now = time.time()
    folders = [RunFolder.create(str(tmp_path), now=now) for _ in range(11)]
    ids = [f.run_id for f in folders]
    assert len(set(ids)) == 11 and ids[1] == ids[0] + '-2' and ids[10] == ids[0] + '-11'
    assert all(os.path.isdir(f.path) for f in folders)
    assert [r.run_id for r in list_runs(str(tmp_path))] == ids           # -2 before -10


def test_publishing_removes_only_unchanged_files_of_the_previous_run(tmp_path):
    from pepper_interface_tests.outputs.history import RunFolder, publish_latest
    a = RunFolder.create(str(tmp_path), now=1.7e9)
    for name in ('sensorTestResults.json', 'frontCameraOutput.mp4', 'bottomCameraOutput.mp4'):
        (tmp_path / 'runs' / a.run_id / name).write_text('run a ' + name)
    assert sorted(publish_latest(a)) == ['bottomCameraOutput.mp4', 'frontCameraOutput.mp4', 'sensorTestResults.json']
    (tmp_path / 'bottomCameraOutput.mp4').unlink()
    (tmp_path / 'bottomCameraOutput.mp4').write_text('edited by a user, longer than before')
    (tmp_path / 'notes.txt').write_text('mine')
    b = RunFolder.create(str(tmp_path), now=1.7e9 + 60)
    (tmp_path / 'runs' / b.run_id / 'sensorTestResults.json').write_text('run b')
    publish_latest(b)
    assert (tmp_path / 'sensorTestResults.json').read_text() == 'run b'
    assert not (tmp_path / 'frontCameraOutput.mp4').exists()                 # run a's, unchanged: gone
    assert (tmp_path / 'bottomCameraOutput.mp4').read_text().startswith('edited')   # changed: kept
    assert (tmp_path / 'notes.txt').read_text() == 'mine'
    assert (tmp_path / 'runs' / a.run_id / 'frontCameraOutput.mp4').exists()  # history intact


# ------------------------------------------------------------------ malformed and incomplete runs

MALFORMED = [
    ('[1, 2]', 'not a JSON object'),
    ('{"sensors": "laser"}', '"sensors" is not a list'),
    ('{"sensors": [{"name": "laser"}]}', 'sensor 1 has no name or verdict'),
    ('{"sensors": [{"name": "laser", "verdict": "PASS", "rate_hz": "fast"}]}', 'rate_hz is not a number'),
    ('{"summary": "2 passed", "sensors": []}', '"summary" is not a table of counts'),
    ('{"platform": 3, "sensors": []}', '"platform" is not a text'),
    ('{"sensors": [{"name": "laser", "verdict": "PASS", "reasons": "none"}]}', 'reasons is not a list'),
    ('{"sensors": [', 'cannot read'),
]


def copy_history(two_runs, tmp_path):
    """The two real runs of the fixture in a folder of this test's own (real files)."""
    import shutil
    out, *_ = two_runs
    mine = tmp_path / 'out'
    shutil.copytree(str(out / 'runs'), str(mine / 'runs'))
    return mine, sorted(os.listdir(str(mine / 'runs')))


def add_run(out, run_id, json_text=None):
    folder = out / 'runs' / run_id
    folder.mkdir()
    if json_text is not None:
        (folder / 'sensorTestResults.json').write_text(json_text, encoding='utf-8')
    return folder


@pytest.mark.parametrize('text, why', MALFORMED)
def test_list_and_compare_skip_a_malformed_run_json_with_a_note(two_runs, tmp_path, text, why):
    """Before: a traceback (AttributeError/KeyError/TypeError) for every one of these."""
    out, runs = copy_history(two_runs, tmp_path)
    add_run(out, '29990101-000000', text)
    p = history('--output-dir', str(out), 'list')
    assert p.returncode == 0 and 'Traceback' not in p.stderr, p.stderr
    row = next(line for line in p.stdout.splitlines() if line.startswith('29990101-000000'))
    assert 'incomplete:' in row and why in row, row
    data = json.loads(history('--output-dir', str(out), 'list', '--json').stdout)
    assert data[-1]['complete'] is False and why in data[-1]['problem']
    c = history('--output-dir', str(out), 'compare')
    assert c.returncode == 0 and 'Traceback' not in c.stderr, c.stderr
    assert c.stdout.startswith('compare %s (A) -> %s (B)' % (runs[0], runs[1]))
    assert 'note: skipping run 29990101-000000' in c.stderr and why in c.stderr
    named = history('--output-dir', str(out), 'compare', '29990101-000000')
    assert named.returncode == 2 and 'cannot be compared' in named.stderr and 'Traceback' not in named.stderr


def test_compare_skips_an_incomplete_latest_run(two_runs, tmp_path):
    """Before: "run ... cannot be compared: no sensorTestResults.json", exit 2, while a run was
    still going (or had been killed)."""
    out, runs = copy_history(two_runs, tmp_path)
    add_run(out, '29990101-000000')              # a run still going: its folder, no JSON yet
    add_run(out, '29990101-000000-2', '{"sensors": 5}')
    p = history('--output-dir', str(out), 'compare', '--json')
    assert p.returncode == 0, p.stderr
    assert (json.loads(p.stdout)['a'], json.loads(p.stdout)['b']) == (runs[0], runs[1])
    notes = [line for line in p.stderr.splitlines() if 'note: skipping run' in line]
    assert len(notes) == 2 and 'still going' in notes[0] and 'malformed' in notes[1], p.stderr
    one = history('--output-dir', str(out), 'compare', runs[0])   # A named, B: latest complete
    assert one.returncode == 0 and one.stdout.startswith('compare %s (A) -> %s (B)' % (runs[0], runs[1]))
    # only one complete run left: a clear usage error, not a traceback
    import shutil
    shutil.rmtree(str(out / 'runs' / runs[0]))
    few = history('--output-dir', str(out), 'compare')
    assert few.returncode == 2 and 'needs two runs' in few.stderr
    assert 'has 1 complete' in few.stderr and '2 incomplete' in few.stderr


# ------------------------------------------------------------------ the command line: options, open, failed, prune

def test_output_dir_before_or_after_the_command(two_runs):
    """Before: `sensorTestHistory list --output-dir DIR` was a usage error (exit 2)."""
    out, *_ = two_runs
    before = history('--output-dir', str(out), 'list')
    after = history('list', '--output-dir', str(out))
    assert after.returncode == 0, after.stderr
    assert after.stdout == before.stdout and '2 runs in %s' % (out / 'runs') in after.stdout
    for cmd in (['compare'], ['path'], ['open'], ['failed'], ['prune', '--keep', '5', '--dry-run']):
        p = history(*cmd, '--output-dir', str(out))
        assert p.returncode == 0 and p.stdout, (cmd, p.stdout, p.stderr)
        assert p.stdout == history('--output-dir', str(out), *cmd).stdout, cmd
    # both given: the one after the command wins; neither: sensorTest's default (not an error)
    p = history('--output-dir', '/nonexistent/x', 'path', '--output-dir', str(out))
    assert p.returncode == 0 and p.stdout.startswith(str(out))


@pytest.mark.parametrize('columns', [80, 120])
def test_compare_prints_verdict_changes_as_a_table_that_fits(two_runs, columns):
    """Before: one line "1 verdict change: laser PASS -> FAIL (no publisher on ...)" of any length."""
    out, *_ = two_runs
    p = history('--output-dir', str(out), 'compare', env={'COLUMNS': str(columns)})
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert max(len(line) for line in lines) <= columns, '\n'.join(x for x in lines if len(x) > columns)
    i = lines.index('1 verdict change:')
    assert lines[i + 1].split() == ['sensor', 'A', 'B', 'why']
    assert lines[i + 2].split()[:3] == ['laser', 'PASS', 'FAIL']
    col = lines[i + 1].index('why')
    reason_lines = [lines[i + 2][col:]]
    for line in lines[i + 3:]:
        if not line.startswith(' ' * col):
            break
        reason_lines.append(line[col:])
    reasons = load(out / 'sensorTestResults.json')['sensors'][1]['reasons']
    assert ' '.join(reason_lines) == '; '.join(reasons)          # the whole reason, in its column
    if columns == 80:
        assert len(reason_lines) > 1                          # wrapped inside the column


def test_open_prints_the_latest_report_and_never_blocks(two_runs, tmp_path):
    out, *_ = two_runs
    runs = sorted(os.listdir(out / 'runs'))
    report = str(out / 'runs' / runs[1] / 'sensorTestReport.html')
    p = history('--output-dir', str(out), 'open', env={'DISPLAY': ''})
    assert p.returncode == 0 and p.stdout == report + '\n', p.stderr
    assert history('--output-dir', str(out), 'open', runs[0]).stdout.startswith(str(out / 'runs' / runs[0]))
    # --browser without a display (CI): the path, a note, exit 0, nothing started
    env = {'DISPLAY': '', 'WAYLAND_DISPLAY': ''}
    p = history('--output-dir', str(out), 'open', '--browser', env=env)
    assert p.returncode == 0 and p.stdout == report + '\n' and 'no display' in p.stderr
    # with a display: xdg-open is started and not waited for (this one takes 60 s to return)
    bin_dir = tmp_path / 'bin'
    bin_dir.mkdir()
    log = tmp_path / 'opened.txt'
    (bin_dir / 'xdg-open').write_text('#!/bin/sh\necho "$$ $1" > %s\nexec sleep 60\n' % log)
    (bin_dir / 'xdg-open').chmod(0o755)
    t0 = time.monotonic()
    p = history('--output-dir', str(out), 'open', '--browser',
                env={'DISPLAY': ':99', 'PATH': '%s:%s' % (bin_dir, os.environ['PATH'])})
    took = time.monotonic() - t0
    assert p.returncode == 0 and p.stdout == report + '\n', p.stderr
    assert took < 10, took
    wait_until(lambda: log.exists() and log.read_text(), 10, 'the stand-in xdg-open never ran')
    pid, opened = log.read_text().split()
    os.kill(int(pid), signal.SIGTERM)                        # the stand-in browser this test made
    assert opened == report
    # a run without a report (--no-report, still going): skipped with a note, or named: exit 2
    mine, ids = copy_history(two_runs, tmp_path)
    add_run(mine, '29990101-000000', '{"sensors": []}')
    p = history('--output-dir', str(mine), 'open')
    assert p.returncode == 0 and p.stdout.startswith(str(mine / 'runs' / ids[1])), p.stderr
    assert 'skipping run 29990101-000000' in p.stderr and 'no sensorTestReport.html' in p.stderr
    named = history('--output-dir', str(mine), 'open', '29990101')
    assert named.returncode == 2 and 'has no sensorTestReport.html' in named.stderr


def test_failed_prints_the_options_that_rerun_what_failed(two_runs, module_master, tmp_path):
    out, *_ = two_runs
    runs = sorted(os.listdir(out / 'runs'))
    p = history('--output-dir', str(out), 'failed')
    assert p.returncode == 0 and p.stdout == '--sensors laser\n', p.stdout + p.stderr
    nothing = history('--output-dir', str(out), 'failed', runs[0])       # run 1: all passed
    assert nothing.returncode == 1 and nothing.stdout == '' and 'no sensor failed' in nothing.stderr
    # what it prints is what sensorTest takes: only the laser runs
    rerun_out = tmp_path / 'rerun'
    proc = sensor_test(module_master, p.stdout.split() + ['--duration', '1', '--wait', '1',
                                                          '--output-dir', str(rerun_out)])
    data = load(rerun_out / 'sensorTestResults.json')
    assert [s['name'] for s in data['sensors']] == ['laser'] and proc.returncode == 1
    # sensorTest --rerun-failed does the same from the output folder's latest JSON (here: the
    # laser's failed re-run above); the header says so
    again = sensor_test(module_master, ['--rerun-failed', '--duration', '1', '--wait', '1',
                                        '--output-dir', str(rerun_out)])
    assert again.returncode == 1, again.stdout + again.stderr
    assert [s['name'] for s in load(rerun_out / 'sensorTestResults.json')['sensors']] == ['laser']
    assert 'note: re-running what did not pass in run %s: laser' % data['run_id'] in again.stdout
    # every verdict that is not PASS or SKIPPED counts (e.g. an INTERRUPTED sensor), in run order
    mine, _ = copy_history(two_runs, tmp_path)
    add_run(mine, '29990101-000000', json.dumps({'platform': 'simulator', 'source': 'live', 'sensors': [
        {'name': 'imu', 'verdict': 'INTERRUPTED'}, {'name': 'laser', 'verdict': 'PASS'},
        {'name': 'odometry', 'verdict': 'FAIL'}, {'name': 'speech', 'verdict': 'SKIPPED'}]}))
    p = history('--output-dir', str(mine), 'failed')
    assert p.stdout == '--platform simulator --sensors imu,odometry\n', p.stdout + p.stderr


def test_prune_keeps_the_last_runs_and_says_why_it_keeps_the_published_one(two_runs, tmp_path):
    import shutil
    out, *_ = two_runs
    mine, ids = copy_history(two_runs, tmp_path)
    shutil.copy(str(out / '.sensorTestLatest.json'), str(mine))       # the output folder holds run 2
    for old in ('20200101-000000', '20200102-000000'):                   # two old runs (real copies)
        shutil.copytree(str(mine / 'runs' / ids[0]), str(mine / 'runs' / old))
    add_run(mine, '29990101-000000', '{"sensors": []}')                   # newer than the published run
    before = sorted(os.listdir(mine / 'runs'))
    dry = history('--output-dir', str(mine), 'prune', '--keep', '1', '--dry-run', env={'COLUMNS': '80'})
    assert dry.returncode == 0, dry.stderr
    assert sorted(os.listdir(mine / 'runs')) == before                  # a dry run deletes nothing
    assert 'would delete 3 runs' in dry.stdout and 'dry run: nothing deleted' in dry.stdout
    assert max(len(line) for line in dry.stdout.splitlines()[:-1]) <= 80
    p = history('--output-dir', str(mine), 'prune', '--keep', '1')
    assert p.returncode == 0, p.stderr
    # kept: the newest run and the run the latest files point at, with a line saying so
    assert sorted(os.listdir(mine / 'runs')) == [ids[1], '29990101-000000']
    keep = ' '.join(line for line in p.stdout.splitlines() if ids[1] in line or line.startswith(' '))
    assert 'keep' in keep and "latest files" in keep and "this run's" in keep, p.stdout
    assert 'deleted 3 runs' in p.stdout and all(r in p.stdout for r in ('20200101-000000', ids[0]))
    # --days: the 2999 run is "newer"; nothing else left to delete but the published run
    p = history('--output-dir', str(mine), 'prune', '--days', '30')
    assert p.returncode == 0 and sorted(os.listdir(mine / 'runs')) == [ids[1], '29990101-000000']
    # usage errors: no rule, a negative count
    assert history('--output-dir', str(mine), 'prune').returncode == 2
    bad = history('--output-dir', str(mine), 'prune', '--keep', '-1')
    assert bad.returncode == 2 and 'whole number' in bad.stderr


def test_prune_keeps_a_run_that_may_still_be_going(two_runs, tmp_path):
    mine, ids = copy_history(two_runs, tmp_path)
    going = add_run(mine, '20200101-000000')                 # old id, no JSON, files just written
    (going / 'sensorTestOutput.dat').write_text('[START TIME]\n')
    odd = mine / 'runs' / 'my-notes'
    odd.mkdir()
    p = history('--output-dir', str(mine), 'prune', '--keep', '0')
    assert p.returncode == 0, p.stderr
    assert sorted(os.listdir(mine / 'runs')) == ['20200101-000000', 'my-notes']
    assert 'may still be going' in p.stdout and 'not a run id' in p.stdout
