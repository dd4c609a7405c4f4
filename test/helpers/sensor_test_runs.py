"""sensorTest runs for the command-line tests: the publishers of the shared topics, a running
sensorTest, the files every run must leave complete (test_cli.py, test_node.py,
test_interrupts.py, outputs/test_terminal.py, outputs/test_files_hostile.py)."""
import json
import os
import signal
import subprocess
import sys
import threading
import time
import xml.etree.ElementTree as ET

import psutil
import pytest

import rosmaster
from rosmaster import NODES, kill_group, script, spawn

HERE = NODES   # the node scripts' folder (test/nodes/)
PUBLISHER = [sys.executable, os.path.join(HERE, 'core_publisher.py')]
DAT, JSON_FILE, XML_FILE = 'sensorTestOutput.dat', 'sensorTestResults.json', 'sensorTestResults.xml'
START_LIMIT = 30    # seconds allowed for publishers to register on a busy machine


def topic_of(prefix, sensor):
    return '%s/%s' % (prefix, sensor)


def write_topics(path, prefix, names):
    with open(str(path), 'w') as f:
        for n in names:
            f.write('%s %s\n' % (n, topic_of(prefix, n)))
    return str(path)


def wait_registered(master, topics=(), subscribed=(), timeout=START_LIMIT):
    """Until every topic has a publisher (and every `subscribed` topic a core_publisher subscriber)."""
    rosmaster.wait_registered(master, topics, subscribed, subscriber='core_publisher', timeout=timeout)


def sonar_and_laser_fixture(prefix, extra_topics=()):
    """A module-scoped `pubs` fixture: sonar_and_laser under `prefix`, stopped after the module."""
    @pytest.fixture(scope='module')
    def pubs(module_master, tmp_path_factory):
        p = sonar_and_laser(module_master, tmp_path_factory.mktemp(prefix.strip('/')), prefix, extra_topics)
        yield p
        p.stop()
    return pubs


def sonar_and_laser(master, tmp, prefix, extra_topics=()):
    """Publishers of a good back sonar and laser under `prefix`, and a topics file naming them
    (plus `extra_topics`, sensors nobody publishes) as `.topics`; stop() them when done."""
    p = Publishers(master, tmp)
    p.start('backSonar', topic_of(prefix, 'backSonar'), 'range', '--frame', 'SonarBack_frame')
    p.start('laser', topic_of(prefix, 'laser'), 'laser')
    p.wait([topic_of(prefix, n) for n in ('backSonar', 'laser')])
    p.topics = write_topics(tmp / 'topics.dat', prefix, ['backSonar', 'laser'] + list(extra_topics))
    return p


class Publishers:
    """core_publisher.py processes for one test (or module); stopped on exit."""

    def __init__(self, master, tmp):
        self.master, self.tmp, self.procs, self.logs = master, str(tmp), {}, {}

    def start(self, sensor, topic, kind, *args, wait=True):
        log = os.path.join(self.tmp, 'pub-%s-%d.log' % (sensor, len(self.procs)))
        self.logs[sensor] = log
        with open(log, 'w') as out:
            self.procs[sensor] = spawn(PUBLISHER + [kind, topic] + list(args), self.master.env(),
                                       stdout=out, stderr=subprocess.STDOUT)
        return self

    def wait(self, topics=(), subscribed=()):
        wait_registered(self.master, topics, subscribed)
        return self

    def log(self, sensor):
        with open(self.logs[sensor]) as f:
            return f.read()

    def stop(self, sig=signal.SIGINT):
        for p in self.procs.values():
            kill_group(p, sig)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.stop()


class Result:
    """A finished sensorTest run: exit code, output, and its three files as they were then."""

    def __init__(self, proc, out_dir, stdout, stderr, elapsed):
        self.rc, self.out_dir, self.stdout, self.stderr, self.elapsed = \
            proc.returncode, str(out_dir), stdout, stderr, elapsed
        self._files = {}
        for name in (DAT, JSON_FILE, XML_FILE):
            if os.path.isfile(self.path(name)):
                with open(self.path(name)) as f:
                    self._files[name] = f.read()

    def path(self, name):
        return os.path.join(self.out_dir, name)

    @property
    def json(self):
        return json.loads(self._files[JSON_FILE])

    @property
    def dat(self):
        return self._files[DAT]

    @property
    def junit(self):
        return ET.fromstring(self._files[XML_FILE])

    @property
    def sensors(self):
        return {s['name']: s for s in self.json['sensors']}

    def block(self, title):
        """The .dat block of one sensor in the last run."""
        last = self.dat.split('[TESTING] ############ SENSORS ############')[-1]
        return last.split('[TESTING] ---- %s ----\n' % title)[1].split('\n\n')[0]

    def files_exist(self):
        return all(n in self._files for n in (DAT, JSON_FILE, XML_FILE))

    def __repr__(self):
        return 'exit %s after %.1f s\nstdout:\n%s\nstderr:\n%s' % (self.rc, self.elapsed,
                                                                   self.stdout, self.stderr)


class Running:
    """sensorTest started in the background, its output read as it comes."""

    def __init__(self, args, env, out_dir):
        self.out_dir = out_dir
        self.t0 = time.monotonic()
        self.proc = spawn(script('sensorTest') + list(args), env, stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True)
        self.out, self.err = [], []
        self._threads = [threading.Thread(target=self._pump, args=(s, buf), daemon=True)
                         for s, buf in ((self.proc.stdout, self.out), (self.proc.stderr, self.err))]
        for t in self._threads:
            t.start()

    @staticmethod
    def _pump(stream, buf):
        for line in stream:
            buf.append(line)

    def wait_for(self, text, timeout=30):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if any(text in line for line in list(self.out)):
                return time.monotonic()
            if self.proc.poll() is not None:
                break
            time.sleep(0.05)
        raise AssertionError('sensorTest never printed %r:\n%s%s' % (text, ''.join(self.out), ''.join(self.err)))

    def finish(self, timeout=90):
        try:
            self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            kill_group(self.proc, signal.SIGKILL)
            raise AssertionError('sensorTest did not end within %s s:\n%s'
                                 % (timeout, ''.join(self.out))) from None
        elapsed = time.monotonic() - self.t0
        for t in self._threads:
            t.join(5)
        return Result(self.proc, self.out_dir, ''.join(self.out), ''.join(self.err), elapsed)


def child_pids(pid):
    """Processes whose parent is `pid` (roscore's rosmaster and rosout run in their own groups)."""
    return [child.pid for child in psutil.Process(pid).children()]


def sensor_test(master, out_dir, *args, timeout=90):
    """Run sensorTest to its end; --output-dir is added."""
    return Running(list(args) + ['--output-dir', str(out_dir)], master.env(), out_dir).finish(timeout)


def assert_outputs_complete(r, names):
    """The three files of a finished run: one block / entry / testcase per sensor."""
    assert r.files_exist(), r
    data = r.json
    assert [s['name'] for s in data['sensors']] == names
    assert data['exit_code'] == r.rc
    last = r.dat.split('[TESTING] ############ SENSORS ############')[-1]
    assert '[START TIME] ' in last and '[END TIME] ' in last
    assert last.count('[RESULT] ') == len(names)
    cases = r.junit.findall('testcase')
    assert [c.get('name') for c in cases] == names
    for c in cases:
        s = r.sensors[c.get('name')]
        failure = c.find('failure')
        assert (failure is not None) == (s['verdict'] == 'FAIL')
        plain = '; '.join(s['reasons'])
        if failure is not None and plain.isprintable() and len(plain) < 2000:   # else: escaped, cut
            assert failure.get('message') == '; '.join(s['reasons'])


def judge_bag(bag, out, sensors, timeout=180, env=None):
    """sensorTest --bag on the robot platform over `sensors`, with no master (a bag run needs
    none): (the finished process, {sensor name: its JSON result}); `env` adds variables."""
    cmd = script('sensorTest') + ['--bag', bag, '--platform', 'robot', '--sensors', ','.join(sensors),
                                  '--output-dir', str(out), '--no-history', '--no-report']
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=timeout,
                       env=dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:1', **(env or {})))
    with open(str(out / JSON_FILE)) as f:
        return p, {s['name']: s for s in json.load(f)['sensors']}
