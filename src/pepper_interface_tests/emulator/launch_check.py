"""Launch-file helper: fail a roslaunch early, with a clear message, when ROS packages are missing.

Used by launch/include/require_packages.xml as a `<param command="...">`, which roslaunch runs
while it parses the launch file (also for `roslaunch --nodes`):

    python3 -m pepper_interface_tests.emulator.launch_check PKG[,PKG...] [--launch NAME]
            [--fix TEXT]

Prints `pkg=path` lines (the param's value) and exits 0 when every package is found by rospack;
otherwise prints which are missing and how to proceed on stderr and exits 1, which makes
roslaunch stop before it starts anything.
"""
import argparse
import sys
from typing import Dict, Iterable, List, Optional, Sequence, Tuple


def find_packages(names: Iterable[str]) -> Tuple[Dict[str, str], List[str]]:
    import rospkg
    rospack = rospkg.RosPack()
    found, missing = {}, []
    for name in names:
        try:
            found[name] = rospack.get_path(name)
        except rospkg.ResourceNotFound:
            missing.append(name)
    return found, missing


def main(argv: Optional[Sequence[str]] = None) -> int:
    p = argparse.ArgumentParser(prog='launch_check')
    p.add_argument('packages', help='comma-separated ROS package names')
    p.add_argument('--launch', default='this launch file')
    p.add_argument('--fix', default='')
    a = p.parse_args(argv)
    names = [n.strip() for n in a.packages.split(',') if n.strip()]
    found, missing = find_packages(names)
    if missing:
        sys.stderr.write(
            '\n%s: missing ROS package%s: %s (rospack cannot find %s on ROS_PACKAGE_PATH).\n'
            '  fix: install %s, then source the setup.bash of the workspace%s\n\n'
            % (a.launch, 's' if len(missing) > 1 else '', ', '.join(missing),
               'them' if len(missing) > 1 else 'it', 'them' if len(missing) > 1 else 'it',
               ('; ' + a.fix) if a.fix else ''))
        sys.stderr.flush()
        return 1
    sys.stdout.write(' '.join('%s=%s' % kv for kv in found.items()))
    return 0


if __name__ == '__main__':
    sys.exit(main())
