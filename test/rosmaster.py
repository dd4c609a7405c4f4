"""Test helpers: a real ROS master on a free port, and running package scripts as a user would.

Every test that needs ROS starts a real ``roscore`` (``Master``) on a port nobody else uses, so
tests can run side by side on one machine. Nothing here imitates ROS.
"""
import os
import signal
import socket
import subprocess
import sys
import time
import xmlrpc.client

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCRIPTS = os.path.join(ROOT, 'scripts')


def free_port():
    with socket.socket() as s:
        s.bind(('127.0.0.1', 0))
        return s.getsockname()[1]


class Master:
    """A real roscore on a free port; use as a context manager."""

    def __init__(self):
        self.port = free_port()
        self.uri = 'http://127.0.0.1:%d' % self.port
        self.proc = None

    def env(self, **extra):
        env = dict(os.environ)
        env['ROS_MASTER_URI'] = self.uri
        env['ROS_IP'] = '127.0.0.1'
        env.pop('ROS_HOSTNAME', None)
        env['PYTHONUNBUFFERED'] = '1'
        env.update({k: str(v) for k, v in extra.items()})
        return env

    def start(self):
        self.proc = subprocess.Popen(['roscore', '-p', str(self.port)], env=self.env(),
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                     start_new_session=True)
        deadline = time.time() + 20
        proxy = xmlrpc.client.ServerProxy(self.uri)
        while time.time() < deadline:
            try:
                code, _, _ = proxy.getSystemState('/test')
                if code == 1 and self._rosout_up(proxy):
                    return self
            except OSError:
                pass
            time.sleep(0.1)
        raise RuntimeError('roscore did not come up on port %d' % self.port)

    @staticmethod
    def _rosout_up(proxy):
        code, _, state = proxy.getSystemState('/test')
        return any(t == '/rosout' for t, _ in state[1])

    def stop(self):
        if self.proc and self.proc.poll() is None:
            os.killpg(self.proc.pid, signal.SIGINT)
            try:
                self.proc.wait(10)
            except subprocess.TimeoutExpired:
                os.killpg(self.proc.pid, signal.SIGKILL)
                self.proc.wait()

    def __enter__(self):
        return self.start()

    def __exit__(self, *exc):
        self.stop()


def script(name):
    """Command line that runs one of the package's scripts with this interpreter."""
    return [sys.executable, os.path.join(SCRIPTS, name)]


def spawn(cmd, env, **kw):
    """Start a process in its own process group (so kill_group stops its children too)."""
    return subprocess.Popen(cmd, env=env, start_new_session=True, **kw)


def kill_group(proc, sig=signal.SIGINT, timeout=10):
    if proc.poll() is None:
        try:
            os.killpg(proc.pid, sig)
        except ProcessLookupError:
            return proc.poll()
        try:
            return proc.wait(timeout)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            return proc.wait()
    return proc.returncode
