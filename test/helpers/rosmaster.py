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

import rosgraph

from pepper_interface_tests.rosmaster import PrivateMaster, free_port, stop_group

TEST_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))   # test/ (this file: test/helpers/)
ROOT = os.path.dirname(TEST_DIR)
SCRIPTS = os.path.join(ROOT, 'scripts')
NODES = os.path.join(TEST_DIR, 'nodes')   # the test nodes and publisher scripts the tests start

__all__ = ['ROOT', 'SCRIPTS', 'TEST_DIR', 'NODES', 'Master', 'free_port', 'script', 'spawn', 'kill_group',
           'wait_until', 'unregistered', 'wait_registered', 'wait_for_publishers']


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


def pause_group(proc, seconds):
    """A real SIGSTOP of the process group of `proc` for `seconds`, then SIGCONT whatever happens:
    what a PC too busy to run it (or a laptop's stall) does to sensorTest."""
    os.killpg(proc.pid, signal.SIGSTOP)
    try:
        time.sleep(seconds)
    finally:
        os.killpg(proc.pid, signal.SIGCONT)


def wait_until(condition, timeout, what, every=0.05):
    """condition()'s first true value, asked every `every` s, instead of sleeping a guessed time;
    after `timeout` s an AssertionError says what did not happen (`what`: text, or a callable
    giving it, asked then)."""
    deadline = time.monotonic() + timeout
    while True:
        value = condition()
        if value:
            return value
        if time.monotonic() > deadline:
            raise AssertionError('%s (waited %.0f s)' % (what() if callable(what) else what, timeout))
        time.sleep(every)


def unregistered(master, published=(), subscribed=(), subscriber=''):
    """What of `published` and `subscribed` the master (its own getSystemState) does not list
    yet: `published` holds topics, or (topic, node) pairs for one given node; a `subscribed`
    topic counts once a node whose name holds `subscriber` subscribes it."""
    code, _, (pubs, subs, _) = xmlrpc.client.ServerProxy(master.uri).getSystemState('/test_wait')
    if code != 1:
        return list(published) + list(subscribed)
    pubs = {topic: set(nodes) for topic, nodes in pubs}
    subs = {topic: [n for n in nodes if subscriber in n] for topic, nodes in subs}
    missing = [p for p in published
               if not (pubs.get(p) if isinstance(p, str) else p[1] in pubs.get(p[0], ()))]
    return missing + ['a subscriber of %s' % t for t in subscribed if not subs.get(t)]


def wait_registered(master, published=(), subscribed=(), subscriber='', timeout=30.0):
    """Return once the master lists every publisher and subscriber asked for (see unregistered)."""
    left = []

    def done():
        left[:] = unregistered(master, published, subscribed, subscriber)
        return not left
    wait_until(done, timeout, lambda: 'not registered on the master: %s' % ', '.join(map(str, left)))


def wait_connected(master, node_prefix, topic, timeout=30.0):
    """Return once the node whose name starts with `node_prefix` has an inbound connection on
    `topic` (its own bus information, the slave API's getBusInfo): registered on the master is
    not yet connected to the publisher."""
    m = rosgraph.Master('/test_wait', master_uri=master.uri)

    def connected():
        _, subs, _ = m.getSystemState()
        nodes = [n for t, ns in subs if t == topic for n in ns if n.startswith(node_prefix)]
        for node in nodes:
            code, _, info = xmlrpc.client.ServerProxy(m.lookupNode(node)).getBusInfo('/test_wait')
            if code == 1 and any(c[2] == 'i' and c[4] == topic and (len(c) < 6 or c[5]) for c in info):
                return True
        return False
    wait_until(connected, timeout, lambda: '%s* has no connection on %s' % (node_prefix, topic))


def wait_for_publishers(master, topics, timeout=30.0):
    """Return once every topic of `topics` has a publisher registered on `master`."""
    wait_registered(master, topics, timeout=timeout)
