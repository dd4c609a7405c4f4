"""What the benchmark measures processes with: their end and CPU (wait4), their memory and
threads (psutil, sampled), the master's view of who subscribed, and the environment they run in
(byte-compiled, as installed)."""
import os
import resource
import subprocess
import sys
import threading
import time
import xmlrpc.client
from typing import Any, Dict, List, Optional, Tuple

from pepper_interface_tests.media.recording import exit_code

Usage = resource.struct_rusage


def wait4(pid: int, timeout: float) -> Tuple[Optional[int], Optional[Usage]]:
    """(exit code, rusage) of a child, waiting at most `timeout` s (None, None when it did not end)."""
    code, usage, _ = wait4_peak(pid, timeout)
    return code, usage


def wait4_peak(pid: int, timeout: float) -> Tuple[Optional[int], Optional[Usage], float]:
    """wait4's answer and the child's peak RSS in MB: the largest VmHWM of /proc/PID/status read
    every 0.02 s while it runs. Not rusage's ru_maxrss: Linux carries a process's high-water
    mark over exec, so a child forked from a parent of 230 MB reports at least 230 MB."""
    deadline = time.monotonic() + timeout
    peak = 0.0
    while True:
        try:
            with open('/proc/%d/status' % pid) as f:
                for line in f:
                    if line.startswith('VmHWM:'):
                        peak = max(peak, int(line.split()[1]) / 1024.0)
                        break
        except OSError:
            pass
        done, status, usage = os.wait4(pid, os.WNOHANG)
        if done:
            return exit_code(status), usage, peak
        if time.monotonic() > deadline:
            return None, None, peak
        time.sleep(0.02)


def byte_compiled(env: Dict[str, str]) -> Dict[str, str]:
    """`env` for the measured processes with Python's bytecode cached, as an installed package
    runs (catkin and pip install compiled modules; rosbag, rospy and rosbags come compiled): a
    shell with PYTHONDONTWRITEBYTECODE would make every sensorTest start compile its ~150
    modules again (0.3-0.5 s of CPU that a user does not pay). The cache is build/pycache, the
    test suite's (tools/run-tests.sh), filled here before anything is measured."""
    import pepper_interface_tests
    from pepper_interface_tests.plan.settings import package_dir
    env = dict(env)
    env.pop('PYTHONDONTWRITEBYTECODE', None)
    env.setdefault('PYTHONPYCACHEPREFIX', os.path.join(package_dir(), 'build', 'pycache'))
    subprocess.run([sys.executable, '-m', 'compileall', '-q'] + list(pepper_interface_tests.__path__),
                   env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
    return env


def wait_subscribed(uri: str, prefix: str, topics: List[str], timeout: float) -> bool:
    """Wait until a node whose name starts with `prefix` subscribes to every topic (on a
    loaded machine `rostopic hz` may take seconds to start: sensorTest's window must not
    begin before the publisher can)."""
    master: Any = xmlrpc.client.ServerProxy(uri)   # typeshed's return types hide the tuple
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            _, _, (_, subscribers, _) = master.getSystemState('/bench')
            subs = {t: nodes for t, nodes in subscribers}
            if all(any(n.startswith(prefix) for n in subs.get(t, ())) for t in topics):
                return True
        except OSError:
            pass
        time.sleep(0.1)
    return False


class MemorySampler:
    """Peaks over a process's life, sampled every 0.1 s (psutil) in a daemon thread:
    peak['rss'] the process alone, peak['rss_children'] its children (sensorTest's ffmpeg
    encoders), peak['rss_tree'] both at the same moment, peak['pss_tree'] the proportional set
    size of the whole tree (each shared page divided among the processes that map it: the shared
    libraries of five ffmpeg processes count once, not five times), peak['uss_tree'] its private
    memory. Linux's smaps_rollup makes a PSS sample cheap (about 0.1 ms a process). With
    `per_thread`, `threads` maps each thread id to its CPU seconds (user + system)."""

    def __init__(self, pid: int, per_thread: bool = False) -> None:
        self.peak: Dict[str, int] = {}
        self.threads: Optional[Dict[int, float]] = {} if per_thread else None
        self._stop = threading.Event()
        threading.Thread(target=self._run, args=(pid,), daemon=True).start()

    def stop(self) -> None:
        self._stop.set()

    def _run(self, pid: int) -> None:
        try:
            import psutil
        except ImportError:
            return
        proc = psutil.Process(pid)
        while not self._stop.is_set():
            try:
                sample = _tree_memory(proc)
            except psutil.Error:
                return
            for key, value in sample.items():
                self.peak[key] = max(self.peak.get(key, 0), value)
            if self.threads is not None:
                try:
                    for th in proc.threads():
                        self.threads[th.id] = th.user_time + th.system_time
                except psutil.Error:
                    pass
            self._stop.wait(0.1)


def _tree_memory(proc: Any) -> Dict[str, int]:
    """One sample of MemorySampler's figures (psutil.Error when `proc` is gone; a child that
    goes while it is read is left out)."""
    import psutil
    tree = [proc] + proc.children(recursive=True)
    own = proc.memory_full_info()
    rss_kids = pss = uss = 0
    for p in tree[1:]:
        try:
            info = p.memory_full_info()
        except psutil.Error:
            continue
        rss_kids += info.rss
        pss += info.pss
        uss += info.uss
    return {'rss': own.rss, 'rss_children': rss_kids, 'rss_tree': own.rss + rss_kids,
            'pss_tree': own.pss + pss, 'uss_tree': own.uss + uss}
