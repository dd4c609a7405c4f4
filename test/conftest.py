import os
import subprocess
import sys
import time

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, 'helpers'))   # the test helpers: fake_pepper, rosmaster, ...
from rosmaster import Master, script  # noqa: E402

# ---------------------------------------------------------------- test tiers
# Every test gets exactly one of the markers declared in pytest.ini, decided here by file and
# fixture so tests added later are classified too (an explicit marker on a test wins). Files are
# named by their path under test/ (the tree mirrors src/pepper_interface_tests/):
#   slow         SLOW_FILES, SLOW_TESTS: a real browser (headless Chromium), a soak, a 240 MB bag;
#                `make test` runs them
#   integration  a test using a ROS fixture (a real roscore) or in INTEGRATION_FILES (every test
#                there starts real processes: sensorTest, the emulator, ffmpeg, rostest,
#                websockets, libqi)
#   unit         the rest: pure functions on in-memory data and tmp files, no master
# `make test-fast` runs `-m unit` (the unit tier must stay under UNIT_BUDGET_CPU_S of CPU, below).
TIERS = ('unit', 'integration', 'slow')
ROS_FIXTURES = {'master', 'module_master', 'recorded_bags'}
SLOW_FILES = {'outputs/report/test_page.py'}
SLOW_TESTS = {'test_chain_60s_realtime_no_lost_buffer',     # 60 s soak of the audio chain
              'test_a_large_bag_is_streamed_not_loaded'}    # a 240 MB bag written and streamed
INTEGRATION_FILES = {
    'audio_bridge/test_audio_bridge.py', 'audio_bridge/test_capture_py27.py', 'sources/test_bag.py',
    'emulator/test_bags.py', 'outputs/test_diagnostics_topic.py',
    'sources/test_ros2_bags.py',
    'outputs/test_files_hostile.py', 'sensors/test_driver_semantics.py', 'emulator/test_emulator_node.py',
    'emulator/test_emulator_cli.py', 'test_node.py', 'emulator/test_fake_naoqi.py',
    'emulator/test_golden_recordings.py', 'emulator/test_golden_recordings2.py',
    'motion/test_recorded.py',
    'outputs/test_history.py', 'launch/test_launch_files.py', 'emulator/test_naoqi_endpoint.py',
    'media/test_recording.py',
    'test_rostest.py',
    'plan/test_selection.py', 'test_cli.py', 'test_interrupts.py', 'sensors/test_clock.py',
    'test_rosmaster.py', 'outputs/test_drift_emulator.py', 'test_demo.py', 'tools/test_gates.py',
    'sensors/test_tf_recordings.py', 'sources/test_bag_chunks.py', 'sources/test_mcap_chunks.py'}
# tests that start real processes without a ROS fixture, in files that are otherwise unit; and the
# simulator's laser as its driver publishes it (in the integration tier with the other drivers'
# semantics, sensors/test_driver_semantics.py)
INTEGRATION_TESTS = {'sensors/test_audio.py': ('real_topic',),
                     # every /tf of a real driver's golden bag, read by rosbag (1.3 s of CPU)
                     'sensors/test_tf_layout.py': ('real_drivers_tf',),
                     'sensors/test_laser.py': ('test_simulator_laser_',
                                               'test_robot_layout_is_not_applied_to_the_simulator'),
                     # gates that parse every file of the tree, as ruff and mypy do (make test runs
                     # them with the gates; 4.4 s of the unit tier's CPU, issue 45)
                     'docs/test_node_api.py': ('every_module_that_talks_to_ros_has_an_owner',),
                     'sensors/test_families.py': ('no_family_is_told_apart_by_a_string_test',),
                     'plan/test_declaration.py': ('no_list_of_sensor_names_is_kept_by_hand',)}


def tier_path(path):
    """A test file's name in the lists above: its path under test/, with '/' on every system."""
    return os.path.relpath(str(path), HERE).replace(os.sep, '/')


def tier_of(item):
    own = [t for t in TIERS if item.get_closest_marker(t)]
    if own:
        return own[0]
    name = tier_path(item.fspath)
    if name.startswith('ros2/'):     # real rclpy processes on a DDS domain: the ROS 2 tier
        return 'integration'
    if name in SLOW_FILES or item.originalname in SLOW_TESTS:
        return 'slow'
    words = INTEGRATION_TESTS.get(name, ())
    if (name in INTEGRATION_FILES or ROS_FIXTURES & set(getattr(item, 'fixturenames', ()))
            or any(w in item.name.lower() for w in words)):
        return 'integration'
    return 'unit'


def pytest_ignore_collect(collection_path, config):
    """`-m unit` does not even import the files whose every test is integration or slow (rosbag,
    rospy, websockets and cv2 at their top would cost the unit tier a second of collection).
    test/ros2/ is the ROS 2 tier's (tools/ros2/tests.sh): collected only in a ROS 2 environment."""
    name = tier_path(collection_path)
    if name.startswith('ros2/') and os.environ.get('ROS_VERSION') != '2':
        return True
    if config.getoption('markexpr') == 'unit' and name in INTEGRATION_FILES | SLOW_FILES:
        return True
    return None


def pytest_collection_modifyitems(config, items):
    for item in items:
        tier = tier_of(item)
        if not item.get_closest_marker(tier):
            item.add_marker(getattr(pytest.mark, tier))


# The unit tier's budget is CPU time, not wall time: its tests are pure computation, and their
# wall time grows with whatever else the machine runs (the full suite's two other xdist workers
# start roscores, emulators and browsers next to them: the tier's 1.5 s read 3 s and more there,
# and 20 s on a machine shared by four test runs). The CPU time of the test process during
# setup, call and teardown is what the tests themselves cost; it is measured in the process
# that runs the test (an xdist worker too) and carried to the summary in the report.
# The budget: the ~500 unit tests took 3.9-4.9 s of CPU on the 2-core test machine at a load
# of 2.5 and 4.1-5.7 s at a load of 8 (contention inflates CPU time too, less than wall time);
# 3.5 s of it in the tests' own calls, the rest pytest's setup (tmp_path and the like). 8 s is
# above all of that, so "OVER BUDGET" appears when the tests themselves grow, not with the load.
UNIT_BUDGET_CPU_S = 8.0
_unit_cpu = []
_unit_wall = []


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_setup(item):
    t0 = time.process_time()
    yield
    item._cpu_s = time.process_time() - t0


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_call(item):
    t0 = time.process_time()
    yield
    item._cpu_s = getattr(item, '_cpu_s', 0.0) + time.process_time() - t0


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_teardown(item, nextitem):
    t0 = time.process_time()
    yield
    item._cpu_s = getattr(item, '_cpu_s', 0.0) + time.process_time() - t0


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    if call.when == 'teardown':
        outcome.get_result().user_properties.append(('cpu_s', getattr(item, '_cpu_s', 0.0)))


def pytest_runtest_logreport(report):
    if 'unit' in report.keywords:
        _unit_wall.append(report.duration)
        _unit_cpu.extend(v for k, v in report.user_properties if k == 'cpu_s')


def pytest_terminal_summary(terminalreporter):
    """The unit tier's own cost: CPU time of its tests against the budget (wall time beside)."""
    if _unit_cpu:
        cpu = sum(_unit_cpu)
        terminalreporter.write_line(
            'unit tier: %.2f s of CPU in its tests (budget %g s), %.2f s of wall time%s'
            % (cpu, UNIT_BUDGET_CPU_S, sum(_unit_wall),
               '' if cpu <= UNIT_BUDGET_CPU_S else ': OVER BUDGET, see --durations=20'))


# A unit test starts no process (issue 45: test_watch's demo and test_motion's lost master,
# 25 s and 7 s of wall time, had put the unit tier over its budget): an audit hook (Python 3.8+,
# PEP 578) sees every process start of the test process (subprocess, os.posix_spawn, os.fork,
# os.exec*, os.system), and a unit test that started one fails in its teardown, named, with the
# fix: its tier is integration (INTEGRATION_FILES, INTEGRATION_TESTS or @pytest.mark.integration).
PROCESS_EVENTS = {'subprocess.Popen', 'os.posix_spawn', 'os.fork', 'os.forkpty', 'os.exec',
                  'os.spawn', 'os.system', 'pty.spawn'}
# Started by a library, not by the test: matplotlib runs fc-list once per machine to build its
# font cache (font_manager._get_fontconfig_fonts), in whichever test draws the first figure.
NOT_THE_TESTS = {'fc-list'}
_started = {'watching': False, 'what': []}


def _audit(event, args):
    if _started['watching'] and event in PROCESS_EVENTS:
        what = args[1] if event == 'subprocess.Popen' and len(args) > 1 else args[:1] if args else ()
        if event == 'subprocess.Popen' and what and os.path.basename(str(list(what)[0])) in NOT_THE_TESTS:
            return
        _started['what'].append('%s %s' % (event, str(what)[:160]))


sys.addaudithook(_audit)


@pytest.fixture(autouse=True)
def _unit_tests_start_no_process(request):
    unit = request.node.get_closest_marker('unit') is not None
    _started['what'] = []
    _started['watching'] = unit
    try:
        yield
    finally:
        _started['watching'] = False
    if unit and _started['what']:
        pytest.fail('a unit test started %d process(es) (%s): the unit tier is pure computation; mark it '
                    'integration (test/conftest.py INTEGRATION_FILES or INTEGRATION_TESTS, or '
                    '@pytest.mark.integration)' % (len(_started['what']), '; '.join(_started['what'][:3])),
                    pytrace=False)


@pytest.fixture
def master():
    """A fresh real roscore on a free port for one test."""
    with Master() as m:
        yield m


@pytest.fixture(scope='module')
def module_master():
    """One real roscore shared by the tests of a module."""
    with Master() as m:
        yield m


BAG_SECONDS = 5.0


@pytest.fixture(scope='session')
def recorded_bags(tmp_path_factory):
    """The bags of recordTestBags (robot/simulator, good/faulty, ...), recorded once per session
    from the emulator with its own roscore: {variant name: path}. Under pytest-xdist the workers
    share one recording (the first to take the lock records, the others read the same files):
    recording runs seven emulators, and doing it once per worker loaded the machine twice."""
    import fcntl
    root = tmp_path_factory.getbasetemp()
    if os.environ.get('PYTEST_XDIST_WORKER'):
        root = root.parent                    # the session's folder, shared by its workers
    out_dir = root / 'recorded-bags'
    with open(str(root / 'recorded-bags.lock'), 'w') as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not (out_dir / 'complete').exists():
            out_dir.mkdir(exist_ok=True)
            run = subprocess.run(script('recordTestBags') + ['--out', str(out_dir), '--seconds', str(BAG_SECONDS)],
                                 stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
            assert run.returncode == 0, run.stdout
            (out_dir / 'complete').write_text('recordTestBags ended with 0\n')
    return {name[:-4]: str(out_dir / name) for name in os.listdir(str(out_dir)) if name.endswith('.bag')}
