#!/usr/bin/env python3
"""recordingBenchmark: what `sensorTest --bag` costs next to the libraries' own reading of the
same recording, for a ROS 1 bag and for ROS 2 recordings (sqlite3 and MCAP) of the same data.

It writes one synthetic recording of Pepper's streams (recording.py: four 640x480 cameras at
10 Hz, depth, laser, sonars, IMU, odometry, joints, microphones; --seconds 60 is about 2.1 GB
per form) as a ROS 1 bag, a rosbag2 sqlite3 folder and a rosbag2 MCAP folder in one pass, or
reuses the ones in --folder. Then, per form, one after the other (never side by side: the
machine's cores are not shared between the two measured processes):
  the floor: `python readers.py rosbag BAG` (rosbag's read_messages, every message deserialized)
  for the ROS 1 bag, `python readers.py rosbags FOLDER` (rosbags' Reader and deserialize_cdr) for
  a ROS 2 recording;
  `sensorTest --bag PATH --sensors (all twelve) --no-record --no-report --no-history --no-show
  --no-diagnostics` with no ROS master.
The measure is CPU time, user + system from wait4 (the process and its reaped children), not
wall time: the machine is shared and wall time counts the others' work. Printed per form: the
CPU of both, their ratio against the target of issue 24 (<= 1.5x), and whether sensorTest's
verdicts and message counts equal those of the ROS 1 bag. Exit code 0 when every form met the
target with the same verdicts, 1 otherwise, 2 when a process failed."""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from typing import Any, Dict, Optional, Sequence, Tuple

import recording
from probes import wait4

from pepper_interface_tests.outputs.terminal import HelpFormatter
from pepper_interface_tests.plan.settings import package_dir

TARGET = 1.5       # issue 24: sensorTest --bag <= 1.5x the library's own deserializing read
HERE = os.path.dirname(os.path.abspath(__file__))
QUIET = ['--no-record', '--no-report', '--no-history', '--no-show', '--no-diagnostics']
FLOOR = {'ros1': 'rosbag', 'sqlite3': 'rosbags', 'mcap': 'rosbags'}


def _measure(cmd: Sequence[str], log: str, env: Dict[str, str]) -> Tuple[Optional[int], float, float]:
    """(exit code, CPU seconds user + system, wall seconds) of one process."""
    t0 = time.monotonic()
    with open(log, 'w') as f:
        p = subprocess.Popen(list(cmd), stdout=f, stderr=subprocess.STDOUT, env=env)
        code, usage = wait4(p.pid, 1800.0)
    if usage is None:
        p.kill()
        p.wait()
        return None, 0.0, time.monotonic() - t0
    return code, usage.ru_utime + usage.ru_stime, time.monotonic() - t0


def _verdicts(out: str) -> Dict[str, Tuple[str, int]]:
    path = os.path.join(out, 'sensorTestResults.json')
    if not os.path.exists(path):
        return {}
    with open(path) as f:
        return {s['name']: (s['verdict'], s['messages']) for s in json.load(f)['sensors']}


def _form(name: str, path: str, tmp: str, env: Dict[str, str]) -> Dict[str, Any]:
    floor_cmd = [sys.executable, os.path.join(HERE, 'readers.py'), FLOOR[name], path]
    code, floor_cpu, _ = _measure(floor_cmd, os.path.join(tmp, 'floor-%s.log' % name), env)
    if code != 0:
        return {'error': '%s: the floor reader failed (%s)' % (name, os.path.join(tmp, 'floor-%s.log' % name))}
    out = os.path.join(tmp, 'out-' + name)
    cmd = [sys.executable, os.path.join(package_dir(), 'scripts', 'sensorTest'), '--bag', path,
           '--sensors', recording.SENSORS, '--output-dir', out] + QUIET
    code, cpu, wall = _measure(cmd, os.path.join(tmp, 'sensorTest-%s.log' % name), env)
    if code not in (0, 1):
        log = os.path.join(tmp, 'sensorTest-%s.log' % name)
        return {'error': '%s: sensorTest ended with %s (%s)' % (name, code, log)}
    return {'form': name, 'floor': FLOOR[name], 'floor_cpu': floor_cpu, 'cpu': cpu, 'wall': wall,
            'code': code, 'verdicts': _verdicts(out)}


def run(args: argparse.Namespace) -> int:
    tmp = tempfile.mkdtemp(prefix='recordingBenchmark-')
    folder = args.folder or tmp
    env = dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:1')
    print('recordingBenchmark: %d CPUs, load average %s; output in %s'
          % (os.cpu_count() or 0, ' '.join('%.2f' % x for x in os.getloadavg()), tmp))
    try:
        paths = {'ros1': os.path.join(folder, 'pepper.bag'), 'sqlite3': os.path.join(folder, 'pepper_sqlite3'),
                 'mcap': os.path.join(folder, 'pepper_mcap')}
        if not all(os.path.exists(p) for p in paths.values()):
            os.makedirs(folder, exist_ok=True)
            print('writing %g s of recording in three forms...' % args.seconds)
            t0 = time.monotonic()
            paths = recording.write(folder, args.seconds)
            print('  written in %.0f s' % (time.monotonic() - t0))
        else:
            print('reusing the recording in %s' % folder)
        rows = []
        for name in args.forms:
            row = _form(name, paths[name], tmp, env)
            if 'error' in row:
                print(row['error'])
                return 2
            rows.append(row)
            print('  %-8s %6.0f MB  sensorTest %6.2f s CPU (%.1f s wall), %-7s %6.2f s CPU: %.2fx'
                  % (name, recording.size(paths[name]) / 1e6, row['cpu'], row['wall'], row['floor'],
                     row['floor_cpu'], row['cpu'] / row['floor_cpu']))
        return 0 if _summary(rows) else 1
    finally:
        if args.keep:
            print('kept: %s' % tmp)
        else:
            shutil.rmtree(tmp, ignore_errors=True)


def _summary(rows: Sequence[Dict[str, Any]]) -> bool:
    ok = True
    ros1 = next((r['verdicts'] for r in rows if r['form'] == 'ros1'), None)
    for r in rows:
        ratio = r['cpu'] / r['floor_cpu']
        passed = sum(1 for v, _ in r['verdicts'].values() if v == 'PASS')
        same = ros1 is None or r['verdicts'] == ros1
        good = ratio <= TARGET and same and bool(r['verdicts'])
        ok = ok and good
        print('%-8s %.2fx of %s (target <= %.1fx), %d/%d sensors PASS, %s: %s'
              % (r['form'], ratio, r['floor'], TARGET, passed, len(r['verdicts']),
                 'verdicts and counts as the ROS 1 bag' if same else 'VERDICTS OR COUNTS DIFFER from the ROS 1 bag',
                 'ok' if good else 'NOT MET'))
        if not same and ros1 is not None:
            for k in sorted(set(ros1) | set(r['verdicts'])):
                if ros1.get(k) != r['verdicts'].get(k):
                    print('    %s: ROS 1 %s, %s %s' % (k, ros1.get(k), r['form'], r['verdicts'].get(k)))
    return ok


def main(argv: Optional[Sequence[str]] = None) -> int:
    p = argparse.ArgumentParser(prog='recordingBenchmark', description=__doc__.split('\n\n')[0],
                                formatter_class=HelpFormatter, epilog=__doc__.split('\n\n', 1)[1])
    p.add_argument('--seconds', type=float, default=60.0,
                   help='length of the recording written (default 60: about 2.1 GB per form)')
    p.add_argument('--folder', help='write the recording here, or reuse the one already there')
    p.add_argument('--forms', default='ros1,sqlite3,mcap', help='forms measured (default ros1,sqlite3,mcap)')
    p.add_argument('--keep', action='store_true', help="keep the temporary folder (logs, results; "
                   "the recording too when --folder is not given)")
    args = p.parse_args(argv)
    args.forms = [f.strip() for f in args.forms.split(',') if f.strip()]
    if not args.forms or any(f not in FLOOR for f in args.forms):
        p.error('--forms takes ros1, sqlite3, mcap separated by commas')
    return run(args)


if __name__ == '__main__':
    sys.exit(main())
