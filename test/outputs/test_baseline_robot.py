"""A baseline is this robot's: the real emulator publishes naoqi_driver's latched info topic with
its serial number (~robot_id, emulator/info.py), the real sensorTest reads it (sources/identity.py)
and records it; two runs of one robot compare, a run of another robot refuses the first robot's
baseline with both serial numbers, and a robot whose driver sends no info topic is compared
without that check (its identity unknown, said once in the header)."""
import json
import os
import subprocess
import time

import pytest

from rosmaster import kill_group, script, spawn, wait_until

PKG = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SENSORS = ['imu', 'jointState']
A, B = 'AP990370B0000000', 'AP990370B0000001'


class Emulator:
    def __init__(self, master, tmp_path, robot_id):
        self.log_path = tmp_path / ('emulator-%d.log' % time.time_ns())
        self.log = open(str(self.log_path), 'w')
        params = ['_profile:=robot', '_condition:=still', '_camera_resolution:=QQVGA', '_audio:=off',
                  '_robot_id:=' + robot_id]
        self.proc = spawn(script('pepperEmulator') + ['__name:=emu_%d' % time.time_ns()] + params,
                          master.env(), stdout=self.log, stderr=subprocess.STDOUT)
        wait_until(lambda: 'publishers up' in self.log_path.read_text(), 30, self.log_path.read_text)

    def stop(self):
        kill_group(self.proc)
        self.log.close()


def sensor_test(master, out, *extra):
    cmd = script('sensorTest') + [
        '--topics', os.path.join(PKG, 'data', 'pepperTopics.dat'), '--sensors', ','.join(SENSORS),
        '--platform', 'robot', '--mode', 'parallel', '--duration', '2', '--wait', '8',
        '--output-dir', str(out), '--no-show', '--no-report', '--no-diagnostics', '--no-record'] + list(extra)
    env = dict(master.env(), COLUMNS='80')
    done = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=120)
    data = json.loads((out / 'sensorTestResults.json').read_text()) if done.returncode in (0, 1) else None
    return done, data


def first_run(out):
    runs = sorted(os.listdir(str(out / 'runs')))
    return str(out / 'runs' / runs[0])


@pytest.fixture(scope='module')
def runs(module_master, tmp_path_factory):
    tmp = tmp_path_factory.mktemp('robot-id')
    out = tmp / 'out'
    got = {}
    emu = Emulator(module_master, tmp, A)
    try:
        got['a1'] = sensor_test(module_master, out)
        pin = script('sensorTestHistory') + ['--output-dir', str(out), 'baseline', 'set', 'latest']
        got['pin'] = subprocess.run(pin, capture_output=True, text=True, timeout=60)
        got['a2'] = sensor_test(module_master, out)
    finally:
        emu.stop()
    emu = Emulator(module_master, tmp, B)
    try:
        got['b_pinned'] = sensor_test(module_master, out)
        got['b_named'] = sensor_test(module_master, out, '--baseline', first_run(out))
    finally:
        emu.stop()
    emu = Emulator(module_master, tmp, 'none')
    try:
        got['unnamed'] = sensor_test(module_master, out)
    finally:
        emu.stop()
    return got


def test_a_run_names_its_robot_in_the_json_the_header_and_the_dat(runs):
    done, data = runs['a1']
    assert done.returncode == 0, done.stdout + done.stderr
    assert data['robot'] == A
    assert data['robot_info'] == {'body_id': A, 'topic': '/naoqi_driver/info', 'head_id': 'AP990495A0000000',
                                  'body_type': 'juliette', 'base_version': '1.8a'}
    assert done.stdout.count('robot %s (juliette, base 1.8a, head AP990495A0000000)' % A) == 1
    dat = open(os.path.join(data['output_dir'], 'sensorTestOutput.dat')).read()
    assert '[RUN] robot %s (juliette, base 1.8a, head AP990495A0000000)\n' % A in dat


def test_two_runs_of_one_robot_compare(runs):
    assert runs['pin'].returncode == 0, runs['pin'].stderr
    done, data = runs['a2']
    assert done.returncode == 0, done.stdout + done.stderr
    assert data['robot'] == A and data['baseline'] and data['baseline']['pinned'] is True
    assert 'comparing with the baseline run' in done.stdout and 'not used' not in done.stdout


def test_another_robots_pinned_baseline_is_not_used_and_says_why(runs):
    done, data = runs['b_pinned']
    assert done.returncode == 0, done.stdout + done.stderr
    assert data['robot'] == B and data['baseline'] is None
    text = ' '.join(done.stdout.split())
    assert ('baseline from robot %s, this run is robot %s: pin a baseline of this robot' % (A, B)) in text
    assert 'comparing with the baseline' not in text


def test_another_robots_baseline_named_with_dash_dash_baseline_is_refused(runs):
    done, data = runs['b_named']
    err = ' '.join(done.stderr.split())
    assert done.returncode == 2 and data is None, done.stdout + done.stderr
    assert 'baseline from robot %s, this run is robot %s: pin a baseline of this robot' % (A, B) in err
    assert 'Traceback' not in done.stderr


def test_a_robot_that_does_not_say_who_it_is_is_compared_without_that_check(runs):
    done, data = runs['unnamed']
    assert done.returncode == 0, done.stdout + done.stderr
    assert data['robot'] is None and 'no driver publishes' in data['robot_info']['unknown']
    text = ' '.join(done.stdout.split())
    assert text.count('robot identity unknown') == 1
    assert data['baseline'] and 'comparing with the baseline run' in text
