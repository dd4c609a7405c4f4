"""NAOqi-to-ROS audio bridge: capture side (``capture``, Python 2.7/3), wire format (``frame``)
and the ROS publisher (``publisher``, Python 3). See docs/audio-bridge.md.

This file also holds the small helpers both sides and the emulator's NAOqi endpoint share (a
log rate limiter, a one-line usage-error parser, a TCP port argument, dropping roslaunch's
remapping arguments); it stays Python 2.7 compatible because the capture side imports it: its
signatures are type comments, which mypy checks and Python 2.7 ignores.
"""
import argparse
import io
import os
import stat
import threading
import time

MYPY = False
if MYPY:    # read by mypy only: the robot's Python 2.7 has no typing module
    from typing import Callable, Dict, List, Mapping, NoReturn, Optional, Sequence, Tuple, Union  # noqa: F401  # novm

# Where both sides take the shared websocket token from, best first. The file is the way under
# roslaunch: roslaunch writes every process's whole environment into its log file
# (ros_comm 1.15 roslaunch/nodeprocess.py:152, create_node_process:
# _logger.info('process[%s]: env[%s]', ...)), and command lines are visible in ``ps``.
TOKEN_FILE_ENV = 'PEPPER_AUDIO_TOKEN_FILE'
TOKEN_ENV = 'PEPPER_AUDIO_TOKEN'


class RateLimiter(object):
    """Lets at most one report per key through every ``interval`` seconds and counts the rest.

    ``hit(key)`` counts one event and returns how many events (this one included) the caller
    should report now, or 0 while the key is muted.
    """

    def __init__(self, interval=5.0, clock=time.time):
        # type: (float, Callable[[], float]) -> None
        self.interval = interval
        self._clock = clock
        self._last = {}  # type: Dict[str, float]
        self._pending = {}  # type: Dict[str, int]
        self._lock = threading.Lock()

    def hit(self, key):
        # type: (str) -> int
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
        # type: (str) -> NoReturn
        self.exit(2, '%s: error: %s (see --help)\n' % (self.prog, message))


class PortError(argparse.ArgumentTypeError, ValueError):
    """Not a TCP port: argparse reports it as a usage error; elsewhere it is a ValueError."""


def port_arg(value):
    # type: (Union[str, int]) -> int
    """A TCP port number (1..65535) from a command-line or param value; PortError otherwise."""
    try:
        port = int(value)
    except (TypeError, ValueError):
        port = -1
    if not 1 <= port <= 65535:
        raise PortError('port %r is not a TCP port (1..65535)' % (value,))
    return port


def listen_port_arg(value):
    # type: (Union[str, int]) -> int
    """A port a server binds: 0 (any free port, chosen by the system) or 1..65535."""
    if str(value).strip() == '0':
        return 0
    return port_arg(value)


class TokenError(ValueError):
    """The token file cannot be used; the message names it and the fix."""


def read_token(cli_token=None, cli_file=None, environ=None):
    # type: (Optional[str], Optional[str], Optional[Mapping[str, str]]) -> Tuple[str, Optional[str], Optional[str]]
    """(token, where it came from, warning or None). Order: --token, --token-file,
    $PEPPER_AUDIO_TOKEN_FILE, $PEPPER_AUDIO_TOKEN; ('', None, None) when none is set."""
    environ = os.environ if environ is None else environ
    if cli_token:
        return cli_token, '--token', ('--token puts the token on the command line, visible in '
                                      'ps; use $%s instead' % TOKEN_FILE_ENV)
    path = cli_file or environ.get(TOKEN_FILE_ENV, '')
    if path:
        where = '--token-file' if cli_file else '$' + TOKEN_FILE_ENV
        try:
            with io.open(path, encoding='utf-8') as f:
                token = f.read().strip()
            mode = os.stat(path).st_mode
        except (IOError, OSError, UnicodeError) as exc:
            raise TokenError('cannot read the token file %s (%s): %s; fix: write the token '
                             'into it, readable by this user only (chmod 600)'
                             % (path, where, getattr(exc, 'strerror', None) or exc))
        if not token:
            raise TokenError('the token file %s (%s) is empty; fix: write the token into it'
                             % (path, where))
        warning = None
        if mode & (stat.S_IRGRP | stat.S_IROTH):
            warning = 'the token file %s is readable by other users; fix: chmod 600 %s' % (
                path, path)
        return token, where, warning
    token = environ.get(TOKEN_ENV, '')
    return token, ('$' + TOKEN_ENV) if token else None, None


def without_remappings(argv):
    # type: (Sequence[str]) -> List[str]
    """Drop the ROS remapping arguments roslaunch adds to every node (__name:=x, __log:=y)."""
    return [a for a in argv if ':=' not in a]
