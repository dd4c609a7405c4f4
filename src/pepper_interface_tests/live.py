"""The live data source: rospy.AnyMsg subscriptions feeding SensorRuns, and master look-ups.

AnyMsg lets a subscription accept whatever type a topic really carries, so a topic advertised
with the wrong type is reported by name instead of being refused silently by rospy's md5 check.
The master is probed with a short TCP connect before anything that would make rospy wait for it
forever (rospy retries registrations until the master comes back).
"""
import socket
import time
import xmlrpc.client
from urllib.parse import urlparse

import rosgraph
import rospy

from .runner import SourceLost

MASTER_TIMEOUT = 2.0


def master_uri():
    return rosgraph.get_master_uri()


def master_reachable(uri=None, timeout=MASTER_TIMEOUT):
    """True when the ROS master answers getPid within `timeout` seconds."""
    uri = uri or master_uri()
    parsed = urlparse(uri)
    try:
        with socket.create_connection((parsed.hostname, parsed.port or 11311), timeout=timeout):
            pass
    except OSError:
        return False

    class _Transport(xmlrpc.client.Transport):
        def make_connection(self, host):
            conn = super().make_connection(host)
            conn.timeout = timeout
            return conn

    try:
        code, _, _ = xmlrpc.client.ServerProxy(uri, transport=_Transport()).getPid('/sensorTest')
        return code == 1
    except (OSError, xmlrpc.client.Error):
        return False


class LiveSource:
    """Subscribes a SensorRun to its topic for the length of its window."""

    def __init__(self, caller_id='/sensorTest'):
        self.caller_id = caller_id
        self.subs = {}
        self._last_probe = 0.0
        self._master_ok = True
        self._last_conn = {}

    def _check_master(self, now, force=False):
        if force or now - self._last_probe >= 1.0:
            self._last_probe = now
            self._master_ok = master_reachable(timeout=1.0)
        if not self._master_ok:
            raise SourceLost('the ROS master at %s went away' % master_uri())

    def attach(self, run):
        self._check_master(time.monotonic(), force=True)
        if run.check.active:
            return

        def callback(msg, run=run):
            conn = msg._connection_header    # type, message_definition, callerid, md5sum
            run.feed_raw(conn.get('type', '?'), msg._buff,
                         time.monotonic(), rospy.get_rostime().to_sec(), conn)

        if not rospy.rostime.is_wallclock():   # /use_sim_time: rates and windows on /clock
            run.use_sim_clock(lambda: rospy.get_rostime().to_sec())
        self.subs[run] = rospy.Subscriber(run.plan.topic, rospy.AnyMsg, callback,
                                          queue_size=run.check.queue_size,
                                          buff_size=run.check.buff_size)

    def detach(self, run):
        sub = self.subs.pop(run, None)
        self._last_conn.pop(run, None)
        if sub is not None and self._master_ok:
            sub.unregister()

    def poll(self, run, now):
        self._check_master(now)
        sub = self.subs.get(run)
        if sub is not None and now - self._last_conn.get(run, 0.0) >= 0.25:
            self._last_conn[run] = now
            run.observe_connections(sub.get_num_connections(), now)

    def lookup(self, topic):
        """(advertised type or None, [publisher node names]) of a topic, or None if unknown."""
        if not self._master_ok:
            return None
        try:
            master = rosgraph.Master(self.caller_id)
            types = dict(master.getTopicTypes())
            pubs, _, _ = master.getSystemState()
            publishers = sorted(n for t, nodes in pubs if t == topic for n in nodes)
            return types.get(topic), publishers
        except Exception:  # the master may have gone between probe and call
            return None

    @staticmethod
    def sleep(dt):
        time.sleep(dt)
