"""sensorTest's command line: options -> plan -> run -> outputs -> exit code.

Exit codes: 0 every selected sensor passed (SKIPPED counts as passed), 1 at least one failed,
2 the run could not start (bad files or options, no ROS master, unwritable output folder),
3 a results file could not be written (named on stderr), 130 interrupted (Ctrl-C, SIGTERM,
SIGHUP, master gone, node replaced; the output files are still written). Signal policy:
interrupts.py.

The node is named /sensorTest_<pid>_<ms> (anonymous) unless --node-name or __name:= fixes it:
two runs on one master never replace each other. Private params given as `_name:=value` on
the command line are deleted from the parameter server when the run ends.
"""
import argparse
import os
import sys
import tempfile
import time
from typing import Any, Callable, Dict, List, Optional

from . import interrupts, results
from .outputs.terminal import HelpFormatter
from .plan import options, settings
from .plan.options import Options
from .plan.settings import ConfigError, TestPlan
from .results import EXIT_CANNOT_START
from .sensors.families import traits
from .sources import Source

EPILOG = '''examples:
  rosrun pepper_interface_tests sensorTest
  rosrun pepper_interface_tests sensorTest --mode parallel --quick
  rosrun pepper_interface_tests sensorTest --sensors laser,frontSonar
  rosrun pepper_interface_tests sensorTest --platform simulator --duration 5
  rosrun pepper_interface_tests sensorTest --bag recorded.bag
  rosrun pepper_interface_tests sensorTest _mode:=parallel _duration:=3
      (options as private ROS params)
''' + ('exit codes: 0 all passed, 1 a sensor failed (also when no sensor topic has a publisher at all: '
       'said once, within --wait), 2 could not start, 3 a results file not written, 130 interrupted')


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        self.print_usage(sys.stderr)
        sys.stderr.write('sensorTest: error: %s\n' % message)
        sys.exit(EXIT_CANNOT_START)


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog='sensorTest', description='Check every sensor of a Pepper robot and report '
                'a verdict per sensor.', epilog=EPILOG, formatter_class=HelpFormatter)
    options.add_arguments(p)
    return p


def check_output_dir(path: str) -> None:
    try:
        os.makedirs(path, exist_ok=True)
        fd, probe = tempfile.mkstemp(prefix='.write-test-', dir=path)
        os.close(fd)
        os.remove(probe)
    except OSError as e:
        raise ConfigError('cannot write results to %s: %s' % (path, e.strerror or e),
                          fix='choose a writable folder with --output-dir (or ~output_dir)') from None


def _fatal(message):
    sys.stderr.write('sensorTest: error: %s\n' % message)
    return EXIT_CANNOT_START


def _debug_line(text):
    sys.stderr.write('[debug] %s\n' % text)


def main(argv: Optional[List[str]] = None) -> int:
    # Ctrl-C, SIGTERM and SIGHUP end the run cleanly, also when started with SIGINT ignored
    # (background jobs of a non-interactive shell inherit that); a broken stdout/stderr is ignored
    from .outputs.terminal import protect_std_streams
    protect_std_streams()
    interrupts.POLICY.install()
    ros_args: List[str] = []
    from .sources.live2 import ros_version
    if ros_version() == 2:      # ROS 2: `--ros-args ...` is rclpy's
        from .ros2run import split_ros_args
        argv, ros_args = split_ros_args(sys.argv[1:] if argv is None else argv)
    elif argv is None:
        import rospy
        argv = rospy.myargv(sys.argv)[1:]
    try:
        code = _main(argv, ros_args)
    except KeyboardInterrupt:
        sys.stderr.write('sensorTest: %s before listening began; nothing written\n'
                         % interrupts.POLICY.reason())
        code = results.EXIT_INTERRUPTED
    if '--end-launch' in argv:     # launch files: see launch/end.py
        from .launch.end import end_launch
        end_launch(code)
    return code


def _main(argv, ros_args=None):
    try:
        ns = build_parser().parse_args(argv)
        cli = options.from_args(ns)
    except ConfigError as e:
        return _fatal(str(e))
    plan: Optional[TestPlan] = None
    plan_error: Optional[ConfigError] = None
    try:
        plan = settings.load_plan(cli)
    except ConfigError as e:
        if cli.bag:
            return _fatal(str(e))
        plan_error = e   # private ROS params may still set it right: see run_live
    interrupts.pause('start-up')
    try:
        if plan is not None and isinstance(cli.baseline, str):
            _baseline(plan)         # a run that cannot serve is refused before any master is sought
        if cli.bag:
            assert plan is not None     # a bag's plan error ended the run above
            return run_bag(plan, cli.bag, cli)
        from .sources.live2 import ros_version
        if ros_version() == 2:
            from .ros2run import run_live2
            return run_live2(cli, ros_args, execute, check_output_dir)
        return run_live(plan, cli, plan_error, node_name=ns.node_name)
    except ConfigError as e:
        return _fatal(str(e))


def _baseline(plan: TestPlan, robot: str = '') -> Any:
    """The run's baseline comparison (outputs/baseline.py) and its note; ConfigError (exit 2)
    when --baseline names a run that is not there or cannot serve."""
    from .outputs import baseline
    from .outputs.history import HistoryError
    try:
        return baseline.for_run(plan.output_dir, plan.options.baseline, plan.platform, robot)
    except HistoryError as e:
        raise ConfigError('--baseline: %s' % e, fix='pin a run where every sensor passed (sensorTestHistory '
                          'baseline set RUN), or run with --no-baseline') from None


def run_live(plan: Optional[TestPlan], cli: Options, plan_error: Optional[ConfigError] = None,
             node_name: Optional[str] = None) -> int:
    from .sources import live
    uri = live.master_uri()
    if plan_error is not None and not live.master_reachable(uri, timeout=1.0):
        raise plan_error    # no master: no private params that could change the files either
    deadline = time.monotonic() + 4.0
    while not live.master_reachable(uri, timeout=1.0):
        if time.monotonic() > deadline:
            raise ConfigError('no ROS master at %s' % uri,
                              fix='start roscore (or roslaunch), or point ROS_MASTER_URI at the robot\'s master')
        time.sleep(0.25)
    import rospy

    from . import node
    rospy.init_node(node_name or 'sensorTest', anonymous=not node_name, disable_signals=True)
    try:
        params, from_server = node.read_params(options.from_params)
        if any(v is not None for v in params.__dict__.values()):
            plan = settings.load_plan(params.merged(cli))
        elif plan_error is not None:
            raise plan_error
        assert plan is not None     # loaded by _main or just now, else its error was raised
        check_output_dir(plan.output_dir)
        source = live.LiveSource(rospy.get_name())
        from_server = {k: v for k, v in from_server.items() if getattr(cli, k, None) is None}
        robot = None
        if plan.platform == 'robot':     # the simulator has no serial number to read
            from .sources import identity
            robot = identity.read_live(rospy.get_name())
        return execute(plan, source, time.monotonic, 'live', from_server, robot)
    finally:
        node.forget_own_params()
        # rospy's shutdown first unregisters the node from the master (its hooks), then joins
        # its threads and sleeps (~0.6 s): wait for the first part only
        import threading
        done = threading.Thread(target=rospy.signal_shutdown, args=('sensorTest finished',),
                                daemon=True)
        done.start()
        done.join(0.25)


def run_bag(plan: TestPlan, bag: str, cli: Options) -> int:
    """Check the recorded bag `bag` (the --bag of `cli`) against the plan."""
    from .sources.ros2bag import Ros2BagSource, open_recording
    source = open_recording(bag)
    notes = list(source.notes)    # e.g. records at bogus times left out of the window
    if isinstance(source, Ros2BagSource):    # naoqi_driver2's topics and driver profile
        from .sources.ros2plan import recording_plan
        names = [s.name for s in plan.sensors
                 if s.skip_reason is None and not traits(s.sensor).drives_itself]
        try:
            plan, picked = recording_plan(plan, cli, source, names)
        except ConfigError:
            source.close()
            raise
        notes += picked
    # a bag is checked as a whole, every topic at once, from its start to its end
    duration = cli.duration if cli.duration is not None else max(source.length + 0.2, 0.2)
    active = []
    for s in plan.sensors:
        if s.skip_reason is None and traits(s.sensor).live_only:
            s = settings.SensorPlan(s.sensor, s.topic, s.expect, 'not checked from a bag (needs a live robot)')
        active.append(s)
    plan = settings.replace(plan, mode='parallel', duration=duration, sensors=tuple(active))
    if not cli.topics:            # the wrong platform: suggest the other one when it fits
        from .sources.bag import platform_hint
        other = 'simulator' if plan.platform == 'robot' else 'robot'
        try:
            listened = [s.topic for s in plan.sensors
                        if s.skip_reason is None and s.topic is not None and not traits(s.sensor).drives_itself]
            hint = platform_hint(plan, listened, source.types, settings.load_plan(
                settings.replace(cli, platform=other, sensors=None, cameras=None, rerun_failed=None)))
        except ConfigError:
            hint = None
        notes += [hint] if hint else []
    for note in notes:
        print('sensorTest: note: %s: %s' % (bag, note), flush=True)
    try:
        check_output_dir(plan.output_dir)
        return execute(plan, source, source.clock, os.path.abspath(bag))
    finally:
        source.close()


def execute(plan: TestPlan, source: Source, clock: Callable[[], float], source_name: str,
            param_sources: Optional[Dict[str, str]] = None, robot: Any = None) -> int:
    """Run the plan against a source and write every output; returns the exit code.
    From here on interrupts are deferred until every output exists (interrupts.py)."""
    interrupts.POLICY.raise_pending()     # one swallowed during start-up: nothing written yet
    interrupts.POLICY.phase = 'defer'
    interrupts.pause('run-folder')
    from .outputs import observers
    from .outputs.history import RunFolder
    from .outputs.terminal import Terminal
    from .runner import Runner
    from .sensors.base import RunContext
    if robot is None and plan.platform == 'robot' and source_name != 'live':
        from .sources import identity  # a recording does not say which robot made it
        robot = identity.unknown('a recording does not name its robot')
    robot_id = robot.body_id if robot is not None else ''
    compare, note = _baseline(plan, robot_id)   # --baseline's run (refused: exit 2), else the pinned one
    if note:
        print('sensorTest: note: %s' % note, flush=True)
    try:   # every run gets an id and, unless --no-history, its own folder <output_dir>/runs/<id>
        folder = RunFolder.create(plan.output_dir, keep=plan.options.history is not False)
    except OSError as e:
        raise ConfigError('cannot create a run folder in %s: %s' % (plan.output_dir, e.strerror or e),
                          fix='choose a writable folder with --output-dir, or run with --no-history') from None
    plan = settings.replace(plan, output_dir=folder.path)
    ctx = RunContext(plan.output_dir, plan.platform, plan.options, topics=plan.topics)
    if plan.options.debug:
        ctx.services.debug = _debug_line
    watchers = observers.observers_for(plan, ctx, source_name, folder)
    first = [compare] if compare is not None else []     # drift on each result before any output sees it
    runner = Runner(plan, ctx, source, observers=first + [Terminal()] + watchers, clock=clock,
                    signals=interrupts.POLICY)
    runner.run.run_id = folder.run_id
    runner.run.source = source_name
    runner.run.options = {k: v for k, v in plan.options.__dict__.items() if v is not None}
    runner.run.param_sources = dict(param_sources or {})
    if robot is not None:
        runner.run.robot, runner.run.robot_info = robot_id, robot.to_dict()
    run = runner.execute()
    if interrupts.POLICY.pending and not run.interrupted:
        sys.stderr.write('sensorTest: the interrupt came while the results were written: they are '
                         'complete; exit code %d as in %s\n' % (run.exit_code, results.JSON_FILE))
    if run.write_errors:
        sys.stderr.write('sensorTest: error: %d results file%s not written (exit %d): %s\n'
                         % (len(run.write_errors), '' if len(run.write_errors) == 1 else 's',
                            run.exit_code, '; '.join(run.write_errors)))
    return run.exit_code
