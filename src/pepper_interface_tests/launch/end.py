"""How a launch that runs sensorTest ends, and how scripts learn its outcome.

roslaunch ends a launch when a `required` node exits, but prints a red "REQUIRED process
[sensorTest-N] has died!" banner even when every sensor passed, and roslaunch itself then
exits 0 whatever the verdict. So the launch files start sensorTest with `--end-launch` and
without `required`: at its end sensorTest

1. writes its exit code to the file named by $PEPPER_SENSORTEST_EXIT_FILE when set (the
   `sensorTestLaunch` wrapper sets it and exits with that code: scripts and CI use the wrapper);
2. sends SIGINT to the roslaunch process that started it (its parent), which shuts the launch
   down as Ctrl-C does, with no banner. Under rostest, or started any other way, nothing is sent;
   nor after an interrupt (exit 130), when the launch is shutting down already.
"""
import os
import signal
import sys

from ..results import EXIT_INTERRUPTED

EXIT_FILE_ENV = 'PEPPER_SENSORTEST_EXIT_FILE'


def _is_roslaunch(pid):
    try:
        with open('/proc/%d/cmdline' % pid, 'rb') as f:
            argv = f.read().split(b'\0')
    except OSError:
        return False
    # roslaunch is a Python script: [python3, /usr/bin/roslaunch, ...] or [/usr/bin/roslaunch, ...]
    return any(os.path.basename(a.decode('utf-8', 'replace')) == 'roslaunch' for a in argv[:2])


def end_launch(code: int, announce: bool = True) -> bool:
    """Report `code` to a waiting wrapper and end the roslaunch that started this process."""
    path = os.environ.get(EXIT_FILE_ENV)
    if path:
        try:
            with open(path, 'w') as f:
                f.write('%d\n' % code)
        except OSError as e:
            sys.stderr.write('sensorTest: cannot write the exit code to %s (%s): %s\n'
                             % (path, EXIT_FILE_ENV, e.strerror or e))
    parent = os.getppid()
    # 130: interrupted, mostly by roslaunch's own shutdown (Ctrl-C, a required node died):
    # the launch is ending already, and a second SIGINT would make roslaunch hurry its nodes
    if code == EXIT_INTERRUPTED or not _is_roslaunch(parent):
        return False
    if announce:
        sys.stdout.write('sensorTest: finished with exit code %d: ending the launch\n' % code)
        sys.stdout.flush()
    # roslaunch answers with SIGINT to its nodes: this process is on its way out already
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    os.kill(parent, signal.SIGINT)
    return True
