"""Live /diagnostics (diagnostics.py), seen by a real rospy subscriber in its own process while
sensorTest runs against test/nodes/core_publisher.py publishers on a real master."""
import json
import select
import statistics
import subprocess
import sys
import time

from report_helpers import HERE, sensor_test, start_publishers, stop
from rosmaster import kill_group, spawn

LISTENER = HERE + '/report_diag_listener.py'   # HERE: test/nodes/
OK, WARN, ERROR, STALE = 0, 1, 2, 3
TOPICS = {'backSonar': '/naoqi_driver/sonar/back', 'frontSonar': '/naoqi_driver/sonar/front',
          'laser': '/naoqi_driver/laser'}


def listen(master):
    p = spawn([sys.executable, LISTENER], master.env(), stdout=subprocess.PIPE,
              stderr=subprocess.DEVNULL, text=True)
    assert p.stdout.readline().strip() == 'listening'
    return p


def arrays_of(listener, until=None, timeout=10.0):
    """The arrays the listener printed; with `until`, first read them as they come until one
    satisfies `until(array)` (or `timeout` s pass), then stop the listener."""
    lines = []
    deadline = time.monotonic() + timeout
    while until is not None and time.monotonic() < deadline:
        ready, _, _ = select.select([listener.stdout], [], [], max(0.0, deadline - time.monotonic()))
        line = listener.stdout.readline() if ready else ''
        if not line:
            break
        lines.append(line)
        if line.startswith('{') and until(json.loads(line)):
            break
    kill_group(listener)
    lines += listener.stdout.read().splitlines()
    listener.stdout.close()
    return [json.loads(line) for line in lines if line.startswith('{')]


def all_final(array):
    """Whether every status of `array` is a final one (it carries the verdict)."""
    return all('verdict' in s['values'] for s in array['status'])


def statuses(arrays, sensor):
    name = 'sensorTest: ' + sensor
    return [s for a in arrays for s in a['status'] if s['name'] == name]


def test_statuses_follow_the_run(module_master, tmp_path):
    pubs = start_publishers(module_master, [
        ('range', TOPICS['backSonar']),
        ('range', TOPICS['frontSonar'], '--fault', 'nan')])    # fails: NaN ranges
    listener = listen(module_master)
    try:
        proc = sensor_test(module_master, ['--sensors', 'backSonar,frontSonar,laser',   # laser: no publisher
                                           '--mode', 'sequential', '--duration', '3', '--wait', '2',
                                           '--no-history', '--no-report', '--output-dir', str(tmp_path)])
    finally:
        stop(pubs)
        arrays = arrays_of(listener, until=all_final)
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert len(arrays) >= 6, arrays
    # one status per sensor in every array, named the diagnostic_updater way, hardware_id = topic
    for a in arrays:
        assert [s['name'] for s in a['status']] == ['sensorTest: backSonar', 'sensorTest: frontSonar',
                                                    'sensorTest: laser']
        for s in a['status']:
            assert s['hardware_id'] == TOPICS[s['name'].split(': ')[1]]
    # about 1 Hz while the run goes on (8 s of windows): the period, not a count in a window
    # whose length a loaded machine stretches (the last array comes when the run ends)
    gaps = [b['t'] - a['t'] for a, b in zip(arrays, arrays[1:-1])]
    assert 0.8 <= statistics.median(gaps) <= 1.3, gaps
    assert statistics.mean(gaps) >= 0.8, gaps          # no burst of arrays in between

    back = statuses(arrays, 'backSonar')
    listening = [s for s in back if s['message'].startswith('listening')]
    assert listening and all(s['level'] == OK for s in listening), back
    # the rate so far (10 Hz published), inside the band the status itself says it is judged by
    assert any(int(s['values']['messages']) > 5 and 4 <= float(s['values']['rate (Hz)']) <= 16
               for s in listening), listening
    assert listening[0]['values']['expected rate (Hz)'] == '4-16'

    front = statuses(arrays, 'frontSonar')
    assert front[0]['level'] == STALE and front[0]['message'] == 'waiting to start'
    warned = [s for s in front if s['level'] == WARN]
    assert warned and 'so far: ' in warned[0]['message'] and 'range is NaN' in warned[0]['message'], front

    laser = statuses(arrays, 'laser')
    waiting = [s for s in laser if s['message'].startswith('waiting for the first message')]
    assert waiting and all(s['level'] == STALE for s in waiting), laser

    final = {s['name'].split(': ')[1]: s for s in arrays[-1]['status']}
    assert final['backSonar']['level'] == OK and final['backSonar']['message'].startswith('PASS')
    assert final['backSonar']['values']['verdict'] == 'PASS'
    assert final['frontSonar']['level'] == ERROR and final['frontSonar']['message'].startswith('FAIL: ')
    assert 'range is NaN' in final['frontSonar']['values']['reasons']
    assert final['laser']['level'] == ERROR and 'no publisher' in final['laser']['message']
    # the statuses reach the subscriber while the run goes on, not only at the end
    assert sum(1 for a in arrays if any(s['message'].startswith('listening') for s in a['status'])) >= 3


def test_no_diagnostics_option_publishes_nothing(module_master, tmp_path):
    pubs = start_publishers(module_master, [('range', TOPICS['backSonar'])])
    listener = listen(module_master)
    try:
        proc = sensor_test(module_master, ['--sensors', 'backSonar', '--duration', '2.5', '--no-diagnostics',
                                           '--no-history', '--no-report', '--output-dir', str(tmp_path)])
        time.sleep(0.3)    # time for a /diagnostics message, which must not come
    finally:
        stop(pubs)
        arrays = arrays_of(listener)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert arrays == []

