"""The demo on a busy PC and over a bursty WiFi (issue 41), as `make demo` runs it
(tools/demo.sh): beside one CPU-bound process per core every row PASSes; beside three per core
no sensor FAILs (a row the PC was too busy to judge says so, naming the load and sensorTest's
own lag); on the emulator's WiFi (network:=wifi) every row PASSes; and a faulty robot still
FAILs there, busy PC and WiFi together.

Real parts: the demo script, roslaunch, the emulator, libqi, websockets; real processes that
keep the cores busy (`python3 -c 'while True: pass'`)."""
import json
import os
import subprocess
import sys

import pytest

from rosmaster import ROOT

pytestmark = pytest.mark.slow
CORES = os.cpu_count() or 1
BUSY = [sys.executable, '-c', 'while True: pass']


def demo(tmp_path, per_core, network='none', faults='none'):
    """tools/demo.sh beside `per_core` busy processes per core: (exit code, rows by name, output)."""
    env = dict(os.environ, ROS_HOME=str(tmp_path / 'ros'), COLUMNS='100', DEMO_NETWORK=network,
               DEMO_FAULTS=faults)
    env.pop('ROS_MASTER_URI', None)
    out_dir = tmp_path / 'out'
    busy = [subprocess.Popen(BUSY) for _ in range(per_core * CORES)]
    try:
        res = subprocess.run([os.path.join(ROOT, 'tools', 'demo.sh'), '--output-dir', str(out_dir)],
                             env=env, stdin=subprocess.DEVNULL, capture_output=True, text=True,
                             timeout=600, start_new_session=True)
    finally:
        for p in busy:
            p.kill()
            p.wait()
    said = res.stdout + res.stderr
    results = json.loads((out_dir / 'sensorTestResults.json').read_text())
    return res.returncode, {s['name']: s for s in results['sensors']}, said


def verdicts(rows, but=('PASS',)):
    return {n: (s['verdict'], s['reasons']) for n, s in rows.items() if s['verdict'] not in but}


def test_beside_one_busy_process_per_core_every_row_passes(tmp_path):
    rc, rows, said = demo(tmp_path, 1)
    assert len(rows) == 20 and verdicts(rows) == {} and rc == 0, said


def test_beside_three_busy_processes_per_core_no_sensor_fails(tmp_path):
    rc, rows, said = demo(tmp_path, 3)
    assert len(rows) == 20 and verdicts(rows, but=('PASS', 'NOT JUDGED', 'SKIPPED')) == {}, said
    # the motion check may skip its base part when no laser or sonar reading reached it in time
    # (seen once in four runs beside six busy loops): no sensor is faulted for it
    assert all(n == 'motion' for n, (v, _) in verdicts(rows).items() if v == 'SKIPPED'), said
    unjudged = {n: v for n, v in verdicts(rows).items() if v[0] == 'NOT JUDGED'}
    for name, (_, reasons) in unjudged.items():    # the PC named, with its load and the lag
        assert reasons and all(r.startswith('PC busy: ') and 'load average' in r for r in reasons), (name, reasons)
    assert rc == (4 if unjudged else 0), said
    if unjudged:
        assert 'could not judge everything' in said, said


def test_on_a_bursty_wifi_beside_a_busy_process_per_core_every_row_passes(tmp_path):
    rc, rows, said = demo(tmp_path, 1, network='wifi')
    assert len(rows) == 20 and verdicts(rows) == {} and rc == 0, said


def test_a_faulty_robot_still_fails_on_a_busy_pc_over_wifi(tmp_path):
    rc, rows, said = demo(tmp_path, 3, network='wifi', faults='frontCamera:frozen;laser:nan')
    assert rows['frontCamera']['verdict'] == 'FAIL' and rows['laser']['verdict'] == 'FAIL', said
    assert rc == 1, said
