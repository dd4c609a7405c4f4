"""A ROS master of our own on a free port, and stopping process groups.

Used by recordTestBags, the benchmark and the tests: each starts its own `roscore` on a port
nobody else uses, so several can run side by side on one machine.
"""
import os
import signal
import socket
import subprocess
import time
import xmlrpc.client


def free_port():
    """A TCP port on 127.0.0.1 that is free right now."""
    with socket.socket() as s:
        s.bind(('127.0.0.1', 0))
        return s.getsockname()[1]


def stop_group(proc, sig=signal.SIGINT, timeout=20.0):
    """Send `sig` to the process group of `proc` (started with start_new_session=True), then
    SIGKILL if it has not ended after `timeout` s. Returns the exit code."""
    if proc is None:
        return None
    if proc.poll() is not None:
        return proc.returncode
    try:
        os.killpg(proc.pid, sig)
        return proc.wait(timeout)
    except ProcessLookupError:
        return proc.wait()
    except subprocess.TimeoutExpired:
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        return proc.wait()


class MasterError(RuntimeError):
    """roscore did not come up."""


class PrivateMaster:
    """A real roscore on a free port; use as a context manager (or start()/stop())."""

    def __init__(self, caller='/private_master', ros_home=None):
        self.port = free_port()
        self.uri = 'http://127.0.0.1:%d' % self.port
        self.caller = caller
        self.ros_home = ros_home
        self.proc = None

    def env(self, **extra):
        """This process's environment pointed at this master (plus `extra`)."""
        env = dict(os.environ)
        env.update(ROS_MASTER_URI=self.uri, ROS_IP='127.0.0.1', PYTHONUNBUFFERED='1')
        env.pop('ROS_HOSTNAME', None)
        if self.ros_home:
            env['ROS_HOME'] = self.ros_home
        env.update({k: str(v) for k, v in extra.items()})
        return env

    def start(self, timeout=30.0):
        """Start roscore and wait until /rosout is up; MasterError otherwise."""
        self.proc = subprocess.Popen(['roscore', '-p', str(self.port)], env=self.env(),
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                     start_new_session=True)
        proxy = xmlrpc.client.ServerProxy(self.uri)
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            try:
                code, _, state = proxy.getSystemState(self.caller)
                if code == 1 and any(t == '/rosout' for t, _ in state[1]):
                    return self
            except OSError:
                pass
            time.sleep(0.1)
        self.stop()
        raise MasterError('roscore did not come up on port %d' % self.port)

    def stop(self):
        stop_group(self.proc, timeout=10.0)

    def __enter__(self):
        return self.start()

    def __exit__(self, *exc):
        self.stop()
