"""NAOqi-to-ROS audio bridge: capture side (``capture``, Python 2.7/3), wire format (``frame``)
and the ROS publisher (``publisher``, Python 3). See docs/audio-bridge.md.

This file also holds the small helpers both sides and the emulator's NAOqi endpoint share (a
log rate limiter, a one-line usage-error parser, a TCP port argument, dropping roslaunch's
remapping arguments); it stays Python 2.7 compatible because the capture side imports it.
"""
import argparse
import threading
import time


class RateLimiter(object):
    """Lets at most one report per key through every ``interval`` seconds and counts the rest.

    ``hit(key)`` counts one event and returns how many events (this one included) the caller
    should report now, or 0 while the key is muted.
    """

    def __init__(self, interval=5.0, clock=time.time):
        self.interval = interval
        self._clock = clock
        self._last = {}
        self._pending = {}
        self._lock = threading.Lock()

    def hit(self, key):
        now = self._clock()
        with self._lock:
            self._pending[key] = self._pending.get(key, 0) + 1
            last = self._last.get(key)
            if last is not None and now - last < self.interval:
                return 0
            self._last[key] = now
            count = self._pending.pop(key)
            return count


class OneLineParser(argparse.ArgumentParser):
    """argparse, but a usage error is one line on stderr (exit code 2), not the usage block."""

    def error(self, message):
        self.exit(2, '%s: error: %s (see --help)\n' % (self.prog, message))


class PortError(argparse.ArgumentTypeError, ValueError):
    """Not a TCP port: argparse reports it as a usage error; elsewhere it is a ValueError."""


def port_arg(value):
    """A TCP port number (1..65535) from a command-line or param value; PortError otherwise."""
    try:
        port = int(value)
    except (TypeError, ValueError):
        port = -1
    if not 1 <= port <= 65535:
        raise PortError('port %r is not a TCP port (1..65535)' % (value,))
    return port


def listen_port_arg(value):
    """A port a server binds: 0 (any free port, chosen by the system) or 1..65535."""
    if str(value).strip() == '0':
        return 0
    return port_arg(value)


def without_remappings(argv):
    """Drop the ROS remapping arguments roslaunch adds to every node (__name:=x, __log:=y)."""
    return [a for a in argv if ':=' not in a]
