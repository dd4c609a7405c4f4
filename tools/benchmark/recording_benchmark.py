#!/usr/bin/env python3
"""recordingBenchmark: sensorTest --bag against the libraries' own reading.

Two synthetic recordings of Pepper's streams (recording.py: four 640x480
cameras at 10 Hz, depth, laser, sonars, IMU, odometry, joints, microphones;
--seconds 60 is about 2.1 GB per form), one with the driver's /tf (50 Hz, 84
transforms a message) and one of the sensors alone, without /tf (users record
what they record: --tf chooses), each written in one pass as a ROS 1 bag, a
rosbag2 sqlite3 folder and a rosbag2 MCAP folder (or the ones already in
--folder, in its with_tf/ and without_tf/, are reused). Then, per recording and
form, one after the other:
  the floor: the library's own read of the same recording, every message
    deserialized (readers.py: rosbag's read_messages for the bag, rosbags'
    Reader and deserialize_cdr for a ROS 2 recording);
  sensorTest --bag on it, all twelve sensors, with no ROS master, recording,
    report, history, live view and diagnostics off.
The measure is CPU time (user + system from wait4, the process and its reaped
children), not wall time: the machine is shared, and wall time counts the
other work on it. Printed: both CPU times and their ratio per run, and the
peak RSS of each process (wait4's ru_maxrss), then per form the median ratio
against the target (<= 1.5x) and whether the verdicts and message counts are
those of the ROS 1 bag, for each recording: each form must meet it on both. Both run byte-compiled, as installed
(probes.byte_compiled).
Exit code 0 when every form met the target with the same verdicts, 1 when
not, 2 when a process failed.
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from typing import Any, Dict, Optional, Sequence, Tuple

import recording
from probes import byte_compiled, wait4_peak

from pepper_interface_tests.outputs.terminal import HelpFormatter
from pepper_interface_tests.plan.settings import package_dir

TARGET = 1.5       # sensorTest --bag <= 1.5x the library's own deserializing read
HERE = os.path.dirname(os.path.abspath(__file__))
QUIET = ['--no-record', '--no-report', '--no-history', '--no-show', '--no-diagnostics']
FLOOR = {'ros1': 'rosbag', 'sqlite3': 'rosbags', 'mcap': 'rosbags'}


def _measure(cmd: Sequence[str], log: str, env: Dict[str, str]) -> Tuple[Optional[int], float, float, float]:
    """(exit code, CPU seconds user + system, wall seconds, peak RSS in MB) of one process (its
    peak RSS: the kernel's high-water mark of its memory, probes.wait4_peak)."""
    t0 = time.monotonic()
    with open(log, 'w') as f:
        p = subprocess.Popen(list(cmd), stdout=f, stderr=subprocess.STDOUT, env=env)
        code, usage, peak = wait4_peak(p.pid, 1800.0)
    if usage is None:
        p.kill()
        p.wait()
        return None, 0.0, time.monotonic() - t0, 0.0
    return code, usage.ru_utime + usage.ru_stime, time.monotonic() - t0, peak


def _verdicts(out: str) -> Dict[str, Tuple[str, int]]:
    path = os.path.join(out, 'sensorTestResults.json')
    if not os.path.exists(path):
        return {}
    with open(path) as f:
        return {s['name']: (s['verdict'], s['messages']) for s in json.load(f)['sensors']}


def measure_form(name: str, path: str, tmp: str, env: Dict[str, str], label: str,
                 sensors: str = recording.SENSORS) -> Dict[str, Any]:
    """One measurement of one form: its floor reader, then sensorTest --bag on `sensors`
    (one after the other)."""
    load = os.getloadavg()[0]     # printed beside the numbers: the machine may be shared
    log = os.path.join(tmp, 'floor-%s.log' % label)
    reader = [sys.executable, os.path.join(HERE, 'readers.py'), FLOOR[name], path]
    code, floor_cpu, _, floor_rss = _measure(reader, log, env)
    if code != 0:
        return {'error': '%s: the floor reader failed (%s)' % (name, log)}
    out = os.path.join(tmp, 'out-' + label)
    log = os.path.join(tmp, 'sensorTest-%s.log' % label)
    cmd = [sys.executable, os.path.join(package_dir(), 'scripts', 'sensorTest'), '--bag', path,
           '--sensors', sensors, '--output-dir', out] + QUIET
    code, cpu, wall, rss = _measure(cmd, log, env)
    if code not in (0, 1):
        return {'error': '%s: sensorTest ended with %s (%s)' % (name, code, log)}
    return {'form': name, 'floor': FLOOR[name], 'floor_cpu': floor_cpu, 'cpu': cpu, 'wall': wall, 'load': load,
            'rss': rss, 'floor_rss': floor_rss, 'verdicts': _verdicts(out)}


VARIANTS = {'with': ('with_tf', True), 'without': ('without_tf', False)}


def _recording(args: argparse.Namespace, folder: str, tf: bool = True) -> Dict[str, str]:
    paths = {'ros1': os.path.join(folder, 'pepper.bag'), 'sqlite3': os.path.join(folder, 'pepper_sqlite3'),
             'mcap': os.path.join(folder, 'pepper_mcap')}
    if all(os.path.exists(p) for p in paths.values()):
        print('reusing the recording in %s' % folder)
        return paths
    os.makedirs(folder, exist_ok=True)
    print('writing %g s of recording %s /tf in three forms...' % (args.seconds, 'with' if tf else 'without'))
    t0 = time.monotonic()
    paths = recording.write(folder, args.seconds, tf=tf)
    print('  written in %.0f s' % (time.monotonic() - t0))
    return paths


def run(args: argparse.Namespace) -> int:
    tmp = tempfile.mkdtemp(prefix='recordingBenchmark-')
    env = byte_compiled(dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:1'))  # no master: --bag needs none
    print('recordingBenchmark: %d CPUs, load average %s; output in %s'
          % (os.cpu_count() or 0, ' '.join('%.2f' % x for x in os.getloadavg()), tmp))
    try:
        ok = True
        for variant in args.tf:
            sub, tf = VARIANTS[variant]
            paths = _recording(args, os.path.join(args.folder or tmp, sub), tf)
            rows = []
            print('the recording %s /tf (load average %s); run, form, size; CPU seconds (user + system) '
                  'of sensorTest --bag, of the floor:'
                  % (variant, ' '.join('%.2f' % x for x in os.getloadavg())))
            for i in range(args.runs):
                for name in args.forms:
                    row = measure_form(name, paths[name], tmp, env, '%s-%s-%d' % (sub, name, i + 1),
                                       recording.sensors(tf))
                    if 'error' in row:
                        print(row['error'])
                        return 2
                    row['size'] = recording.size(paths[name])
                    rows.append(row)
                    print(row_line(row, i + 1))
            print('%s /tf (load average %s):' % (variant, ' '.join('%.2f' % x for x in os.getloadavg())))
            ok = summary(rows) and ok
        return 0 if ok else 1
    finally:
        if args.keep:
            print('kept: %s' % tmp)
        else:
            shutil.rmtree(tmp, ignore_errors=True)


def row_line(row: Dict[str, Any], run: int) -> str:
    """One measurement in 80 columns: CPU seconds of sensorTest and of the floor, their ratio;
    the peak RSS of each (MB)."""
    return ('  %d %-7s %5.0f MB  sensorTest %5.2f s  %-7s %5.2f s  %.2fx  wall %.1f s\n'
            '            peak RSS: sensorTest %.0f MB, %s %.0f MB; load average %.2f'
            % (run, row['form'], row['size'] / 1e6, row['cpu'], row['floor'], row['floor_cpu'],
               row['cpu'] / row['floor_cpu'], row['wall'], row['rss'], row['floor'], row['floor_rss'],
               row.get('load', 0.0)))


def summary(rows: Sequence[Dict[str, Any]]) -> bool:
    """One line per form: the median ratio over the runs against TARGET, and whether every run
    gave the ROS 1 bag's verdicts and message counts; True when every form met both."""
    ok = True
    ros1 = next((r['verdicts'] for r in rows if r['form'] == 'ros1'), None)
    for form in dict.fromkeys(r['form'] for r in rows):
        mine = [r for r in rows if r['form'] == form]
        ratio = statistics.median(r['cpu'] / r['floor_cpu'] for r in mine)
        verdicts = mine[0]['verdicts']
        same = all(r['verdicts'] == (ros1 if ros1 is not None else verdicts) for r in mine)
        passed = sum(1 for v, _ in verdicts.values() if v == 'PASS')
        good = ratio <= TARGET and same and bool(verdicts)
        ok = ok and good
        print('%-8s %.2fx of %s (median of %d, target <= %.1fx): %s'
              % (form, ratio, mine[0]['floor'], len(mine), TARGET, 'ok' if good else 'NOT MET'))
        print('         peak RSS: sensorTest %.0f MB, %s %.0f MB (the largest of the runs)'
              % (max(r['rss'] for r in mine), mine[0]['floor'], max(r['floor_rss'] for r in mine)))
        print('         %d/%d sensors PASS, %s' % (
            passed, len(verdicts), "verdicts and counts as the ROS 1 bag's" if same
            else 'VERDICTS OR COUNTS DIFFER from the ROS 1 bag'))
        for r in mine:
            if ros1 is not None and r['verdicts'] != ros1:
                for k in sorted(set(ros1) | set(r['verdicts'])):
                    if ros1.get(k) != r['verdicts'].get(k):
                        print('    %s: ROS 1 %s, %s %s' % (k, ros1.get(k), form, r['verdicts'].get(k)))
                break
    return ok


def main(argv: Optional[Sequence[str]] = None) -> int:
    p = argparse.ArgumentParser(prog='recordingBenchmark', description=__doc__.split('\n\n')[0],
                                formatter_class=HelpFormatter, epilog=__doc__.split('\n\n', 1)[1])
    p.add_argument('--seconds', type=float, default=60.0,
                   help='length of the recording written (default 60: about 2.1 GB per form)')
    p.add_argument('--folder', help='write the recording here, or reuse the one already there')
    p.add_argument('--forms', default='ros1,sqlite3,mcap', help='forms measured (default ros1,sqlite3,mcap)')
    p.add_argument('--tf', default='with,without', help='the recordings measured: with the driver\'s /tf, '
                   'without it (the sensors alone), or both (default with,without)')
    p.add_argument('--runs', type=int, default=3, help='measure every form this many times; the '
                   'median ratio is judged (default 3: one form\'s floor moves by a tenth between runs)')
    p.add_argument('--keep', action='store_true', help="keep the temporary folder (logs, results; "
                   "the recording too when --folder is not given)")
    args = p.parse_args(argv)
    args.forms = [f.strip() for f in args.forms.split(',') if f.strip()]
    if not args.forms or any(f not in FLOOR for f in args.forms):
        p.error('--forms takes ros1, sqlite3, mcap separated by commas')
    args.tf = [v.strip() for v in args.tf.split(',') if v.strip()]
    if not args.tf or any(v not in VARIANTS for v in args.tf):
        p.error('--tf takes with, without or with,without')
    if args.runs < 1 or args.seconds <= 0:
        p.error('--runs and --seconds take a positive number')
    return run(args)


if __name__ == '__main__':
    sys.exit(main())
