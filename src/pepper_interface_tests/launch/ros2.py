"""What the ROS 2 launch files (launch/*.launch.py) share: a node that ends the launch with its
verdict, a node without which the launch cannot go on, a package the launch needs.

`ros2 launch` returns 0 however its nodes end: Humble's LaunchService.run_async returns 1 only
when an exception reached its loop (launch/launch_service.py, "Caught exception in launch"),
and then shuts every process down first. So sensorTest's end is turned into the launch's exit
status here: exit 0 shuts the launch down (exit 0), any other code raises LaunchEnded, which
the launch reports in one line and ends with exit 1, as sensorTestLaunch does on ROS 1 (0: every
row passed; 1: not, or no verdict). The launch's own exit status has no room for more: the
code itself (1 FAIL, 2 a bad option, 130 interrupted) is in that line and in the results.
"""
from typing import Any, List, Optional


class LaunchEnded(RuntimeError):
    """The launch ends with exit 1; the text is the one line `ros2 launch` prints."""


def _exit_code(event: Any) -> int:
    code = event.returncode
    return int(code) if code is not None else 1


def ends_launch(action: Any, name: str) -> Any:
    """An event handler: when `action` (sensorTest) exits, the launch ends with its verdict."""
    from launch.actions import EmitEvent
    from launch.event_handlers import OnProcessExit
    from launch.events import Shutdown

    def on_exit(event: Any, context: Any) -> List[Any]:
        code = _exit_code(event)
        if code == 0:
            return [EmitEvent(event=Shutdown(reason='%s passed (exit 0)' % name))]
        raise LaunchEnded('%s exited with code %d (%s); the launch exits 1' % (name, code, meaning(code)))
    return OnProcessExit(target_action=action, on_exit=on_exit)


def required(action: Any, name: str) -> Any:
    """An event handler: `action` ending with an error ends the launch (exit 1), naming it, as
    required="true" does on ROS 1; ending with 0 (Ctrl-C, SIGTERM) ends nothing."""
    from launch.event_handlers import OnProcessExit

    def on_exit(event: Any, context: Any) -> List[Any]:
        code = _exit_code(event)
        if code != 0:
            raise LaunchEnded('%s exited with code %d: the launch cannot go on without it (its '
                              'own message is above)' % (name, code))
        return []
    return OnProcessExit(target_action=action, on_exit=on_exit)


def start_when_up(emulator: Any, action: Any, ready: str = 'publishers up') -> Any:
    """An event handler: `action` (sensorTest) is started once `emulator` says `ready` on its
    output (pepperEmulator's "all N publishers up" line). Started together, sensorTest's
    windows began before the emulator's publishers existed: the tree had no /tf publisher when
    the run began and no sensor's frame was judged."""
    from launch.event_handlers import OnProcessIO
    started: List[bool] = []

    def on_output(event: Any) -> Optional[List[Any]]:
        if not started and ready in event.text.decode('utf-8', 'replace'):
            started.append(True)
            return [action]
        return None
    return OnProcessIO(target_action=emulator, on_stdout=on_output, on_stderr=on_output)


def meaning(code: int) -> str:
    """sensorTest's exit codes (docs/options.md)."""
    return {1: 'a row did not pass', 2: 'a bad option or input', 130: 'interrupted'}.get(
        code, 'ended by signal %d' % -code if code < 0 else 'no verdict')


def require_package(package: str, launch_file: str, fix: str) -> None:
    """Stop the launch at once, naming the missing package and the fix (require_packages.xml's
    role on ROS 1), instead of launch's own "package not found" deep inside an include."""
    from ament_index_python.packages import PackageNotFoundError, get_package_share_directory
    try:
        get_package_share_directory(package)
    except PackageNotFoundError:
        raise LaunchEnded('%s needs the ROS 2 package %s, which is not installed; fix: %s'
                          % (launch_file, package, fix)) from None


def flag(value: str, name: str) -> bool:
    """A launch argument that must be true or false."""
    if value.strip().lower() in ('true', '1', 'yes'):
        return True
    if value.strip().lower() in ('false', '0', 'no'):
        return False
    raise LaunchEnded('launch argument %s:=%s: expected true or false' % (name, value))
