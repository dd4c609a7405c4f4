"""Drift end to end: the real emulator publishes, the real sensorTest listens (3 s windows) and
keeps its runs; `sensorTestHistory baseline set` pins a healthy run; a second healthy run shows
no drift; a run with the emulator's wear faults (each small enough that the absolute rules still
PASS) has a WARN on each worn sensor naming the value then and now; --baseline refuses a run
that failed; --no-baseline compares with none."""
import json
import os
import subprocess
import time

import pytest

from rosmaster import kill_group, script, spawn, wait_until

PKG = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SENSORS = ['frontCamera', 'bottomCamera', 'laser', 'imu', 'microphone', 'backSonar', 'frontSonar',
           'jointState', 'robotHealth']
WEAR = ('frontCamera:blur;bottomCamera:dim=0.6;laser:scratched=front;imu:gyro_bias=0.02;'
        'microphone:quiet_channel=rearLeft;backSonar:noisy;frontSonar:rate=0.5;jointState:noisy;'
        'robotHealth:hot_joint=55')
# what each fault drifts (the measure's key in outputs/drift.py)
EXPECTED = {'frontCamera': 'sharpness', 'bottomCamera': 'brightness', 'laser': 'valid_share:front',
            'imu': 'gyro_bias', 'microphone': 'level:rearLeft', 'backSonar': 'range_noise',
            'frontSonar': 'rate', 'jointState': 'joint_noise:', 'robotHealth': 'temperature:HipPitch'}
# the degraded conditions, each against a baseline of the same condition (loaded: ~1.3 fps cameras)
CONDITIONS = {'dark': (['frontCamera', 'depthCamera', 'laser', 'imu', 'backSonar', 'jointState'], 3),
              'loaded': (['frontCamera', 'depthCamera', 'imu', 'jointState'], 6)}


class Emulator:
    def __init__(self, master, tmp_path, faults='', condition='still'):
        self.log_path = tmp_path / ('emulator-%d.log' % time.time_ns())
        self.log = open(str(self.log_path), 'w')
        params = ['_profile:=robot', '_condition:=' + condition, '_camera_resolution:=QQVGA',
                  '_audio:=direct']
        if faults:
            params.append('_faults:=' + faults)
        self.proc = spawn(script('pepperEmulator') + ['__name:=emu_%d' % time.time_ns()] + params,
                          master.env(), stdout=self.log, stderr=subprocess.STDOUT)
        wait_until(lambda: 'publishers up' in self.log_path.read_text(), 30, self.log_path.read_text)

    def stop(self):
        kill_group(self.proc)
        self.log.close()


def sensor_test(master, out, *extra, sensors=SENSORS, duration=3):
    cmd = script('sensorTest') + [
        '--topics', os.path.join(PKG, 'data', 'pepperTopics.dat'), '--sensors', ','.join(sensors),
        '--platform', 'robot', '--mode', 'parallel', '--duration', str(duration), '--wait', '8',
        '--output-dir', str(out), '--no-show', '--no-report', '--no-diagnostics', '--no-record'] + list(extra)
    done = subprocess.run(cmd, env=master.env(), capture_output=True, text=True, timeout=120)
    data = json.loads((out / 'sensorTestResults.json').read_text()) if done.returncode in (0, 1) else None
    return done, data


def history(out, *args):
    return subprocess.run(script('sensorTestHistory') + ['--output-dir', str(out)] + list(args),
                          capture_output=True, text=True, timeout=60)


@pytest.fixture(scope='module')
def runs(module_master, tmp_path_factory):
    tmp = tmp_path_factory.mktemp('drift')
    out = tmp / 'out'
    emu = Emulator(module_master, tmp)
    try:
        first, base = sensor_test(module_master, out)
        pinned = history(out, 'baseline', 'set', 'latest')
        second, healthy = sensor_test(module_master, out)
    finally:
        emu.stop()
    emu = Emulator(module_master, tmp, WEAR)
    try:
        third, worn = sensor_test(module_master, out)
        fourth, none = sensor_test(module_master, out, '--no-baseline')
    finally:
        emu.stop()
    return dict(out=out, first=first, base=base, pinned=pinned, second=second, healthy=healthy,
                third=third, worn=worn, fourth=fourth, none=none)


def by_name(data):
    return {s['name']: s for s in data['sensors']}


def test_a_healthy_run_against_a_healthy_baseline_shows_no_drift(runs):
    assert runs['pinned'].returncode == 0, runs['pinned'].stderr
    assert runs['base'] is not None and runs['base']['baseline'] is None, runs['first'].stderr
    data = runs['healthy']
    assert data['baseline']['run_id'] == runs['base']['run_id'] and data['baseline']['pinned'] is True
    for s in data['sensors']:
        assert s['verdict'] == 'PASS' and s['drift'] == [], (s['name'], s['drift'], s['reasons'])
    assert 'no drift since the baseline run' in runs['second'].stdout


def test_each_worn_sensor_passes_with_a_drift_warning_naming_then_and_now(runs):
    data = runs['worn']
    assert data is not None, runs['third'].stderr
    s = by_name(data)
    for name, measure in EXPECTED.items():
        assert s[name]['verdict'] == 'PASS', (name, s[name]['reasons'])
        hits = [d for d in s[name]['drift'] if d['measure'].startswith(measure)]
        assert hits, (name, s[name]['drift'])
        assert ', was ' in hits[0]['text'] and hits[0]['text'] in s[name]['warnings']
    mic = [d for d in s['microphone']['drift'] if d['measure'] == 'level:rearLeft'][0]
    assert 'dB quieter' in mic['change'] and 'grille' in mic['text']
    assert 'drift since the baseline run' in runs['third'].stdout
    # the .dat carries them as warnings
    dat = (runs['out'] / 'runs' / data['run_id'] / 'sensorTestOutput.dat').read_text()
    assert '[WARNING] rearLeft level' in dat


def test_no_baseline_compares_with_none_and_a_failed_run_is_refused(runs, module_master):
    assert runs['none']['baseline'] is None
    assert all(s['drift'] == [] for s in runs['none']['sensors'])
    # a failed run as --baseline: refused before anything is written (exit 2, the reason)
    out = runs['out']
    folder = out / 'runs' / runs['none']['run_id']
    data = json.loads((folder / 'sensorTestResults.json').read_text())
    data['sensors'][0]['verdict'] = 'FAIL'
    (folder / 'sensorTestResults.json').write_text(json.dumps(data))
    before = sorted(os.listdir(out / 'runs'))
    done, _ = sensor_test(module_master, out, '--baseline', str(folder))
    assert done.returncode == 2 and 'cannot be the baseline' in done.stderr and 'failed in it' in done.stderr
    assert sorted(os.listdir(out / 'runs')) == before


@pytest.mark.parametrize('condition', sorted(CONDITIONS))
def test_a_degraded_condition_against_a_baseline_of_the_same_condition_shows_no_drift(
        module_master, tmp_path, condition):
    sensors, duration = CONDITIONS[condition]
    out = tmp_path / 'out'
    emu = Emulator(module_master, tmp_path, condition=condition)
    try:
        first, base = sensor_test(module_master, out, sensors=sensors, duration=duration)
        second, data = sensor_test(module_master, out, '--baseline', base['run_id'] if base else 'latest',
                                   sensors=sensors, duration=duration)
    finally:
        emu.stop()
    assert data is not None and data['baseline']['pinned'] is False, second.stderr
    for s in data['sensors']:
        assert s['verdict'] == 'PASS' and s['drift'] == [], (s['name'], s['drift'], s['reasons'])


def test_a_baseline_that_cannot_serve_is_refused_before_any_master_is_sought(tmp_path):
    folder = tmp_path / 'out' / 'runs' / '20261120-101500'
    folder.mkdir(parents=True)
    (folder / 'sensorTestResults.json').write_text(json.dumps(
        {'schema_version': 1, 'run_id': '20261120-101500', 'platform': 'robot', 'interrupted': True,
         'interrupt_reason': 'SIGTERM', 'sensors': [{'name': 'laser', 'verdict': 'PASS'}]}))
    env = dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:9')     # nothing listens there
    for ref, why in (('20261120', 'it was interrupted (SIGTERM)'), ('2025', 'unknown run id "2025"')):
        done = subprocess.run(script('sensorTest') + ['--output-dir', str(tmp_path / 'out'), '--baseline', ref,
                                                      '--sensors', 'laser'],
                              env=env, capture_output=True, text=True, timeout=60)
        assert done.returncode == 2 and why in done.stderr and 'no ROS master' not in done.stderr, done.stderr
        assert '--no-baseline' in done.stderr
    assert os.listdir(tmp_path / 'out' / 'runs') == ['20261120-101500']
