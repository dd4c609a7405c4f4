"""sensorTestLaunch: run a launch file that runs sensorTest and exit with sensorTest's exit code.

    sensorTestLaunch [--timeout S] LAUNCH [arg:=value ...] [roslaunch options, e.g. --wait]

LAUNCH is a path, or a file name of this package's launch/ folder (pepperEmulator.launch).
`run_test:=true` is added unless given. roslaunch's own output passes through. Exit code: the
one sensorTest wrote (0 passed, 1 a sensor failed, 2 could not start, 3, 130: see sensorTest
--help); 2 when the launch ended without sensorTest finishing (a node it needs failed, e.g. the
emulator refusing a fault string: its message is above; sensorTest then reports 130, interrupted
by roslaunch's shutdown) or after --timeout; 130 on Ctrl-C. See launch/end.py for how sensorTest ends the launch."""
import argparse
import os
import signal
import subprocess
import sys
import tempfile
from typing import List, Optional, Sequence

from ..results import EXIT_CANNOT_START, EXIT_INTERRUPTED
from .end import EXIT_FILE_ENV


def resolve(launch: str) -> Optional[str]:
    if os.path.isfile(launch):
        return os.path.abspath(launch)
    from ..plan.settings import package_dir
    path = os.path.join(package_dir(), 'launch', launch)
    return path if os.path.isfile(path) else None


def parse(argv: Sequence[str]) -> argparse.Namespace:
    p = argparse.ArgumentParser(prog='sensorTestLaunch', description=__doc__.split('\n')[0],
                                epilog='example: sensorTestLaunch pepperEmulator.launch duration:=3 '
                                       '--wait; echo "exit $?"')
    p.add_argument('--timeout', type=float, metavar='S',
                   help='end the launch and exit 2 when sensorTest has not finished after S seconds')
    p.add_argument('launch', help='launch file: a path or a file name in this package\'s launch/')
    p.add_argument('rest', nargs=argparse.REMAINDER,
                   help='arg:=value pairs and roslaunch options, passed on to roslaunch')
    return p.parse_args(argv)


def main(argv: Optional[Sequence[str]] = None) -> int:
    ns = parse(sys.argv[1:] if argv is None else argv)
    path = resolve(ns.launch)
    if path is None:
        sys.stderr.write('sensorTestLaunch: error: no launch file %s\n  fix: give a path, or one of: '
                         'pepperEmulator.launch, sensorTestLaunchRobot.launch, '
                         'sensorTestLaunchSimulator.launch\n' % ns.launch)
        return EXIT_CANNOT_START
    args = list(ns.rest)
    if not any(a.startswith('run_test:=') for a in args):
        args.append('run_test:=true')
    fd, exit_file = tempfile.mkstemp(prefix='sensorTest-exit-')
    os.close(fd)
    env = dict(os.environ, **{EXIT_FILE_ENV: exit_file})
    proc = subprocess.Popen(['roslaunch', path] + args, env=env)
    interrupted: List[int] = []
    timed_out, limit = False, ns.timeout

    def forward(signum, frame):     # Ctrl-C reaches roslaunch through the terminal as well
        interrupted.append(signum)
        if proc.poll() is None:
            proc.send_signal(signal.SIGINT)
    signal.signal(signal.SIGINT, forward)
    signal.signal(signal.SIGTERM, forward)
    try:
        while True:
            try:
                proc.wait(None if timed_out else limit)
                break
            except subprocess.TimeoutExpired:
                timed_out = True
                proc.send_signal(signal.SIGINT)
        with open(exit_file) as f:
            text = f.read().strip()
    finally:
        os.unlink(exit_file)
    if text.isdigit() and not (int(text) == EXIT_INTERRUPTED and not interrupted and not timed_out):
        return int(text)
    if timed_out:
        why = 'sensorTest did not finish within --timeout %g s' % limit
    elif interrupted:
        sys.stderr.write('sensorTestLaunch: interrupted before sensorTest finished\n')
        return EXIT_INTERRUPTED
    else:
        # sensorTest interrupted (130) while nobody pressed Ctrl-C: roslaunch shut it down
        why = ('the launch ended (roslaunch exit %d) before sensorTest finished%s: a node it needs '
               'failed (a "REQUIRED process" above names it) or the launch could not start; the '
               'reason is in the messages above' % (proc.returncode, ' (it was interrupted)'
                                                    if text.isdigit() else ''))
    sys.stderr.write('sensorTestLaunch: error: %s\n' % why)
    return EXIT_CANNOT_START
