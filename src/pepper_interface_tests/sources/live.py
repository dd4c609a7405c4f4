"""The live data source: rospy.AnyMsg subscriptions feeding sensor windows, and master look-ups.

AnyMsg lets a subscription accept whatever type a topic really carries, so a topic advertised
with the wrong type is reported by name instead of being refused silently by rospy's md5 check.
The master is probed in a background thread (a short TCP connect, then getPid), so a slow master
never blocks the listening loop. Data connections do not need the master: a master that stalls
(no answer, e.g. WiFi to the robot) is tolerated for MASTER_SILENCE s; only a master that
refuses connections (its port closed: it died) for MASTER_REFUSED s, or stays silent longer,
ends the run ("went away"). rospy retries registrations until the master answers, so nothing
registers or unregisters while it does not answer.

A node that registers with this node's name makes the master shut this one down; rospy then
stops every subscription. That is reported as such (exit 130), not as publishers that left.
"""
import errno
import socket
import threading
import time
import xmlrpc.client
from typing import Any, Dict, List, Optional, Set
from urllib.parse import urlparse

import rosgraph
import rospy

from . import Graph, Listener, SourceLost, TopicInfo, handling, ros1_graph

MASTER_TIMEOUT = 2.0
# a master stalled for several seconds (WiFi, a loaded robot) is not gone: rospy's data
# connections are peer to peer and keep flowing; 1.3-2 s stalls were seen over WiFi
MASTER_SILENCE = 10.0
# a closed port is a dead master (a restarting one is back within this, and a new master has
# lost every registration anyway)
MASTER_REFUSED = 1.5
# s a probe round (the wait, a connect and a call, each within the timeout) may take beyond
# `every` + 2 timeouts before the rest counts as time this process did not run (issue 41): a
# sensorTest stopped or starved for longer than MASTER_SILENCE (SIGSTOP for 16 s, a swapping
# laptop) found the master silent for all that time and ended the run "the ROS master went away
# (no answer for 16 s)" although the master never stopped answering
UNRUN_SLACK = 1.0


def _other_connections(sub: Any) -> int:
    """The subscriber's connections to publishers other than this node: rospy connects a node's
    subscriber to its own publisher of the topic too (sensorTest publishes /diagnostics, which
    robotHealth listens to), each transport named by its publisher's URI (rospy
    impl/tcpros_pubsub.py create_transport: connect(..., pub_uri))."""
    own = rospy.core.get_node_uri()
    try:
        return sum(1 for c in list(sub.impl.connections) if getattr(c, 'endpoint_id', None) != own)
    except AttributeError:      # no impl: count them all, as get_num_connections does
        return sub.get_num_connections()


def master_uri() -> str:
    return rosgraph.get_master_uri()


def master_reachable(uri: Optional[str] = None, timeout: float = MASTER_TIMEOUT) -> bool:
    """True when the ROS master answers getPid within `timeout` seconds."""
    return master_state(uri, timeout) == 'ok'


def master_state(uri: Optional[str] = None, timeout: float = MASTER_TIMEOUT) -> str:
    """'ok', 'refused' (nothing listens on the master's port) or 'silent' (no answer)."""
    uri = uri or master_uri()
    parsed = urlparse(uri)
    try:
        with socket.create_connection((parsed.hostname, parsed.port or 11311), timeout=timeout):
            pass
    except ConnectionRefusedError:
        return 'refused'
    except OSError as e:
        return 'refused' if e.errno in (errno.ECONNREFUSED, errno.EHOSTUNREACH, errno.ENETUNREACH) \
            else 'silent'

    class _Transport(xmlrpc.client.Transport):
        def make_connection(self, host):
            conn = super().make_connection(host)
            conn.timeout = timeout
            return conn

    try:
        code, _, _ = xmlrpc.client.ServerProxy(uri, transport=_Transport()).getPid('/sensorTest')  # type: ignore[misc,str-unpack]  # getPid answers [code, status, pid]
        return 'ok' if code == 1 else 'silent'
    except ConnectionRefusedError:
        return 'refused'
    except (OSError, xmlrpc.client.Error):
        return 'silent'


class MasterWatch:
    """Probes the master every `every` s in a thread of its own; `lost()` says why it counts as
    gone ('' while it answers or has been silent or refusing for less than the limits)."""

    def __init__(self, uri: Optional[str] = None, every: float = 0.5, timeout: float = 1.0,
                 silence: Optional[float] = None, refused: Optional[float] = None) -> None:
        self.uri = uri or master_uri()
        self.every, self.timeout = every, timeout
        self.silence = MASTER_SILENCE if silence is None else silence
        self.refused = MASTER_REFUSED if refused is None else refused
        now = time.monotonic()
        self.last_ok = now
        self.unrun = 0.0        # s since last_ok that this process did not run (UNRUN_SLACK)
        self.round_at = now     # when the last probe round ended
        self.state = 'ok'
        self.bad_since: Optional[float] = None   # when the current run of 'refused' answers began
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._loop, daemon=True, name='master-watch')
        self._thread.start()

    def _loop(self):
        while not self._stop.is_set():
            state = master_state(self.uri, self.timeout)
            now = time.monotonic()
            self.unrun += self._not_run(now)
            self.round_at = now
            if state == 'ok':
                self.last_ok, self.bad_since, self.unrun = now, None, 0.0
            elif state == 'refused':
                self.bad_since = self.bad_since or now
            else:
                self.bad_since = None
            self.state = state
            self._stop.wait(self.every)

    def _not_run(self, now: float) -> float:
        """Of the time since the last probe round ended, what no round can take: this process
        did not run (UNRUN_SLACK)."""
        return max(0.0, now - self.round_at - self.every - 2 * self.timeout - UNRUN_SLACK)

    @property
    def answering(self) -> bool:
        return self.state == 'ok'

    def lost(self) -> str:
        now = time.monotonic()
        if self.state == 'refused' and self.bad_since is not None and now - self.bad_since >= self.refused:
            return 'the ROS master at %s went away' % self.uri
        # silent for `silence` s while this process ran: a stall of sensorTest is not the master's
        if now - self.last_ok - self.unrun - self._not_run(now) >= self.silence:
            return 'the ROS master at %s went away (no answer for %.0f s)' % (self.uri, now - self.last_ok)
        return ''

    def wait_answering(self, limit: float) -> bool:
        """Until the master answers (True) or it counts as gone or `limit` s pass (False)."""
        deadline = time.monotonic() + limit
        while not self.answering and not self.lost() and time.monotonic() < deadline:
            time.sleep(0.05)
        return self.answering

    def stop(self) -> None:
        self._stop.set()


class LiveSource:
    live = True
    """Subscribes a window (Listener) to its topic for the length of its window."""

    def __init__(self, caller_id: str = '/sensorTest') -> None:
        self.caller_id = caller_id
        self.subs: Dict[Listener, Any] = {}       # the window -> its rospy.Subscriber
        self._last_conn: Dict[Listener, float] = {}
        self.watch: Optional[MasterWatch] = None
        self.shutdown_reason: Optional[str] = None
        rospy.core.add_preshutdown_hook(self._on_shutdown)

    def _on_shutdown(self, reason):
        self.shutdown_reason = str(reason)

    @property
    def _master_ok(self):
        return self.watch is None or self.watch.answering

    def _check_master(self, force=False):
        if self.watch is None:
            self.watch = MasterWatch()
        reason = self.shutdown_reason
        if reason is not None:
            if 'same name' in reason:
                raise SourceLost('another node named %s started on this master, which shut this run '
                                 'down (one node per name: run without --node-name/__name:= to get a '
                                 'unique name)' % self.caller_id)
            raise SourceLost('the ROS node was shut down: %s' % reason)
        lost = self.watch.lost()
        if lost:
            raise SourceLost(lost)
        if force and not self.watch.wait_answering(self.watch.silence):
            raise SourceLost(self.watch.lost() or 'the ROS master at %s does not answer' % self.watch.uri)

    def attach(self, run: Listener) -> None:
        self._check_master(force=True)   # registering waits for the master
        if not run.listens:
            return

        me = rospy.get_name()

        def callback(msg, run=run):
            conn = msg._connection_header    # type, message_definition, callerid, md5sum
            if conn.get('callerid') == me:   # never judge this node's own messages (/diagnostics)
                return
            with handling.measured() as own:     # how late this process handles it
                run.feed_raw(conn.get('type', '?'), msg._buff, own.t0, rospy.get_rostime().to_sec(), conn, own)

        if not rospy.rostime.is_wallclock():   # /use_sim_time: rates and windows on /clock
            run.use_sim_clock(lambda: rospy.get_rostime().to_sec())
        self.subs[run] = rospy.Subscriber(run.topic, rospy.AnyMsg, callback,
                                          queue_size=run.queue_size,
                                          buff_size=run.buff_size)

    def detach(self, run: Listener) -> None:
        sub = self.subs.pop(run, None)
        self._last_conn.pop(run, None)
        if sub is None:
            return
        if self._master_ok:
            sub.unregister()
        else:   # unregistering waits for the master: never in the listening loop
            threading.Thread(target=sub.unregister, daemon=True, name='unregister').start()

    def poll(self, run: Listener, now: float) -> None:
        self._check_master()
        sub = self.subs.get(run)
        if sub is not None and now - self._last_conn.get(run, 0.0) >= 0.25:
            self._last_conn[run] = now
            run.observe_connections(_other_connections(sub), now)

    @property
    def graph_words(self) -> Optional[Graph]:
        return ros1_graph(master_uri())

    def _publishers(self) -> Dict[str, List[str]]:
        """Topic -> the nodes publishing it other than this one (one getSystemState). This node
        publishes its own statuses on /diagnostics (outputs/diagnostics.py), robotHealth's
        topic: counted, it made /diagnostics always "published", with no driver at all."""
        pubs, _, _ = rosgraph.Master(self.caller_id).getSystemState()
        out: Dict[str, List[str]] = {}
        for topic, nodes in pubs:
            others = sorted(n for n in nodes if n != self.caller_id)
            if others:
                out[topic] = others
        return out

    def published_topics(self) -> Optional[Set[str]]:
        """The set of topics with a publisher other than this node (one question to the
        master), or None when the master does not answer it."""
        if not self._master_ok:
            return None
        try:
            return set(self._publishers())
        except Exception:  # the master may have gone between probe and call
            return None

    def lookup(self, topic: str) -> Optional[TopicInfo]:
        """(advertised type or None, [publisher node names other than this node]) of a topic,
        or None if unknown."""
        if not self._master_ok:
            return None
        try:
            types = dict(rosgraph.Master(self.caller_id).getTopicTypes())
            return types.get(topic), self._publishers().get(topic, [])
        except Exception:  # the master may have gone between probe and call
            return None

    @staticmethod
    def sleep(dt: float) -> None:
        time.sleep(dt)
