"""Run the real emulator and the real sensorTest on it: the JSON's sensors by name."""
import json
import os
import subprocess
import time

from rosmaster import kill_group, script, spawn, wait_until

PKG = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def run(master, tmp_path, emu_params, sensors, platform='robot', duration=3, tag='run'):
    """Start the emulator, wait until it is up, run sensorTest on `sensors`; the JSON's
    sensors by name (and the sensorTest process)."""
    name = 'pepperEmulator_%d' % time.time_ns()
    log_path = tmp_path / (tag + '-emulator.log')
    with open(str(log_path), 'w') as log:
        emu = spawn(script('pepperEmulator') + ['__name:=' + name] + list(emu_params), master.env(),
                    stdout=log, stderr=subprocess.STDOUT)
        try:
            wait_until(lambda: 'publishers up' in log_path.read_text(), 30, log_path.read_text)
            out = tmp_path / (tag + '-out')
            topics = os.path.join(PKG, 'data', 'pepperTopics.dat' if platform == 'robot'
                                  else 'simulatorTopics.dat')
            cmd = script('sensorTest') + [
                '--topics', topics, '--sensors', ','.join(sensors), '--platform', platform,
                '--mode', 'parallel', '--duration', str(duration), '--wait', '8',
                '--output-dir', str(out), '--no-show', '--no-history', '--no-report',
                '--no-diagnostics', '--no-record']
            done = subprocess.run(cmd, env=master.env(), capture_output=True, text=True, timeout=120)
        finally:
            kill_group(emu)
    path = out / 'sensorTestResults.json'
    assert path.exists(), done.stdout + done.stderr
    return {s['name']: s for s in json.loads(path.read_text())['sensors']}, done
