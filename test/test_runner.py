"""The runner (runner.py): its lanes, and whole runs over a real bag file (order, parallel start,
interrupt, a failing observer)."""
import io
import json
import re
import xml.etree.ElementTree as ET

import genpy
import pytest
import rosbag

from check_runs import R0
from fake_pepper import laser, sonar
from pepper_interface_tests import results
from pepper_interface_tests.observer import RunObserver
from pepper_interface_tests.outputs.observers import ResultFiles
from pepper_interface_tests.outputs.terminal import Terminal
from pepper_interface_tests.plan import catalog, settings
from pepper_interface_tests.plan.settings import Options
from pepper_interface_tests.results import FAIL, PASS, SKIPPED
from pepper_interface_tests.runner import Runner, lanes_for
from pepper_interface_tests.sensors.base import RunContext
from pepper_interface_tests.sources.bag import BagSource


def _plan(tmp_path, platform, mode, sensors):
    d = tmp_path / 'files'
    d.mkdir(exist_ok=True)
    (d / 'config.ini').write_text('platform %s\nmode %s\n' % (platform, mode))
    (d / 'topics.dat').write_text(''.join('%s /%s\n' % (n, n) for n in catalog.SENSORS))
    return settings.load_plan(Options(config=str(d / 'config.ini'), topics=str(d / 'topics.dat'),
                                      sensors=tuple(sensors), output_dir=str(tmp_path / 'out'),
                                      duration=2, wait=1))


def test_lanes_sequential_is_one_lane_in_order(tmp_path):
    order = ['odometry', 'frontCamera', 'laser', 'backSonar']
    lanes = lanes_for(_plan(tmp_path, 'robot', 'sequential', order))
    assert [[s.name for s in lane] for lane in lanes] == [order]


def test_lanes_parallel_on_the_robot_one_per_sensor(tmp_path):
    order = ['frontCamera', 'laser', 'bottomCamera', 'depthCamera']
    lanes = lanes_for(_plan(tmp_path, 'robot', 'parallel', order))
    assert [[s.name for s in lane] for lane in lanes] == [[n] for n in order]


def test_lanes_parallel_in_the_simulator_cameras_share_one_lane(tmp_path):
    order = ['laser', 'frontCamera', 'backSonar', 'depthCamera', 'stereoCamera', 'bottomCamera']
    plan = _plan(tmp_path, 'simulator', 'parallel', order)
    lanes = [[s.name for s in lane] for lane in lanes_for(plan)]
    # scenario: the order above, not a list of the simulator's cameras
    assert lanes == [['laser'], ['frontCamera', 'depthCamera', 'bottomCamera'], ['backSonar'],
                     ['stereoCamera']]     # stereo is skipped in the simulator: its own lane


def write_bag(path, topics, seconds=8.0, rate=10.0, begin=R0):
    """topics: {topic: builder(i)}; messages recorded at `rate`, stamps 10 ms before recording."""
    with rosbag.Bag(str(path), 'w') as bag:
        for topic, build in topics.items():
            for i in range(int(seconds * rate)):
                t = begin + i / rate
                m = build(i)
                m.header.stamp = genpy.Time.from_sec(t - 0.01)
                bag.write(topic, m, genpy.Time.from_sec(t))
    return str(path)


class Interrupter(RunObserver):
    """An observer that presses Ctrl-C after `after` seconds of run time."""

    def __init__(self, after):
        self.after = after
        self.start = None

    def run_started(self, run, plan):
        self.start = None

    def tick(self, runs, now):
        self.start = now if self.start is None else self.start
        if now - self.start >= self.after:
            raise KeyboardInterrupt


class Broken(RunObserver):
    """An observer that fails: the run must go on."""

    def sensor_done(self, result):
        raise RuntimeError('observer failed')


def run_bag(tmp_path, mode, sensors, extra_observers=(), cameras=None):
    bag = write_bag(tmp_path / 'run.bag', {'/laser': laser, '/back': sonar})
    d = tmp_path / 'files'
    d.mkdir(exist_ok=True)
    (d / 'config.ini').write_text('platform robot\nmode %s\n' % mode)
    (d / 'topics.dat').write_text('Laser /laser\nBackSonar /back\nFrontSonar /front\n'
                                  'RealSenseCameraRGB /rs\n')
    out = tmp_path / 'out'
    out.mkdir(exist_ok=True)
    plan = settings.load_plan(Options(config=str(d / 'config.ini'), topics=str(d / 'topics.dat'),
                                      sensors=tuple(sensors), output_dir=str(out), duration=2,
                                      wait=1, cameras=cameras))
    source = BagSource(bag)
    ctx = RunContext(plan.output_dir, plan.platform, plan.options)
    term = io.StringIO()
    runner = Runner(plan, ctx, source, clock=source.clock,
                    observers=[Terminal(stream=term)] + list(extra_observers)
                    + [ResultFiles(str(out), out=io.StringIO())])
    run = runner.execute()
    return run, out, term.getvalue()


def test_runner_sequential_follows_the_given_order(tmp_path):
    run, out, term = run_bag(tmp_path, 'sequential', ['laser', 'realsenseRGBCamera', 'frontSonar', 'backSonar'],
                             cameras='pepper')
    r = {s.name: s for s in run.sensors}
    assert [s.name for s in run.sensors] == ['laser', 'realsenseRGBCamera', 'frontSonar', 'backSonar']
    assert (r['laser'].verdict, r['backSonar'].verdict) == (PASS, PASS), (r['laser'].reasons, r['backSonar'].reasons)
    assert r['realsenseRGBCamera'].verdict == SKIPPED
    assert r['frontSonar'].verdict == FAIL and r['frontSonar'].reasons == ['topic /front is not in the bag']
    # one after another, in this order, each a full window (bag time: exact)
    assert r['laser'].started_at == pytest.approx(0.0, abs=0.06)
    assert r['frontSonar'].started_at >= r['laser'].ended_at
    assert r['backSonar'].started_at >= r['frontSonar'].ended_at
    assert r['laser'].window_s == pytest.approx(2.0, abs=0.06)
    assert r['frontSonar'].window_s == pytest.approx(1.0, abs=0.06)      # --wait
    assert run.exit_code == results.EXIT_FAIL and not run.interrupted
    assert term.index('laser') < term.index('frontSonar') < term.rindex('backSonar')
    assert '2 passed, 1 failed, 1 skipped' in term


def test_runner_parallel_starts_everything_at_once(tmp_path):
    run, out, _ = run_bag(tmp_path, 'parallel', ['backSonar', 'laser'])
    assert [s.verdict for s in run.sensors] == [PASS, PASS]
    assert all(s.started_at == 0.0 for s in run.sensors)
    assert all(s.ended_at == pytest.approx(2.0, abs=0.06) for s in run.sensors)
    assert run.exit_code == results.EXIT_PASS


def test_runner_interrupt_finishes_the_files(tmp_path):
    run, out, term = run_bag(tmp_path, 'sequential', ['laser', 'backSonar'], [Interrupter(1.0)])
    assert run.interrupted and run.exit_code == results.EXIT_INTERRUPTED
    assert run.interrupt_reason == 'interrupted by Ctrl-C'
    laser, sonar_ = run.sensors
    assert laser.stopped_because == 'interrupted' and laser.messages >= 9
    assert sonar_.verdict == SKIPPED
    assert sonar_.reasons == ['not run: the run was interrupted before it started']
    dat = (out / results.OUTPUT_FILE).read_text()
    assert '[INTERRUPTED] interrupted by Ctrl-C' in dat
    assert re.search(r'\[END TIME\] \d{4}-\d\d-\d\d\.\d\d:\d\d:\d\d\n', dat)
    data = json.loads((out / results.JSON_FILE).read_text())
    assert data['interrupted'] is True and data['exit_code'] == 130
    assert [s['name'] for s in data['sensors']] == ['laser', 'backSonar']
    assert ET.parse(str(out / results.JUNIT_FILE)).getroot().get('tests') == '2'
    assert 'INTERRUPTED: interrupted by Ctrl-C' in term


def test_runner_simulator_cameras_one_at_a_time_in_parallel_mode(tmp_path):
    """Gazebo cannot render several cameras at once at full rate: in parallel mode the simulator's
    cameras share one lane, while the other sensors still run at the same time."""
    bag = write_bag(tmp_path / 'sim.bag', {'/laser': laser, '/back': sonar})
    d = tmp_path / 'files'
    d.mkdir()
    (d / 'config.ini').write_text('platform simulator\nmode parallel\n')
    (d / 'topics.dat').write_text('laserSensor /laser\nbackSonar /back\nfrontCamera /front_cam\n'
                                  'bottomCamera /bottom_cam\ndepthCamera /depth_cam\n')
    out = tmp_path / 'out'
    out.mkdir()
    plan = settings.load_plan(Options(config=str(d / 'config.ini'), topics=str(d / 'topics.dat'),
                                      sensors=('frontCamera', 'laser', 'bottomCamera', 'backSonar',
                                               'depthCamera', 'imu'),
                                      output_dir=str(out), duration=2, wait=1, record=False, show=False))
    source = BagSource(bag)
    source.live = True   # replayed as if live: the lanes of a live simulator run
    runner = Runner(plan, RunContext(plan.output_dir, plan.platform, plan.options), source,
                    clock=source.clock, observers=[ResultFiles(str(out), out=io.StringIO())])
    run = runner.execute()
    r = {s.name: s for s in run.sensors}
    assert [s.name for s in run.sensors] == [p.name for p in plan.sensors]
    cams = [r['frontCamera'], r['bottomCamera'], r['depthCamera']]
    for a, b in zip(cams, cams[1:]):
        assert b.started_at >= a.ended_at                 # one camera at a time
    assert r['laser'].started_at == 0.0 and r['backSonar'].started_at == 0.0
    assert r['laser'].ended_at > r['bottomCamera'].started_at       # overlapping the cameras
    assert (r['laser'].verdict, r['backSonar'].verdict) == (PASS, PASS)
    assert r['imu'].verdict == SKIPPED
    assert all(c.reasons == ['topic %s is not in the bag' % c.topic] for c in cams)
    # a real bag replay (sensorTest --bag) has no Gazebo behind it: all cameras at once
    out2 = tmp_path / 'out2'
    out2.mkdir()
    plan2 = settings.replace(plan, output_dir=str(out2))
    source = BagSource(bag)
    run = Runner(plan2, RunContext(plan2.output_dir, plan2.platform, plan2.options), source,
                 clock=source.clock, observers=[ResultFiles(str(out2), out=io.StringIO())]).execute()
    assert {s.name: s.started_at for s in run.sensors if s.name.endswith('Camera')} == \
        {'frontCamera': 0.0, 'bottomCamera': 0.0, 'depthCamera': 0.0}     # scenario: the bag's cameras


def test_a_failing_observer_does_not_stop_the_run(tmp_path, capsys):
    run, out, _ = run_bag(tmp_path, 'parallel', ['backSonar', 'laser'], [Broken()])
    assert [s.verdict for s in run.sensors] == [PASS, PASS]
    data = json.loads((out / results.JSON_FILE).read_text())
    assert [s['verdict'] for s in data['sensors']] == [PASS, PASS]
    assert 'observer failed' in capsys.readouterr().err
