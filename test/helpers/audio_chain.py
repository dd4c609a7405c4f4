"""Test helpers for the audio bridge: start the real processes of the chain and read results.

naoqiEndpoint -> naoqiAudio -> websocket -> naoqiAudioPublisher -> ROS -> audio_dump.py

Every process runs in its own process group with stdout+stderr in a log file under the test's
tmp_path, so a failing test can show what each process said.
"""
import os
import re
import subprocess
import sys
import time
import xmlrpc.client

import numpy as np

from pepper_interface_tests.emulator.audio_source import expected_counter, find_counter_start
from rosmaster import NODES, free_port, kill_group, script, spawn, wait_until

BUFFER = 4096
RATE = 48000


def python27_or_skip():
    """CPython 2.7.12 from tools/platform/python27.sh (built by tools/setup.sh --test), the
    capture side's Python on the robot. Not built (a clone without ../shared/python): the test
    is skipped with the reason and the fix, no error; on CI (CI=true, .ci/run) it fails instead:
    CI runs every tier."""
    import pytest

    from rosmaster import ROOT
    res = subprocess.run([os.path.join(ROOT, 'tools/platform/python27.sh'), '--installed'],
                         capture_output=True)
    if res.returncode == 3 and os.environ.get('CI') != 'true':
        pytest.skip('NOT RUN: ' + res.stderr.decode().strip().replace('[python27] ', ''))
    assert res.returncode == 0, res.stderr.decode()
    return res.stdout.decode().strip()


def robot_env(**extra):
    """The environment of a Python 2.7 process as on the robot: none of this machine's Python 3
    settings (ROS's PYTHONPATH would hand it the Python 3 packages)."""
    env = {k: v for k, v in os.environ.items() if not k.startswith('PYTHON')}
    env.update(PYTHONUNBUFFERED='1', PYTHONDONTWRITEBYTECODE='1', PYTHONNOUSERSITE='1', **extra)
    return env


class Proc:
    """A spawned process with its log file."""

    def __init__(self, name, cmd, env, log_dir):
        self.name = name
        self.log_path = os.path.join(str(log_dir), '%s-%d.log' % (name, time.time() * 1000))
        self._log = open(self.log_path, 'wb')
        self.proc = spawn(cmd, env, stdout=self._log, stderr=subprocess.STDOUT)

    def log(self):
        with open(self.log_path, 'rb') as f:
            return f.read().decode('utf-8', 'replace')

    def wait_for(self, pattern, timeout=30.0, count=1):
        """Wait until ``pattern`` (regex) occurs ``count`` times in the log; return the log."""
        deadline = time.time() + timeout
        while time.time() < deadline:
            text = self.log()
            if len(re.findall(pattern, text)) >= count:
                return text
            if self.proc.poll() is not None:
                raise AssertionError('%s exited (%s) before %r:\n%s'
                                     % (self.name, self.proc.returncode, pattern, text))
            time.sleep(0.1)
        raise AssertionError('%s: no %r within %.0f s:\n%s'
                             % (self.name, pattern, timeout, self.log()))

    def stop(self, sig=None, timeout=15):
        import signal
        rc = kill_group(self.proc, sig or signal.SIGINT, timeout)
        self._log.close()
        return rc

    def alive(self):
        return self.proc.poll() is None


class Procs:
    """Keeps every started process so the test's finally block stops them all."""

    def __init__(self, log_dir):
        self.log_dir, self.all = log_dir, []

    def start(self, name, cmd, env=None):
        p = Proc(name, cmd, env or _plain_env(), self.log_dir)
        self.all.append(p)
        return p

    def endpoint(self, port=0, *extra):
        """naoqiEndpoint on ``port`` (0: the system picks a free one); ``p.port`` is the port
        it really listens on, read from its ready line."""
        p = self.start('endpoint', script('naoqiEndpoint') + ['--port', str(port)] + list(extra))
        text = p.wait_for(r'NAOqi endpoint ready on tcp://127\.0\.0\.1:%s\b'
                          % (port or r'\d+'))
        p.port = int(re.findall(r'ready on tcp://127\.0\.0\.1:(\d+)', text)[-1])
        return p

    def publisher(self, master, ws_port=0, *extra, env=None):
        """naoqiAudioPublisher on ``ws_port`` (0: any free port); ``p.port`` is the real one."""
        p = self.start('publisher', script('naoqiAudioPublisher') + ['--port', str(ws_port)]
                       + list(extra), master.env(**(env or {})))
        text = p.wait_for(r'listening on ws://127\.0\.0\.1:%s\b' % (ws_port or r'\d+'))
        p.port = int(re.findall(r'listening on ws://127\.0\.0\.1:(\d+)', text)[-1])
        return p

    def capture(self, naoqi_port, ws_port, *extra, **kw):
        """naoqiAudio; kw ``name`` (log name, starting with 'capture'), ``env`` (extra vars)."""
        env = _plain_env()
        env.update(kw.get('env') or {})
        return self.start(kw.get('name', 'capture'), script('naoqiAudio') + [
            '--ip', '127.0.0.1', '--port', str(naoqi_port),
            '--ws', 'ws://127.0.0.1:%d' % ws_port] + list(extra), env)

    def dumper(self, master, out):
        p = self.start('dump', [sys.executable, os.path.join(NODES, 'audio_dump.py'), str(out)],
                       master.env())
        p.wait_for(r'ready')
        return p

    def stop_all(self):
        """Capture first (so it can still unsubscribe from NAOqi), then the rest, newest first."""
        for p in sorted(reversed(self.all), key=lambda p: not p.name.startswith('capture')):
            if p.alive():
                p.stop()
            elif not p._log.closed:
                p._log.close()

    def logs(self):
        return '\n'.join('==== %s ====\n%s' % (p.name, p.log()[-4000:]) for p in self.all)


def _plain_env():
    env = dict(os.environ)
    env['PYTHONUNBUFFERED'] = '1'
    return env


def wait_messages(dumper, n, timeout):
    """Wait until the dumper has received ``n`` messages."""
    return dumper.wait_for(r'msg %d ' % n, timeout)


def message_count(dumper):
    found = re.findall(r'^msg (\d+) ', dumper.log(), re.M)
    return int(found[-1]) if found else 0


def finish_dump(dumper, out):
    """Stop the dumper and load its .npz: (blocks list of (L, 4) arrays, recv_time)."""
    dumper.stop()
    data = np.load(str(out))
    samples, lengths = data['samples'], data['lengths']
    edges = np.concatenate([[0], np.cumsum(lengths)])
    blocks = [samples[:, edges[i]:edges[i + 1]].T for i in range(len(lengths))]
    return blocks, data['recv_time']


def counter_starts(blocks, samples=BUFFER):
    """Start index of every received block; fails unless each is an exact counter run of
    ``samples`` samples in the right fields (rearLeft, rearRight, frontLeft, frontRight =
    channels 0..3; emulator/audio_source.py, pattern ``counter``)."""
    starts = []
    for i, b in enumerate(blocks):
        assert b.shape == (samples, 4), 'message %d has shape %s' % (i, b.shape)
        start = find_counter_start(b)  # raises unless every field is its channel's exact run
        assert np.array_equal(b, expected_counter(start, samples))
        starts.append(start)
    return np.array(starts)


def get_param(master, name):
    code, msg, value = xmlrpc.client.ServerProxy(master.uri).getParam('/audio_test', name)
    return value if code == 1 else None


def wait_param(master, name, predicate, timeout):
    """The param's value once `predicate` holds for it (asked every 0.2 s)."""
    last = [None]

    def holds():
        last[0] = get_param(master, name)
        return last[0] if last[0] is not None and predicate(last[0]) else None
    return wait_until(holds, timeout, lambda: 'param %s never satisfied the condition; last value %r'
                      % (name, last[0]), every=0.2)


__all__ = ['Procs', 'free_port', 'wait_messages', 'message_count', 'finish_dump', 'counter_starts',
           'get_param', 'wait_param', 'BUFFER', 'RATE']
