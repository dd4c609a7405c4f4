"""One side-by-side round: the publisher, then `rostopic hz` and sensorTest listening to the
same streams, sensorTest's memory sampled, the end awaited, the numbers collected."""
import argparse
import glob
import json
import os
import shutil
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from typing import IO, Any, Dict, List, Optional, Tuple, Union

import report
from probes import MemorySampler, Usage, byte_compiled, wait4, wait_subscribed
from workload import topics

from pepper_interface_tests.plan.settings import package_dir
from pepper_interface_tests.results import JSON_FILE
from pepper_interface_tests.rosmaster import PrivateMaster, stop_group

PUBLISHER = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'publisher.py')


@dataclass
class Round:
    """What a round runs with: the options, its label (e.g. on-1), recording off or on."""
    args: argparse.Namespace
    tmp: str
    label: str
    mode: str
    env: Dict[str, str]
    master_uri: str

    @property
    def out_dir(self) -> str:
        return os.path.join(self.tmp, 'out-' + self.label)

    def log(self, name: str) -> IO[str]:
        return open(os.path.join(self.tmp, '%s-%s.log' % (name, self.label)), 'w')


@dataclass
class Listeners:
    """The two listeners of a round and their logs; t0: when sensorTest started (monotonic)."""
    hz: subprocess.Popen
    hz_log: IO[str]
    sensor_test: subprocess.Popen
    log: IO[str]
    t0: float


@dataclass
class Ended:
    """How a round ended: the publisher's report, each listener's exit and rusage."""
    published: Dict[str, Any]
    hz_usage: Optional[Usage]
    code: Optional[int]
    usage: Optional[Usage]
    wall: float


def _sensor_test_command(rnd: Round, files: Tuple[str, str, str]) -> Tuple[List[str], Optional[str]]:
    """sensorTest's command line (under py-spy with --profile) and the profile's path."""
    topics_file, inputs, expect = files
    args = rnd.args
    cmd = [sys.executable, os.path.join(package_dir(), 'scripts', 'sensorTest'), '--topics', topics_file,
           '--input', inputs, '--expectations', expect, '--platform', 'robot', '--mode', 'parallel',
           '--duration', '%g' % args.duration, '--wait', '10', '--output-dir', rnd.out_dir, '--no-show',
           '--no-history', '--no-diagnostics', '--no-report'] + ([] if rnd.mode == 'on' else ['--no-record'])
    if not args.profile:
        return cmd, None
    spy = shutil.which('py-spy')
    if not spy:
        print('py-spy not found: no profile')
        return cmd, None
    os.makedirs(args.profile, exist_ok=True)
    profile = os.path.join(os.path.abspath(args.profile), 'sensorTest-%s.txt' % rnd.label)
    return [spy, 'record', '--format', 'raw', '--rate', '200', '--nonblocking', '-o', profile, '--'] + cmd, profile


def _hz_command() -> List[str]:
    return [shutil.which('rostopic') or 'rostopic', 'hz'] + topics()


def _print_commands(rnd: Round, cmd: List[str]) -> None:
    root = package_dir()
    sensor_test = os.path.join(root, 'scripts', 'sensorTest')
    print('\n== round %s: recording %s ==' % (rnd.label, rnd.mode))
    print('sensorTest: ' + ' '.join(cmd[cmd.index(sensor_test) + 1:]).replace(root + '/', ''))
    print('alongside:  ' + ' '.join(['rostopic'] + _hz_command()[1:]))


def _start_publisher(rnd: Round, procs: List[subprocess.Popen]) -> subprocess.Popen:
    """The publisher, waiting for two subscribers on every topic (rostopic hz and sensorTest)."""
    # 10 s of streams as in issue 12; the window is longer so that a publisher that starts late
    # (on a loaded machine) still ends inside it
    args = rnd.args
    publish_s = args.publish if args.publish else min(10.0, max(1.0, args.duration - 2.0))
    pub = subprocess.Popen([sys.executable, PUBLISHER, '--subscribers', '2', '--publish', '%g' % publish_s],
                           env=rnd.env, stdout=subprocess.PIPE, text=True, start_new_session=True)
    procs.append(pub)
    time.sleep(1.0)
    return pub


def _start_listeners(rnd: Round, cmd: List[str], procs: List[subprocess.Popen]) -> Union[Listeners, str]:
    """`rostopic hz` first, then sensorTest once hz has subscribed everywhere (or an error)."""
    hz_log = rnd.log('rostopic-hz')
    hz = subprocess.Popen(_hz_command(), env=rnd.env, stdout=hz_log, stderr=subprocess.STDOUT,
                          start_new_session=True)
    procs.append(hz)
    if not wait_subscribed(rnd.master_uri, '/rostopic_', topics(), 60.0):
        return 'rostopic hz did not subscribe within 60 s; log: %s' % hz_log.name
    log = rnd.log('sensorTest')
    t0 = time.monotonic()
    st = subprocess.Popen(cmd, env=rnd.env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    procs.append(st)
    return Listeners(hz, hz_log, st, log, t0)


def _wait_for_end(pub: subprocess.Popen, lst: Listeners, sampler: MemorySampler, duration: float) -> Ended:
    """The publisher's counts; `rostopic hz` stopped (SIGINT) once it is done; sensorTest's end."""
    line = pub.stdout.readline() if pub.stdout else ''   # the publisher reports once it has published everything
    published = json.loads(line) if line.strip() else {'error': 'publisher printed nothing'}
    time.sleep(0.5)                      # let the last messages arrive at rostopic hz
    if lst.hz.poll() is None:
        os.killpg(lst.hz.pid, signal.SIGINT)
    hz_code, hz_usage = wait4(lst.hz.pid, 20.0)
    lst.hz.returncode = hz_code
    lst.hz_log.close()
    code, usage = wait4(lst.sensor_test.pid, duration + 120.0)
    lst.sensor_test.returncode = code
    wall = time.monotonic() - lst.t0
    sampler.stop()
    lst.log.close()
    return Ended(published, hz_usage, code, usage, wall)


def _results(rnd: Round, lst: Listeners, end: Ended) -> Union[Dict[str, Any], str]:
    """sensorTest's results JSON, or why the round has none."""
    if 'error' in end.published:
        return 'publisher: ' + end.published['error']
    if end.usage is None or end.hz_usage is None:
        return 'sensorTest or rostopic hz did not end; logs in %s' % rnd.tmp
    path = os.path.join(rnd.out_dir, JSON_FILE)
    if not os.path.exists(path):
        return 'sensorTest wrote no results (exit %s); log: %s' % (end.code, lst.log.name)
    with open(path) as f:
        run: Dict[str, Any] = json.load(f)
    return run


def _last_file(out_dir: str, run: Dict[str, Any]) -> Optional[float]:
    """Seconds from the end of the window to the last mp4 or WAV written (its mtime)."""
    window_end = run['start_unix'] + max(s['ended_at'] for s in run['sensors'])
    media = [p for ext in ('mp4', 'wav') for p in glob.glob(os.path.join(out_dir, '*.' + ext))]
    return (max(os.path.getmtime(p) for p in media) - window_end) if media else None


def _video_cpu(results: Dict[str, Dict[str, Any]]) -> Tuple[float, float]:
    """CPU seconds of the encoders and of the writer threads, summed over the videos."""
    videos = [(r.get('values') or {}).get('video') or {} for r in results.values()]
    encoders = sum(v.get('encoder_cpu_s') or 0.0 for v in videos if isinstance(v, dict))
    writers = sum(v.get('writer_cpu_s') or 0.0 for v in videos if isinstance(v, dict))
    return encoders, writers


def _measurements(rnd: Round, end: Ended, usage: Usage, hz_usage: Usage, peak: Dict[str, int]) -> Dict[str, Any]:
    """The round's numbers: CPU (user + system with reaped children), peak memory in MB."""
    cpu = usage.ru_utime + usage.ru_stime
    hz_cpu = hz_usage.ru_utime + hz_usage.ru_stime
    return {'label': rnd.label, 'mode': rnd.mode, 'exit': end.code, 'wall': end.wall, 'cpu': cpu,
            'user': usage.ru_utime, 'system': usage.ru_stime, 'hz_cpu': hz_cpu,
            'hz_user': hz_usage.ru_utime, 'hz_system': hz_usage.ru_stime,
            'faults': usage.ru_minflt, 'hz_faults': hz_usage.ru_minflt,
            'ratio': cpu / hz_cpu if hz_cpu else float('inf'),
            # sampled only: ru_maxrss carries the forking parent's high-water mark over exec
            'rss': peak.get('rss', 0) / 1e6,
            'rss_children': peak.get('rss_children', 0) / 1e6, 'rss_tree': peak.get('rss_tree', 0) / 1e6,
            'pss_tree': peak.get('pss_tree', 0) / 1e6, 'uss_tree': peak.get('uss_tree', 0) / 1e6,
            'late': end.published['finished_late_s'], 'publish_s': end.published['seconds']}


def _collect(rnd: Round, lst: Listeners, end: Ended, sampler: MemorySampler,
             profile: Optional[str]) -> Dict[str, Any]:
    """Print the round's table and lines; its measurements (or {'error': text})."""
    run = _results(rnd, lst, end)
    if isinstance(run, str):
        return {'error': run}
    assert end.usage is not None and end.hz_usage is not None    # _results said why otherwise
    results = {s['name']: s for s in run['sensors']}
    streams, ok_counts = report.stream_table(results, end.published, rnd.out_dir, rnd.args.target, rnd.mode == 'on')
    m = _measurements(rnd, end, end.usage, end.hz_usage, sampler.peak)
    m['encoders'], m['writers'] = _video_cpu(results)
    m.update({'last_file': _last_file(rnd.out_dir, run) if rnd.mode == 'on' else None,
              'counts_ok': ok_counts, 'streams': streams, 'profile': profile})
    report.print_round(m, sampler.threads, lst.sensor_test.pid)
    return m


def run_round(args: argparse.Namespace, tmp: str, master: PrivateMaster, files: Tuple[str, str, str],
              mode: str, label: str) -> Dict[str, Any]:
    """One side-by-side round; a dict of measurements (or {'error': text})."""
    rnd = Round(args, tmp, label, mode, byte_compiled(master.env()), master.uri)
    cmd, profile = _sensor_test_command(rnd, files)
    _print_commands(rnd, cmd)
    procs: List[subprocess.Popen] = []
    try:
        pub = _start_publisher(rnd, procs)
        lst = _start_listeners(rnd, cmd, procs)
        if isinstance(lst, str):
            return {'error': lst}
        sampler = MemorySampler(lst.sensor_test.pid, per_thread=args.threads)
        end = _wait_for_end(pub, lst, sampler, args.duration)
        return _collect(rnd, lst, end, sampler, profile)
    finally:
        for p in reversed(procs):
            stop_group(p, timeout=10.0)
