"""A ROS master of our own on a free port, picking free ports, and stopping process groups.

Used by recordTestBags, the benchmark, tools/demo.sh and the tests: each starts its own
`roscore` on a port nobody else uses, so several can run side by side on one machine.

Why ports are picked the way they are (a demo once failed with two equal picks): a port that
was free when picked can be taken before the server binds it, by another picker or by any
program's bind to port 0 (every rospy node binds its XML-RPC and TCPROS servers that way). So
`free_ports` takes ports *below* the kernel's ephemeral range (/proc/sys/net/ipv4/
ip_local_port_range: no port-0 bind ever lands there), random, all distinct, and never one this
process handed out before; and `PrivateMaster` makes a remaining collision harmless: it sees
roscore's "port ... is already in use" (or a master on its port that is not its own) within a
second and starts again on other ports.
"""
import os
import random
import signal
import socket
import subprocess
import tempfile
import time
import xmlrpc.client
from typing import Any, Dict, Iterable, List, Optional, Sequence, Set, Tuple, Union

PICK_LOW = 20000   # below: well-known and registered service ports (11311, 9090, 9559 ...)
_handed_out: Set[int] = set()


def ephemeral_range() -> Tuple[int, int]:
    """(low, high) of the kernel's range for port-0 binds; Linux's default if unreadable."""
    try:
        with open('/proc/sys/net/ipv4/ip_local_port_range') as f:
            low, high = (int(x) for x in f.read().split())
        return low, high
    except (OSError, ValueError):
        return 32768, 60999


def _candidates():
    low, high = ephemeral_range()
    if low - PICK_LOW >= 2000:
        return range(PICK_LOW, low)
    if 65535 - high >= 2000:
        return range(high + 1, 65536)
    return range(1024, 65536)  # an unusual kernel set-up: any port, collisions still detected


def free_ports(n: int, host: str = '127.0.0.1') -> List[int]:
    """`n` distinct TCP ports on `host`, each free right now, outside the ephemeral range and
    never returned before by this process. The probe sockets are held until all are chosen."""
    held: List[socket.socket] = []
    ports: List[int] = []
    pool = _candidates()
    try:
        for _ in range(200 * n):
            if len(ports) == n:
                break
            port = random.choice(pool)
            if port in _handed_out or port in ports:
                continue
            s = socket.socket()
            try:
                s.bind((host, port))  # no SO_REUSEADDR: a port in TIME_WAIT is skipped too
            except OSError:
                s.close()
                continue
            held.append(s)
            ports.append(port)
    finally:
        for s in held:
            s.close()
    if len(ports) < n:
        raise OSError('no free TCP port found below the ephemeral range on %s' % host)
    _handed_out.update(ports)
    return ports


def free_port() -> int:
    """One TCP port on 127.0.0.1 that is free right now (see free_ports)."""
    return free_ports(1)[0]


def stop_group(proc: Optional[subprocess.Popen], sig: int = signal.SIGINT,
               timeout: float = 20.0) -> Optional[int]:
    """Send `sig` to the process group of `proc` (started with start_new_session=True), then
    SIGKILL if it has not ended after `timeout` s, together with the children it had (roslaunch
    starts each node in a session of its own, so they are not in its group). Returns the exit
    code."""
    if proc is None:
        return None
    if proc.poll() is not None:
        return proc.returncode
    children = _children(proc.pid)
    try:
        os.killpg(proc.pid, sig)
        return proc.wait(timeout)
    except ProcessLookupError:
        return proc.wait()
    except subprocess.TimeoutExpired:
        for pid in [proc.pid] + children:
            try:
                if pid == proc.pid:
                    os.killpg(pid, signal.SIGKILL)
                elif _parent(pid) in (proc.pid, 1):  # still ours, not a reused pid
                    os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        return proc.wait()


def _children(pid):
    """Pids of the direct children of `pid` (Linux /proc)."""
    return [int(p) for p in os.listdir('/proc') if p.isdigit() and _parent(int(p)) == pid]


class MasterError(RuntimeError):
    """roscore did not come up."""


# roscore's words when its port is taken (rosgraph/xmlrpc.py, roslaunch/launch.py). The
# run_id line is the race of two roscores picking one port at the same moment: the other's
# master came up between this one's check and its /run_id (roslaunch/launch.py
# _setup_master_run_id, ros_comm 1.15 line 474).
PORT_TAKEN = ('is already in use', 'another roscore/master is already running',
              'run_id on parameter server does not match declared run_id')


class PrivateMaster:
    """A real roscore on a free port; use as a context manager (or start()/stop())."""

    def __init__(self, caller: str = '/private_master', ros_home: Optional[str] = None) -> None:
        self.caller = caller
        self.ros_home = ros_home
        self.proc: Optional[subprocess.Popen] = None
        self.attempts: List[str] = []  # one line per failed attempt: port and roscore's reason
        self._use_port(free_port())

    def _use_port(self, port):
        self.port = port
        self.uri = 'http://127.0.0.1:%d' % port

    def env(self, **extra: Any) -> Dict[str, str]:
        """This process's environment pointed at this master (plus `extra`)."""
        env = dict(os.environ)
        env.update(ROS_MASTER_URI=self.uri, ROS_IP='127.0.0.1', PYTHONUNBUFFERED='1')
        env.pop('ROS_HOSTNAME', None)
        if self.ros_home:
            env['ROS_HOME'] = self.ros_home
        env.update({k: str(v) for k, v in extra.items()})
        return env

    def start(self, timeout: float = 30.0, attempts: int = 4) -> 'PrivateMaster':
        """Start roscore and wait until /rosout is up on a master of its own; when its port
        turns out to be taken, start again on another one. MasterError (with roscore's own
        words) otherwise."""
        for attempt in range(attempts):
            if attempt:
                self._use_port(free_port())
            reason = self._start_once(timeout)
            if reason is None:
                return self
            self.attempts.append('port %d: %s' % (self.port, reason))
            if not port_taken([reason]) and 'not our own' not in reason:
                break
        raise MasterError('roscore did not come up: ' + '; '.join(self.attempts))

    def _start_once(self, timeout):
        """None once up, else the reason (roscore's first error line)."""
        out = tempfile.TemporaryFile()
        self.proc = subprocess.Popen(['roscore', '-p', str(self.port)], env=self.env(),
                                     stdout=out, stderr=subprocess.STDOUT,
                                     start_new_session=True)
        proxy: Any = xmlrpc.client.ServerProxy(self.uri)   # typeshed's return types hide the tuples
        deadline = time.monotonic() + timeout
        reason = 'no master on port %d after %.0f s' % (self.port, timeout)
        while time.monotonic() < deadline:
            said = _error_line(out)
            if said or self.proc.poll() is not None:
                reason = said or 'roscore exited with code %s' % self.proc.returncode
                break
            try:
                code, _, state = proxy.getSystemState(self.caller)
                if code == 1 and any(t == '/rosout' for t, _ in state[1]):
                    if _master_owner(self.uri, self.proc.pid, self.caller) == 'ours':
                        out.close()
                        return None
                    reason = 'the master on port %d is not our own (another picked it too)' % (
                        self.port)
                    break
            except OSError:
                pass
            time.sleep(0.1)
        stop_group(self.proc, timeout=2.0)  # a roscore that failed can take 10 s on SIGINT
        out.close()
        return reason

    def stop(self) -> None:
        stop_group(self.proc, timeout=10.0)

    def __enter__(self):
        return self.start()

    def __exit__(self, *exc):
        self.stop()


def _parent(pid):
    """Parent pid of `pid` (Linux /proc), 0 when unknown."""
    try:
        with open('/proc/%d/stat' % pid) as f:
            return int(f.read().rsplit(')', 1)[1].split()[1])
    except (OSError, ValueError, IndexError):
        return 0


def _alive(pid):
    """Whether process `pid` exists and is not a zombie (it need not be our child)."""
    try:
        with open('/proc/%d/stat' % pid) as f:
            return f.read().rsplit(')', 1)[1].split()[0] not in ('Z', 'X')
    except (OSError, IndexError):
        return False


def _error_line(out):
    """roscore's first line naming an error, from its output file so far, or ''."""
    out.seek(0)
    for line in out.read().decode('utf-8', 'replace').splitlines():
        if 'ERROR' in line or 'RLException' in line or any(w in line for w in PORT_TAKEN):
            return line.replace('\x1b[31m', '').replace('\x1b[0m', '').strip()
    return ''


def _descends(pid, ancestor):
    """Whether process `pid` is `ancestor` or one of its descendants (up to 4 levels)."""
    for _ in range(5):
        if pid <= 1:
            return False
        if pid == ancestor:
            return True
        pid = _parent(pid)
    return False


# Lines of a roslaunch log that explain a failed start, best first.
_CAUSE_WORDS = ('already in use', 'another roscore', 'cannot listen', 'error:', 'ERROR',
                'RLException', 'Error', 'cannot', 'not found')


def launch_failure(text: str) -> List[str]:
    """Why a roslaunch (its combined output `text`) failed, in its own words: a list of up to
    3 lines (the first process that died, and the first line naming an error), or []."""
    lines = [line.replace('\x1b[31m', '').replace('\x1b[0m', '').replace('\x1b[1m', '').strip()
             for line in text.splitlines()]
    died = [line for line in lines if 'process has died' in line]
    causes: List[str] = []
    for words in _CAUSE_WORDS:
        causes = [line for line in lines if words in line and 'process has died' not in line]
        if causes:
            break
    out = (died[:1] + causes[:2]) if (died or causes) else []
    return [line[:300] for line in out]


def port_taken(lines: Iterable[str]) -> bool:
    """Whether a failure (launch_failure's lines) is a port somebody else holds: retry then."""
    return any(w in line for line in lines for w in PORT_TAKEN + (
        'Address already in use', 'address in use', 'held by another program'))


def _master_pid(uri, timeout=2.0, caller='/launch_watch'):
    """The pid of the master at `uri`; None when nothing listens there yet; 'silent' when
    something accepts connections but does not answer as a master within `timeout` s."""
    import http.client

    class Transport(xmlrpc.client.Transport):
        def make_connection(self, host):
            return http.client.HTTPConnection(host, timeout=timeout)
    try:
        proxy: Any = xmlrpc.client.ServerProxy(uri, transport=Transport())
        code, _, pid = proxy.getPid(caller)
        return pid if code == 1 else 'silent'
    except ConnectionRefusedError:
        return None
    except (OSError, xmlrpc.client.Error, http.client.HTTPException):
        return 'silent'


def _master_owner(uri, pid, caller='/launch_watch'):
    """Who answers as the master at `uri`: 'ours' when it is process `pid` or one of its
    descendants (roslaunch starts rosmaster in a session of its own, so the process group does
    not tell), 'another' for a ROS master that is not, 'silent' and None as _master_pid."""
    master = _master_pid(uri, caller=caller)
    if isinstance(master, int):
        return 'ours' if _descends(master, pid) else 'another'
    return master


def wait_for_launch(launcher: Union[subprocess.Popen, int], log_path: str, master_uri: str,
                    topics: Sequence[str], timeout: float = 60.0, grace: float = 8.0) -> Tuple[str, List[str]]:
    """Watch a roslaunch we started (Popen-like `launcher` or a pid) until `topics` are all
    published on its own master: ('up', []), or ('failed', reason lines) as soon as one of its
    processes dies, roslaunch ends, or the master port is held by another program (a master
    that is not its own, or something that does not answer as a master for `grace` s)."""
    import rosgraph
    pid = launcher if isinstance(launcher, int) else launcher.pid
    start = time.monotonic()
    own = False
    while time.monotonic() < start + timeout:
        with open(log_path, 'rb') as f:
            text = f.read().decode('utf-8', 'replace')
        failure = launch_failure(text)
        alive = launcher.poll() is None if hasattr(launcher, 'poll') else _alive(pid)
        if not alive:
            return 'failed', failure or ['roslaunch ended']
        if 'process has died' in text or port_taken(failure):
            return 'failed', failure
        if not own:
            owner = _master_owner(master_uri, pid)
            own = owner == 'ours'
            if not own and owner is not None and time.monotonic() > start + grace:
                return 'failed', ['port %s is held by another program: %s' % (
                    master_uri.rsplit(':', 1)[-1], 'a ROS master that is not our own'
                    if owner == 'another' else 'it does not answer as a ROS master')]
        if own:
            try:
                published = {t for t, _ in rosgraph.Master('/launch_watch',
                                                           master_uri).getPublishedTopics('')}
            except Exception:
                published = set()
            if set(topics) <= published:
                return 'up', []
        time.sleep(0.3)
    with open(log_path, 'rb') as f:
        text = f.read().decode('utf-8', 'replace')
    return 'failed', ['not up after %.0f s' % timeout] + launch_failure(text)
