"""Integration: sensorTest --move against the real emulator, with what the robot receives
recorded by a real rospy node in a process of its own (test/nodes/motion_recorder.py).

Safety, tested rather than assumed: Ctrl-C, SIGTERM and a lost master during a base turn stop
the base at once (the last /cmd_vel the robot received is a zero twist, and no goal comes after
it), the head is sent back to where it started, and the outputs are complete and say where the
motion stopped and why.
"""
import contextlib
import json
import os
import select
import signal
import subprocess
import sys
import time

import pytest

from motion_runs import GOAL, JOINTS, TWIST, assert_stopped_safely, expectations  # noqa: F401
from rosmaster import NODES, Master, kill_group, pause_group, script, spawn, wait_until

PKG = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


class Robot:
    """The emulator (a robot standing still) and the recorder of what it is sent."""

    def __init__(self, master, tmp_path, emu_params=()):
        self.master, self.tmp = master, tmp_path
        self.emu_log = tmp_path / 'emulator.log'
        self.rec_path = tmp_path / 'received.jsonl'
        self.rec_log = tmp_path / 'recorder.log'
        self.marked = 0
        with open(str(self.emu_log), 'w') as log:
            self.emu = spawn(script('pepperEmulator') + ['__name:=emu_%d' % time.time_ns(), '_audio:=off',
                                                          '_condition:=still', '_camera_resolution:=QQVGA']
                             + list(emu_params), master.env(), stdout=log, stderr=subprocess.STDOUT)
        with open(str(self.rec_log), 'w') as log:
            self.rec = spawn([sys.executable, os.path.join(NODES, 'motion_recorder.py'), str(self.rec_path)],
                             master.env(), stdout=log, stderr=subprocess.STDOUT)
        wait_until(lambda: 'publishers up' in self.emu_log.read_text(), 30, self.emu_log.read_text)
        wait_until(lambda: 'recorder up' in self.rec_log.read_text(), 30, self.rec_log.read_text)

    def received(self):
        """What the robot received since the last mark()."""
        if not self.rec_path.exists():
            return []
        rows = [json.loads(line) for line in self.rec_path.read_text().splitlines() if line.strip()]
        return rows[self.marked:]

    def mark(self):
        """From now on received() starts here (one emulator shared by several tests)."""
        self.marked = 0
        self.marked = len(self.received())
        return self

    def stop(self):
        kill_group(self.emu)
        kill_group(self.rec)


@pytest.fixture(scope='module')
def still(tmp_path_factory):
    """One emulator standing still, with its recorder, on a master of its own, shared by the
    tests that do not fault it (the fault tests start their own on module_master)."""
    with Master() as m:
        r = Robot(m, tmp_path_factory.mktemp('still'))
        r.master = m
        yield r
        r.stop()


@pytest.fixture
def robot(still):
    return still.mark()


@pytest.fixture
def master(still):
    """The shared still robot's master (a fresh one per test would need a robot per test)."""
    return still.master


def sensor_test(master, tmp_path, *args, sensors='jointState,odometry,imu,laser', expect=None):
    out = tmp_path / 'out'
    cmd = script('sensorTest') + [
        '--move', '--sensors', sensors, '--mode', 'parallel', '--duration', '1', '--wait', '8',
        '--expectations', expect or expectations(tmp_path, witness_wait=1.0, step_timeout=6.0),
        '--output-dir', str(out), '--no-show', '--no-history', '--no-record', '--no-report',
        '--no-diagnostics'] + list(args)
    log = open(str(tmp_path / 'sensorTest.log'), 'w')
    return spawn(cmd, master.env(), stdout=log, stderr=subprocess.STDOUT), out


def results(out):
    data = json.loads((out / 'sensorTestResults.json').read_text())
    return data, {s['name']: s for s in data['sensors']}


@pytest.mark.parametrize('sig, words, head_yaw', [(signal.SIGINT, 'Ctrl-C', 0.5), (signal.SIGTERM, 'SIGTERM', 0)],
                         ids=['SIGINT', 'SIGTERM'])
def test_a_signal_during_a_turn_stops_the_base_and_returns_the_head(master, robot, tmp_path, sig, words,
                                                                    head_yaw):
    # (the head part takes ~8 s: once is enough to see it sent back)
    proc, out = sensor_test(master, tmp_path, expect=expectations(tmp_path, witness_wait=1.0, step_timeout=6.0,
                                                                  head_yaw=head_yaw))
    try:
        wait_until(lambda: any(r['topic'] == GOAL for r in robot.received()), 40,
                   lambda: 'no goal: %s' % (tmp_path / 'sensorTest.log').read_text()[-2000:])
        proc.send_signal(sig)
        assert proc.wait(30) == 130 if sig == signal.SIGINT else proc.wait(30) != 0
    finally:
        kill_group(proc)
    time.sleep(0.5)     # anything still in flight reaches the recorder
    assert_stopped_safely(robot.received(), head_yaw)
    data, rows = results(out)
    assert data['interrupted'] and words in data['interrupt_reason']
    motion = rows['motion']
    assert motion['verdict'] == 'INTERRUPTED'
    # where the motion stopped and why, on the row's own reasons (the terminal shows them)
    assert any('stopped during "base turn +0.50 rad"' in r and 'zero /cmd_vel' in r and words in r
               for r in motion['reasons']), motion
    # every other selected sensor is in the results too (not run: the run ended)
    assert set(rows) == {'motion', 'jointState', 'odometry', 'imu', 'laser'}


@pytest.mark.integration     # its own roscore, the emulator and a recorder node
def test_a_lost_master_during_a_turn_stops_the_base(tmp_path):
    with Master() as master:
        robot = Robot(master, tmp_path)
        try:
            proc, out = sensor_test(master, tmp_path, expect=expectations(tmp_path, witness_wait=1.0, head_yaw=0))
            try:
                wait_until(lambda: any(r['topic'] == GOAL for r in robot.received()), 40,
                           lambda: (tmp_path / 'sensorTest.log').read_text()[-2000:])
                master.stop()
                proc.wait(40)
            finally:
                kill_group(proc)
            time.sleep(0.5)
            assert_stopped_safely(robot.received(), 0)
        finally:
            robot.stop()
    data, rows = results(out)
    assert data['interrupted'] and 'master' in data['interrupt_reason']
    assert any('stopped during "base turn' in r and 'master' in r for r in rows['motion']['reasons']), rows['motion']


# ------------------------------------------------------------------ the rules against the emulator

QUICK = dict(witness_wait=1.0, step_timeout=6.0, settle_time=0.5)   # head_speed: the default 0.1
BASE = 'jointState,odometry,imu,laser'
HEAD_AND_BASE = BASE + ',frontCamera,bottomCamera'


def move_run(master, tmp_path, faults, sensors, **motion):
    """The emulator (standing still, `faults`), sensorTest --move on `sensors`: the rows by name.
    The topics file leaves out the stereo and depth cameras: on a loaded test machine four camera
    witnesses at 10 fps each left gaps of half a second between frames."""
    robot = Robot(master, tmp_path, ['_faults:=' + faults] if faults else [])
    lines = [ln for ln in open(os.path.join(PKG, 'data', 'pepperTopics.dat')).read().splitlines()
             if not ln.startswith(('StereoCamera ', 'DepthCamera '))]
    (tmp_path / 'topics.dat').write_text('\n'.join(lines) + '\n')
    try:
        proc, out = sensor_test(master, tmp_path, '--topics', str(tmp_path / 'topics.dat'), sensors=sensors,
                                expect=expectations(tmp_path, **dict(QUICK, **motion)))
        try:
            proc.wait(90)
        finally:
            kill_group(proc)
    finally:
        robot.stop()
    data, rows = results(out)
    return rows, robot.received()


def reason(row, words):
    assert row['verdict'] == 'FAIL' and any(words in r for r in row['reasons']), (row['name'], row['reasons'])


def test_a_healthy_robot_passes_every_motion_sensor_and_ends_where_it_started(master, robot, tmp_path):
    proc, out = sensor_test(master, tmp_path, sensors=HEAD_AND_BASE + ',depthCamera,frontSonar',
                            expect=expectations(tmp_path, **QUICK))
    try:
        proc.wait(90)
    finally:
        kill_group(proc)
    _, rows = results(out)
    received = robot.received()
    for name, row in rows.items():
        assert row['verdict'] == 'PASS', (name, row['reasons'], row['warnings'])
    v = rows['motion']['values']
    assert (v['head'], v['base']) == ('moved', 'moved')
    steps = v['steps']
    assert abs(sum(s['measured']['odometry'] for s in steps if s['part'] == 'base')) < 0.05   # turned back
    heads = [r['angles'][0] for r in received if r['topic'] == JOINTS]
    assert heads[-1] == pytest.approx(heads[0] - 0.5, abs=1e-4)   # the head back at its start
    assert [round(g['yaw'], 2) for g in received if g['topic'] == GOAL] == [0.5, -0.5]


@pytest.mark.parametrize('faults, sensors, motion, failed', [
    ('imu:gyro_inverted;laser:reversed;frontCamera:not_following',
     HEAD_AND_BASE, {}, {'imu': 'opposite sign', 'laser': 'wrong way', 'frontCamera': 'not following'}),
    # the encoder stuck, both cameras follow: two witnesses of three saw the head turn
    ('jointState:stuck_joint=HeadYaw', 'jointState,frontCamera,bottomCamera', {'base_turn': 0},
     {'jointState': 'HeadYaw did not move'}),
    # the gyro on the wrong axis still saw a turn: with the wheels and the laser, three of four
    ('odometry:frozen_pose;imu:swapped_axes', BASE, {'head_yaw': 0},
     {'odometry': 'did not change', 'imu': "gyro's x axis"}),
    ('imu:dead_gyro', BASE, {'head_yaw': 0}, {'imu': 'gyro reads about zero'}),
], ids=['three-at-once', 'stuck_joint', 'frozen_pose+swapped_axes', 'dead_gyro'])
def test_each_motion_fault_fails_its_own_sensor_and_no_other(module_master, tmp_path, faults, sensors,
                                                             motion, failed):
    rows, _ = move_run(module_master, tmp_path, faults, sensors, **motion)
    for name, words in failed.items():
        reason(rows[name], words)
    for name, row in rows.items():
        if name not in failed:
            assert row['verdict'] in ('PASS', 'SKIPPED'), (name, row['reasons'])
    assert rows['motion']['verdict'] != 'FAIL'


def test_a_base_that_refuses_to_move_fails_the_motion_row_not_the_sensors(module_master, tmp_path):
    rows, received = move_run(module_master, tmp_path, 'robot:base_blocked', BASE, head_yaw=0)
    reason(rows['motion'], 'the base did not move when commanded')
    for name in BASE.split(','):
        assert rows[name]['verdict'] == 'PASS', (name, rows[name]['reasons'])


@pytest.mark.parametrize('fault, words', [
    ('robot:resting', 'wake it up'),
    ('robot:obstacle', 'not enough free space'),
])
def test_a_robot_that_may_not_move_is_not_moved_and_says_why(module_master, tmp_path, fault, words):
    rows, received = move_run(module_master, tmp_path, fault, BASE + ',frontSonar,robotHealth')
    motion = rows['motion']
    assert motion['verdict'] == 'SKIPPED' and words in motion['reasons'][0], motion['reasons']
    assert not [r for r in received if r['topic'] == GOAL]
    for name in BASE.split(','):
        assert rows[name]['verdict'] != 'FAIL', (name, rows[name]['reasons'])


def test_a_resting_robot_whose_diagnostics_come_late_is_still_not_moved(module_master, tmp_path):
    """naoqi_driver's /diagnostics comes at 1 Hz, and on a loaded machine its first message may
    come after witness_wait: the checks before moving wait for it (DIAGNOSTICS_WAIT), so a
    resting robot is not sent a turn it ignores and its base is not called broken."""
    topic = '/late/diagnostics'
    lines = [ln for ln in open(os.path.join(PKG, 'data', 'pepperTopics.dat')).read().splitlines()
             if not ln.startswith(('StereoCamera ', 'DepthCamera ', 'RobotHealth '))]
    (tmp_path / 'topics.dat').write_text('\n'.join(lines + ['RobotHealth %s' % topic]) + '\n')
    log = tmp_path / 'late.log'
    robot = Robot(module_master, tmp_path, ['_faults:=robot:resting'])
    try:
        with open(str(log), 'w') as out:   # its first message 1.5 s after sensorTest subscribes
            late = spawn([sys.executable, os.path.join(NODES, 'late_diagnostics.py'), topic, '1.5'],
                         module_master.env(), stdout=out, stderr=subprocess.STDOUT)
        try:
            wait_until(lambda: 'diagnostics up' in log.read_text(), 30, log.read_text)
            proc, out_dir = sensor_test(module_master, tmp_path, '--topics', str(tmp_path / 'topics.dat'),
                                        sensors=BASE + ',frontSonar',
                                        expect=expectations(tmp_path, **QUICK))   # witness_wait 1.0
            try:
                proc.wait(90)
            finally:
                kill_group(proc)
        finally:
            kill_group(late)
    finally:
        robot.stop()
    _, rows = results(out_dir)
    motion = rows['motion']
    assert motion['verdict'] == 'SKIPPED' and 'wake it up' in motion['reasons'][0], motion['reasons']
    assert not [r for r in robot.received() if r['topic'] == GOAL]


@pytest.mark.parametrize('kind, key, words', [
    ('sonar', 'FrontSonar', 'obstacle closer than 0.30 m: the front sonar sees something 0.20 m away'),
    ('bumper', 'Bumper', 'the back bumper is pressed'),
], ids=['obstacle', 'bumper'])
def test_a_hazard_during_a_turn_stops_the_base_at_once(master, robot, tmp_path, kind, key, words):
    """A bumper pressed, or something closer than stop_distance, while the base turns: a zero
    /cmd_vel, no further goal, and the motion row says where and why it stopped."""
    topic = '/hazard/' + kind
    lines = [ln for ln in open(os.path.join(PKG, 'data', 'pepperTopics.dat')).read().splitlines()
             if not ln.startswith(key + ' ')]
    (tmp_path / 'topics.dat').write_text('\n'.join(lines + ['%s %s' % (key, topic)]) + '\n')
    trigger = tmp_path / 'near'
    log = tmp_path / 'hazard.log'
    with open(str(log), 'w') as out:
        hazard = spawn([sys.executable, os.path.join(NODES, 'motion_hazard.py'), kind, topic, str(trigger)],
                       master.env(), stdout=out, stderr=subprocess.STDOUT)
    try:
        wait_until(lambda: 'hazard up' in log.read_text(), 30, log.read_text)
        proc, out_dir = sensor_test(master, tmp_path, '--topics', str(tmp_path / 'topics.dat'),
                                    expect=expectations(tmp_path, witness_wait=1.5, head_yaw=0))
        try:
            wait_until(lambda: any(r['topic'] == GOAL for r in robot.received()), 40,
                       lambda: (tmp_path / 'sensorTest.log').read_text()[-2000:])
            trigger.write_text('now')
            proc.wait(60)
        finally:
            kill_group(proc)
    finally:
        kill_group(hazard)
    time.sleep(0.3)
    received = robot.received()
    assert_stopped_safely(received, 0)
    assert len([r for r in received if r['topic'] == GOAL]) == 1     # the turn back never sent
    data, rows = results(out_dir)
    motion = rows['motion']
    assert not data['interrupted']
    assert any('stopped during "base turn +0.50 rad"' in w and words in w for w in motion['warnings']), motion
    assert motion['verdict'] == 'SKIPPED' and 'base part not finished' in motion['reasons'][0]
    for name in BASE.split(','):
        assert rows[name]['verdict'] == 'PASS', (name, rows[name]['reasons'])


@contextlib.contextmanager
def move_on_a_pty(master, tmp_path, columns, witness_wait):
    """sensorTest --move on a real pty `columns` wide, without --yes, read until "Press Enter":
    yields (process, the pty's primary side, output folder, what it showed, the deadline); the
    process group is killed and the pty closed on the way out."""
    import fcntl
    import pty
    import struct
    import termios
    primary, secondary = pty.openpty()
    fcntl.ioctl(secondary, termios.TIOCSWINSZ, struct.pack('HHHH', 40, columns, 0, 0))
    out = tmp_path / 'out'
    cmd = script('sensorTest') + [
        '--move', '--sensors', 'jointState', '--duration', '1', '--wait', '8',
        '--expectations', expectations(tmp_path, witness_wait=witness_wait), '--output-dir', str(out),
        '--no-show', '--no-history', '--no-record', '--no-report']
    proc = subprocess.Popen(cmd, env=master.env(), stdin=secondary, stdout=secondary, stderr=secondary,
                            start_new_session=True)
    os.close(secondary)
    seen = b''
    deadline = time.monotonic() + 40
    try:
        while b'Press Enter' not in seen and time.monotonic() < deadline:
            if select.select([primary], [], [], 0.5)[0]:
                seen += os.read(primary, 4096)
        yield proc, primary, out, seen, deadline
    finally:
        kill_group(proc)
        os.close(primary)


def answer_s_and_wait(proc, primary, deadline):
    """Type `s` and Enter (skip the motion), then read the pty until sensorTest ends."""
    os.write(primary, b's\n')
    while proc.poll() is None and time.monotonic() < deadline:
        if select.select([primary], [], [], 0.5)[0]:
            try:
                os.read(primary, 4096)
            except OSError:
                break
    proc.wait(20)


def test_on_a_terminal_the_person_is_told_and_s_skips(master, robot, tmp_path):
    """sensorTest on a terminal (a real pty), without --yes: the plan is said, and `s` then
    Enter skips the motion: nothing is sent."""
    with move_on_a_pty(master, tmp_path, 80, witness_wait=1.0) as (proc, primary, out, seen, deadline):
        assert b'I will turn my head 29 degrees to the left' in seen, seen.decode(errors='replace')
        said = seen.decode(errors='replace')
        said = said[said.index('sensorTest --move:'):said.index('Press Enter')]
        assert all(len(line) <= 80 for line in said.splitlines()), said     # broken at spaces
        answer_s_and_wait(proc, primary, deadline)
    _, rows = results(out)
    assert rows['motion']['verdict'] == 'SKIPPED', rows['motion']
    assert 'skipped by the operator' in rows['motion']['reasons'][0]
    assert [r for r in robot.received() if r['topic'] in (GOAL, JOINTS, TWIST)] == []


def screen(raw):
    """The rows a terminal shows for `raw` output: '\\r' back to the row's start, ESC[K erases
    the rest of the row, ESC[F goes up a row (what Terminal and the guide write)."""
    rows, row, col = [''], 0, 0
    i = 0
    while i < len(raw):
        if raw.startswith('\033[K', i):
            rows[row] = rows[row][:col]
            i += 3
        elif raw.startswith('\033[F', i):
            row, col = max(0, row - 1), 0
            i += 3
        elif raw[i] == '\r':
            col, i = 0, i + 1
        elif raw[i] == '\n':
            row, col, i = row + 1, 0, i + 1
            if row == len(rows):
                rows.append('')
        else:
            text = rows[row]
            rows[row] = text[:col] + raw[i] + text[col + 1:]
            col, i = col + 1, i + 1
    return rows


def test_screen_renders_a_cleared_progress_line():
    assert screen('a\n  ... x: 3 s left\r\033[Kquestion\n') == ['a', 'question', '']
    assert screen('a\n  ... x: 3 s left\nquestion\n') == ['a', '  ... x: 3 s left', 'question', '']


def test_nothing_else_prints_while_the_person_is_asked(master, robot, tmp_path):
    """On a terminal (a real pty), the question stands alone: no progress line ("... motion:
    N s left") above it, and nothing printed while it waits for Enter (the progress line
    ticks every 0.5 s); after Enter, the run goes on (issue 45)."""
    with move_on_a_pty(master, tmp_path, 100, witness_wait=1.5) as (proc, primary, out, seen, deadline):
        asked = seen.decode(errors='replace')
        assert 'Press Enter' in asked, asked
        after = b''
        quiet_until = time.monotonic() + 2.5           # five ticks of the progress line
        while time.monotonic() < quiet_until:
            if select.select([primary], [], [], 0.2)[0]:
                after += os.read(primary, 4096)
        shown = screen(asked)
        question = max(i for i, row in enumerate(shown) if row.startswith('sensorTest --move:'))
        above = [row for row in shown[:question] if '... motion' in row]
        assert above == [], 'a progress line above the question:\n' + '\n'.join(shown)
        assert after.strip(b'\r\n') == b'', 'printed while the question waits: %r' % after
        answer_s_and_wait(proc, primary, deadline)
    _, rows = results(out)
    assert rows['motion']['verdict'] == 'SKIPPED' and 'skipped by the operator' in rows['motion']['reasons'][0]


def test_a_motion_cut_short_by_a_stalled_pc_says_the_pc_was_busy(master, robot, tmp_path):
    """sensorTest stopped (a real SIGSTOP) through the head's first step for longer than the
    motion check's window: the part is not finished, and the row says the PC was busy, naming
    how long sensorTest did not run (sensors/motion_pc.py), not a fault of the robot."""
    proc, out = sensor_test(master, tmp_path, sensors='jointState',
                            expect=expectations(tmp_path, witness_wait=1.0, step_timeout=2.0, base_turn=0))
    try:
        wait_until(lambda: any(r['topic'] == JOINTS for r in robot.received()), 40,
                   lambda: 'no head command: %s' % (tmp_path / 'sensorTest.log').read_text()[-2000:])
        pause_group(proc, 16.0)     # longer than the window: witness_wait + 3 s + 5 step_timeouts
        proc.wait(60)
    finally:
        kill_group(proc)
    _, rows = results(out)
    motion = rows['motion']
    assert motion['verdict'] == 'SKIPPED', motion
    why = motion['reasons'][0]
    assert "the check's window ended" in why and 'This PC was busy' in why, motion
    assert 'sensorTest did not run for 1' in why, why      # the 16 s stall, named
