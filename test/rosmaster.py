"""Test helpers: a real ROS master on a free port, and running package scripts as a user would.

Every test that needs ROS starts a real ``roscore`` (``Master``) on a port nobody else uses, so
tests can run side by side on one machine. Nothing here imitates ROS: ``Master`` is the
package's own PrivateMaster (src/pepper_interface_tests/rosmaster.py).
"""
import os
import signal
import subprocess
import sys
import time
import xmlrpc.client

from pepper_interface_tests.rosmaster import PrivateMaster, free_port, stop_group

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCRIPTS = os.path.join(ROOT, 'scripts')

__all__ = ['ROOT', 'SCRIPTS', 'Master', 'free_port', 'script', 'spawn', 'kill_group',
           'wait_for_publishers']


class Master(PrivateMaster):
    """A real roscore on a free port for tests; use as a context manager."""

    def __init__(self):
        super().__init__('/test')


def script(name):
    """Command line that runs one of the package's scripts with this interpreter."""
    return [sys.executable, os.path.join(SCRIPTS, name)]


def spawn(cmd, env, **kw):
    """Start a process in its own process group (so kill_group stops its children too)."""
    return subprocess.Popen(cmd, env=env, start_new_session=True, **kw)


def kill_group(proc, sig=signal.SIGINT, timeout=10):
    """Signal the process group of `proc`, SIGKILL after `timeout` s; returns the exit code."""
    return stop_group(proc, sig, timeout)


def wait_for_publishers(master, topics, timeout=30.0):
    """Return once every topic of `topics` has a publisher registered on `master` (asked with
    the master's own getSystemState every 50 ms), instead of sleeping a guessed time; after
    `timeout` s an AssertionError names the topics still without one."""
    proxy = xmlrpc.client.ServerProxy(master.uri)
    deadline = time.monotonic() + timeout
    missing = set(topics)
    while True:
        code, _, (publishers, _, _) = proxy.getSystemState('/test_wait')
        if code == 1:
            missing = set(topics) - {topic for topic, nodes in publishers if nodes}
            if not missing:
                return
        if time.monotonic() > deadline:
            raise AssertionError('no publisher registered within %.0f s on: %s'
                                 % (timeout, ', '.join(sorted(missing))))
        time.sleep(0.05)
