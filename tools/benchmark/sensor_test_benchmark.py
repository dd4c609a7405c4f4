#!/usr/bin/env python3
"""sensorTestBenchmark: what sensorTest costs next to `rostopic hz` on the same heavy streams.

It starts its own roscore on a free port and a publisher process (rospy) with the streams of
issue 12 (about 1 GB in 10 s):
  frontCamera, bottomCamera  640x480 rgb8 at 30 Hz
  depthCamera                320x240 16UC1 at 20 Hz
  realsenseRGBCamera         640x480 rgb8 at 30 Hz
  realsenseDepthCamera       640x480 16UC1 at 30 Hz
  microphone                 AudioCustomMsg 4 x 4096 samples at 48 kHz (11.7 buffers/s)
Each round runs, side by side on those topics, `rostopic hz` (the floor for a rospy listener:
AnyMsg, no deserialisation) and `sensorTest --platform robot --mode parallel --duration D` (default 15)
with a temporary topics, input and expectations file and output folder. The publisher waits
until both have subscribed to every topic, publishes for `--publish` seconds (default 10)
and stops, so the number published is exact and falls inside the listening window (the
temporary expectations accept the quiet tail); `rostopic hz` is stopped (SIGINT) once the
publisher is done, sensorTest ends on its own.

A round is `off` (sensorTest --no-record: every check, no recording) or `on` (checks and
recording); by default both, `--runs` times. Printed per round: published, received
(sensorTest's count) and recorded (frames decoded from the mp4 by ffprobe; buffers' worth of
samples in the WAV) per stream; the CPU seconds (user + system, from wait4: the process and
its reaped children, so sensorTest's ffmpeg encoders and any encoding after the window count)
of sensorTest and of `rostopic hz` and their ratio; the time from the end of the window to
the last recording written (mtime); the peak memory of sensorTest and its ffmpeg children
together (psutil, sampled every 0.1 s) as PSS (each shared page divided among the processes
that map it) and as RSS (the sum counts the libraries every ffmpeg maps once per process),
and sensorTest's own RSS. After each recording round, the recorders alone (encoders.py): the
package's own video recorders record the frames the round published, at the times they were
published, with nothing else running; their CPU (ffmpeg and their writer threads) is the
recording's floor above listening. Then one summary line per round against the targets:
listening (recording off) <= 1.1x the CPU of `rostopic hz` beside it; recording <= 1.1x of
(the same run's listening round + the recorders alone); last file <= 2 s
after the window; peak memory (PSS of the whole tree) <= 300 MB; every message received
(>= --target) and recorded. The processes run byte-compiled, as installed (probes.byte_compiled).
Exit code 0 when every round met every target, 1 otherwise, 2 when a round could not run.
`--profile DIR` runs sensorTest under py-spy (if installed) and prints the top entries
(CPU ratios of such a round include the profiler and are not comparable).
"""
import argparse
import os
import shutil
import sys
import tempfile
from typing import Any, Dict, List, Optional, Sequence

from bench_round import run_round
from encoders import recorders_alone
from report import TARGETS, summary
from workload import write_files

from pepper_interface_tests.outputs.terminal import HelpFormatter
from pepper_interface_tests.rosmaster import MasterError, PrivateMaster


def _rounds(args: argparse.Namespace, tmp: str, master: PrivateMaster) -> Optional[List[Dict[str, Any]]]:
    """Every round, `--runs` times over `--modes`; None when one could not run (said why)."""
    files = write_files(tmp)
    rounds = []
    for i in range(args.runs):
        for mode in args.modes:
            m = run_round(args, tmp, master, files, mode, '%s-%d' % (mode, i + 1))
            if 'error' in m:
                print(m['error'])
                return None
            if mode == 'on':
                m['recorders_alone'] = _recorders_alone(m, os.path.join(tmp, 'recorders-%d' % (i + 1)))
            rounds.append(m)
    return rounds


def _recorders_alone(m: Dict[str, Any], folder: str) -> Optional[float]:
    """CPU seconds of the recorders alone (ffmpeg and the writer threads, encoders.py) on the
    frames the round published, fed at the times they were published."""
    encoders, writers, errors = recorders_alone({name: row['published'] for name, row in m['streams'].items()},
                                               folder)
    for error in errors:
        print('recorders alone: ' + error)
    print('recorders alone (the same frames at the same rates, nothing else running): CPU %.2f s '
          '(ffmpeg %.2f s, writer threads %.2f s; in the round %.2f s and %.2f s)'
          % (encoders + writers, encoders, writers, m['encoders'], m['writers']))
    return None if errors else encoders + writers


def run(args: argparse.Namespace) -> int:
    """The benchmark in a temporary folder with a private master: 0 every target met, 1 not, 2 no run."""
    tmp = tempfile.mkdtemp(prefix='sensorTestBenchmark-')
    master = PrivateMaster('/bench', ros_home=os.path.join(tmp, 'ros_home'))
    print('sensorTestBenchmark: %d CPUs, load average %s; output in %s'
          % (os.cpu_count() or 0, ' '.join('%.2f' % x for x in os.getloadavg()), tmp))
    try:
        try:
            master.start(timeout=20.0)
        except MasterError as exc:
            print(str(exc))
            return 2
        rounds = _rounds(args, tmp, master)
        if rounds is None:
            return 2
        ok = summary(rounds, args)
        if args.keep:
            print('kept: %s' % tmp)
        return 0 if ok else 1
    finally:
        master.stop()
        if not args.keep:
            shutil.rmtree(tmp, ignore_errors=True)


def main(argv: Optional[Sequence[str]] = None) -> int:
    p = argparse.ArgumentParser(prog='sensorTestBenchmark', description=__doc__.split('\n\n')[0],
                                formatter_class=HelpFormatter,
                                epilog=__doc__.split('\n\n', 1)[1])
    p.add_argument('--duration', type=float, default=15.0, help='sensorTest --duration (default 15)')
    p.add_argument('--publish', type=float, default=None, help='seconds of publishing (default 10)')
    p.add_argument('--modes', default='off,on',
                   help='rounds per run: off (--no-record), on (recording), or off,on (default)')
    p.add_argument('--runs', type=int, default=1, help='repeat the rounds this many times (default 1)')
    p.add_argument('--no-record', dest='modes', action='store_const', const='off',
                   help='only the round with recording off (same as --modes off)')
    p.add_argument('--target', type=float, default=0.99, help='share that must be received and recorded')
    p.add_argument('--profile', metavar='DIR', help='run sensorTest under py-spy, profiles into DIR')
    p.add_argument('--threads', action='store_true', help='print the CPU of each sensorTest thread')
    p.add_argument('--keep', action='store_true', help='keep the temporary folder (videos, logs)')
    args = p.parse_args(argv)
    args.modes = [m.strip() for m in args.modes.split(',') if m.strip()]
    if not args.modes or any(m not in TARGETS for m in args.modes):
        p.error('--modes takes off, on or off,on')
    return run(args)


if __name__ == '__main__':
    sys.exit(main())
