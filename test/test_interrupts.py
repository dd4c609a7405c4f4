"""Interrupted runs lose nothing: real signals sent to a real sensorTest process at controlled
moments (a marker line it prints, or the documented test hook SENSORTEST_TEST_PAUSE that makes it
pause at a named point, see src/pepper_interface_tests/interrupts.py), real rospy publishers on
a real roscore, real pipes. Every test checks the three result files and the exit code.
"""
import os
import signal
import subprocess
import sys
import time

import pytest

from rosmaster import NODES, kill_group, script, spawn, wait_until
from sensor_test_runs import (
    Result,
    Running,
    assert_outputs_complete,
    sonar_and_laser_fixture,
)

HERE = NODES   # the node scripts' folder (test/nodes/)
PREFIX = '/sig'
NAMES = ['backSonar', 'laser']


pubs = sonar_and_laser_fixture(PREFIX, ['frontSonar'])


def start(master, pubs, out, *args, pause=None, sensors=NAMES, duration=30):
    env = master.env()
    if pause:
        env['SENSORTEST_TEST_PAUSE'] = pause
    return Running(['--topics', pubs.topics, '--sensors', ','.join(sensors), '--mode', 'sequential',
                    '--duration', str(duration), '--wait', '3', '--no-report', '--output-dir', str(out)]
                   + list(args), env, out)


def wait_err(run, text, timeout=30):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if any(text in line for line in list(run.err)):
            return
        if run.proc.poll() is not None:
            break
        time.sleep(0.02)
    raise AssertionError('sensorTest never printed %r on stderr:\n%s' % (text, ''.join(run.err)))


def last_run(dat):
    return dat.split('[TESTING] ############ SENSORS ############')[-1]


# ------------------------------------------------------------------ a second Ctrl-C

def test_second_ctrl_c_within_50_ms_never_cuts_the_final_write(module_master, pubs, tmp_path):
    out = tmp_path / 'out'
    run = start(module_master, pubs, out)
    run.wait_for('start  backSonar')
    time.sleep(1.5)    # 1.5 s into the window: Ctrl-C mid-listening
    run.proc.send_signal(signal.SIGINT)
    time.sleep(0.03)    # the second Ctrl-C within 50 ms (under test)
    run.proc.send_signal(signal.SIGINT)
    r = run.finish(30)
    assert r.rc == 130, r
    assert_outputs_complete(r, NAMES)
    last = last_run(r.dat)
    assert '[INTERRUPTED] interrupted by Ctrl-C' in last and '[END TIME] ' in last
    assert r.json['exit_code'] == 130 and r.json['interrupted'] is True
    assert 'before listening began' not in r.stderr


def test_third_interrupt_quits_at_once(module_master, pubs, tmp_path):
    """The final write paused (test hook) for 20 s: the second interrupt waits, the third quits."""
    out = tmp_path / 'out'
    run = start(module_master, pubs, out, pause='final-write:20')
    run.wait_for('start  backSonar')
    time.sleep(1.0)    # mid-window
    run.proc.send_signal(signal.SIGINT)
    wait_err(run, '[test-pause] final-write')
    run.proc.send_signal(signal.SIGINT)
    time.sleep(0.5)    # the second interrupt had its chance to cut the write
    assert run.proc.poll() is None          # the second one did not cut the write short
    sent = time.monotonic()
    run.proc.send_signal(signal.SIGINT)
    r = run.finish(30)
    assert r.rc == 130, r
    assert time.monotonic() - sent < 3
    assert 'third interrupt' in r.stderr


# ------------------------------------------------------------------ SIGHUP

def test_sighup_is_treated_like_sigterm_and_finishes_recordings(module_master, tmp_path):
    topic = '/sig/camera/front/image_raw'
    env = module_master.env()
    cam = spawn([sys.executable, os.path.join(HERE, 'media_publisher.py'), 'camera', topic,
                 '--rate', '10', '--width', '160', '--height', '120'], env,
                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        topics = str(tmp_path / 't.dat')
        with open(topics, 'w') as f:
            f.write('frontCamera %s\n' % topic)
        out = tmp_path / 'out'
        run = Running(['--topics', topics, '--sensors', 'frontCamera', '--duration', '30', '--wait', '10',
                       '--no-report', '--no-show', '--no-history', '--output-dir', str(out)], env, out)
        run.wait_for('start  frontCamera')
        wait_until(lambda: any(n.endswith('.writing.mp4') for n in os.listdir(str(out))), 20,
                   lambda: 'no video being written: %s' % os.listdir(str(out)))
        time.sleep(1.5)     # 1.5 s of video in the file when the signal comes
        run.proc.send_signal(signal.SIGHUP)
        r = run.finish(30)
    finally:
        kill_group(cam)
    assert r.rc == 130, r
    assert_outputs_complete(r, ['frontCamera'])
    assert 'SIGHUP' in r.json['interrupt_reason']
    names = os.listdir(str(out))
    assert not [n for n in names if '.writing.' in n], names
    video = out / 'frontCameraOutput.mp4'
    assert video.is_file() and video.stat().st_size > 1000
    cam_result = r.sensors['frontCamera']
    assert cam_result['verdict'] == 'INTERRUPTED' and cam_result['messages'] >= 5


# ------------------------------------------------------------------ start-up

def test_sigterm_while_a_sensor_starts_keeps_it_in_every_output(module_master, pubs, tmp_path):
    out = tmp_path / 'out'
    run = start(module_master, pubs, out, pause='sensor-start:5')
    wait_err(run, '[test-pause] sensor-start')
    sent = time.monotonic()
    run.proc.send_signal(signal.SIGTERM)
    r = run.finish(30)
    assert r.rc == 130, r
    assert time.monotonic() - sent < 3
    assert_outputs_complete(r, NAMES)
    assert '[INTERRUPTED] terminated (SIGTERM)' in last_run(r.dat)


def test_sigterm_before_the_files_exist_still_writes_every_sensor(module_master, pubs, tmp_path):
    out = tmp_path / 'out'
    run = start(module_master, pubs, out, pause='run-folder:3')
    wait_err(run, '[test-pause] run-folder')
    run.proc.send_signal(signal.SIGTERM)
    r = run.finish(30)
    assert r.rc == 130, r
    assert_outputs_complete(r, NAMES)
    assert all(s['reasons'] == ['not run: the run was interrupted before it started']
               for s in r.sensors.values()), r.json


@pytest.mark.parametrize('point', ['sensor-start', 'start-up'])
def test_ctrl_c_swallowed_by_a_library_still_ends_the_run(module_master, pubs, tmp_path, point):
    """`:swallow` makes the pause swallow the KeyboardInterrupt, as a C extension's import that
    clears Python errors does (seen inside the cv_bridge import)."""
    out = tmp_path / 'out'
    run = start(module_master, pubs, out, pause='%s:1.5:swallow' % point, duration=8)
    wait_err(run, '[test-pause] ' + point)
    sent = time.monotonic()
    run.proc.send_signal(signal.SIGINT)
    r = run.finish(30)
    assert r.rc == 130, r
    assert time.monotonic() - sent < 1.5 + 2.0, 'took %.1f s' % (time.monotonic() - sent)
    if point == 'sensor-start':
        assert_outputs_complete(r, NAMES)


# ------------------------------------------------------------------ Ctrl-C during the final write

def test_ctrl_c_during_the_final_write_exit_code_json_and_terminal_agree(module_master, pubs, tmp_path):
    out = tmp_path / 'out'
    run = start(module_master, pubs, out, pause='final-write:2', duration=2)
    wait_err(run, '[test-pause] final-write')
    run.proc.send_signal(signal.SIGINT)
    r = run.finish(30)
    assert_outputs_complete(r, NAMES)        # also: the JSON's exit_code is the exit code
    assert r.rc == 0, r
    assert '2 passed, 0 failed, 0 skipped' in r.stdout and 'INTERRUPTED' not in r.stdout, r.stdout
    assert 'exit code 0 as in sensorTestResults.json' in r.stderr


# ------------------------------------------------------------------ what an interrupted sensor says

def test_a_window_cut_short_is_interrupted_not_failed(module_master, pubs, tmp_path):
    """backSonar listens, frontSonar has no publisher at all: after 1 s neither is judged."""
    out = tmp_path / 'out'
    run = start(module_master, pubs, out, '--mode', 'parallel', sensors=['backSonar', 'frontSonar'])
    run.wait_for('start  frontSonar')
    time.sleep(1.0)    # 1 s into both windows
    run.proc.send_signal(signal.SIGINT)
    r = run.finish(30)
    assert r.rc == 130, r
    assert_outputs_complete(r, ['backSonar', 'frontSonar'])
    for name in ('backSonar', 'frontSonar'):
        s = r.sensors[name]
        assert s['verdict'] == 'INTERRUPTED', s
        assert s['reasons'][0].startswith('interrupted after ')
        assert not any('no message within' in x or 'publishes it' in x for x in s['reasons'])
    assert r.sensors['backSonar']['messages'] >= 3
    assert r.json['summary']['INTERRUPTED'] == 2 and r.json['summary']['FAIL'] == 0
    suite = r.junit
    assert suite.get('failures') == '0' and suite.get('skipped') == '2'
    for case in suite.findall('testcase'):
        assert case.find('failure') is None and case.find('skipped') is not None
    assert '[RESULT] INTERRUPTED: interrupted after ' in r.block('BACK SONAR')


# ------------------------------------------------------------------ broken stdout / stderr

@pytest.mark.parametrize('then', ['ctrl_c', 'run_to_the_end'])
def test_a_broken_pipe_never_stops_the_results(module_master, pubs, tmp_path, then):
    """`sensorTest | tee log` killed by the same Ctrl-C, or `| head` that exited: stdout and
    stderr are pipes whose reader is gone."""
    out = tmp_path / 'out'
    args = ['--topics', pubs.topics, '--sensors', ','.join(NAMES), '--mode', 'sequential',
            '--duration', '30' if then == 'ctrl_c' else '2', '--wait', '3', '--output-dir', str(out)]
    t0 = time.monotonic()
    proc = spawn(script('sensorTest') + args, module_master.env(), stdout=subprocess.PIPE,
                 stderr=subprocess.PIPE)
    seen = b''
    while b'start  backSonar' not in seen:
        chunk = proc.stdout.readline()
        assert chunk, 'sensorTest ended early: %r' % seen
        seen += chunk
    proc.stdout.close()           # the reader exits
    proc.stderr.close()
    if then == 'ctrl_c':
        time.sleep(1.0)    # a moment into the window
        proc.send_signal(signal.SIGINT)
    try:
        proc.wait(60)
    except subprocess.TimeoutExpired:
        kill_group(proc, signal.SIGKILL)
        raise
    r = Result(proc, out, '', '', time.monotonic() - t0)
    assert r.rc == (130 if then == 'ctrl_c' else 0)
    assert_outputs_complete(r, NAMES)
    assert '[END TIME] ' in last_run(r.dat)
