"""sensorTest's ROS node: where its params come from, and what it leaves behind.

Params are read from the node's private namespace (~name: `_name:=value` on the command line,
<param> inside the node tag of a launch file) and, when the node name is the default unique one
(/sensorTest_<pid>_<ms>), also from /sensorTest/name (set with `rosparam set`), the private one
winning. Each value used is reported with its origin in the run header.

rospy writes `_name:=value` arguments to the parameter server, where they would stay after the
run and change every later run with the same node name: forget_own_params() deletes exactly those
when the run ends (params set by a launch file or by rosparam are left alone).
"""
import sys
import threading
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

import rospy

from .plan.options import Options

DEFAULT_NAMESPACE = '/sensorTest'


def command_line_params(argv: Optional[Sequence[str]] = None) -> List[str]:
    """Names given as `_name:=value` on the command line."""
    argv = sys.argv if argv is None else argv
    return [a.split(':=', 1)[0][1:] for a in argv[1:]
            if ':=' in a and a.startswith('_') and not a.startswith('__')]


def read_params(options_from_params: Callable[[Callable[..., Any]], Options]) -> Tuple[Options, Dict[str, str]]:
    """(Options, {name: origin}) from the parameter server: `options_from_params(get)` reads
    each param with `get(key, default)`, as rospy.get_param."""
    own = set(command_line_params())
    fallback = rospy.get_name() != DEFAULT_NAMESPACE and not _fixed_name()
    origins: Dict[str, str] = {}

    def get(key: str, default: Any = None) -> Any:
        name = key.lstrip('~')
        value = rospy.get_param(key, None)
        if value is not None and value != '':
            origins[name] = ('command line _%s:=' % name) if name in own \
                else 'parameter server %s' % rospy.resolve_name(key)
            return value
        if fallback:
            other = '%s/%s' % (DEFAULT_NAMESPACE, name)
            value = rospy.get_param(other, None)
            if value is not None and value != '':
                origins[name] = 'parameter server %s' % other
                return value
        return default

    return options_from_params(get), origins


def _fixed_name():
    return any(a.startswith('__name:=') or a.startswith('--node-name') for a in sys.argv)


def forget_own_params(timeout: float = 1.0) -> None:
    """Delete the `_name:=value` params of this run from the server (never waits more than
    `timeout` s: a stalled or vanished master must not hold the exit)."""
    names = command_line_params()
    if not names:
        return

    def delete():
        for name in names:
            try:
                rospy.delete_param('~' + name)
            except Exception:   # already gone, or the master went away
                pass

    t = threading.Thread(target=delete, daemon=True, name='forget-params')
    t.start()
    t.join(timeout)
