"""The report's laser and odometry views: the dead boards named in words, the pose jumps
counted, from the values dataclasses the checks hand over (no page rendered: test_page.py
renders whole pages in Chromium)."""
from pepper_interface_tests.outputs.report.blocks import KV, Heading, Span
from pepper_interface_tests.outputs.report.views import laser, odometry
from pepper_interface_tests.results import FAIL, SensorResult
from pepper_interface_tests.sensors.values.laser import LaserValues
from pepper_interface_tests.sensors.values.odometry import OdometryValues

RUNS = {'right': 1, 'front': 1, 'left': 1}


def text(parts):
    """Inline content (a string, a Span or a list of both) as the page shows it."""
    if isinstance(parts, list):
        return ''.join(text(p) for p in parts)
    return str(parts.text) if isinstance(parts, Span) else str(parts)


def marked(parts):
    """The texts shown in the failure colour."""
    items = parts if isinstance(parts, list) else [parts]
    return [p.text for p in items if isinstance(p, Span) and p.cls == 'fail-text']


def result(name):
    return SensorResult(name=name, title=name, topic='/' + name, msg_type='', family=name, verdict=FAIL)


def test_a_dead_board_is_named_and_marked_the_others_said_alive():
    parts = laser.boards_text(LaserValues(dead_boards=['front'], longest_identical_board_run=RUNS))
    assert marked(parts) == ['front board dead']
    assert text(parts) == ('front board dead: no valid reading in the window; the right and left '
                           'boards gave readings')


def test_two_dead_boards_and_all_dead():
    two = laser.boards_text(LaserValues(dead_boards=['front', 'left'], longest_identical_board_run=RUNS))
    assert marked(two) == ['front and left boards dead'] and text(two).endswith('the right board gave readings')
    every = laser.boards_text(LaserValues(dead_boards=['right', 'front', 'left'], longest_identical_board_run=RUNS))
    assert marked(every) == ['right, front and left boards dead'] and 'gave readings' not in text(every)


def test_healthy_boards_and_a_layout_without_boards():
    assert laser.boards_text(LaserValues(dead_boards=[], longest_identical_board_run=RUNS)) == \
        'all gave valid readings (right, front, left)'
    assert laser.boards_text(LaserValues(beams=488)) is None      # the simulator's: no boards
    blocks = laser.render(result('laser'), LaserValues(beams=488), None)  # type: ignore[arg-type]
    assert blocks == []


def test_pose_jumps_counted_and_the_largest_shown():
    blocks = odometry.render(result('odometry'), OdometryValues(pose_jumps=5, largest_pose_jump_m=25.004),
                             None)  # type: ignore[arg-type]
    assert isinstance(blocks[0], Heading) and blocks[0].text == 'Pose jumps'
    rows = dict(blocks[1].rows) if isinstance(blocks[1], KV) else {}
    assert text(rows['pose jumps']) == '5' and marked(rows['pose jumps']) == ['5']
    assert text(rows['largest jump']) == '25.004 m'


def test_no_jump_and_no_jump_rule():
    assert odometry.jump_rows(OdometryValues(pose_jumps=0, largest_pose_jump_m=0.0)) == [('pose jumps', 'none')]
    assert odometry.jump_rows(OdometryValues()) == []          # max_speed not set: not judged


def test_the_motion_view_tables_each_step_and_plots_commanded_against_measured():
    from pepper_interface_tests.outputs.report.blocks import Image, Table
    from pepper_interface_tests.outputs.report.views import motion
    from pepper_interface_tests.sensors.values.motion import MotionValues, StepValues
    v = MotionValues(head='moved', base='did not move', steps=[
        StepValues('base', 0.5, 1.0, 4.0, True, {'odometry': 0.0, 'gyro_z': 0.01, 'laser': None})],
        commanded_yaw=[(0.0, 0.0), (1.0, 0.0), (1.0, 0.5), (4.0, 0.5)], odometry_yaw=[(0.5, 0.0), (3.5, 0.0)],
        head_commanded=[(0.2, 0.5)], head_measured=[(0.3, 0.1), (0.9, 0.5)])
    blocks = motion.render(result('motion'), v, None)
    kv = next(b for b in blocks if isinstance(b, KV))
    assert ('base', 'did not move') in kv.rows
    table = next(b for b in blocks if isinstance(b, Table))
    assert table.head[-3:] == ['odometry', 'gyro_z', 'laser'] and table.rows[0][-3:] == ['+0.00', '+0.01', '-']
    assert any(isinstance(b, Image) for b in blocks)


def test_the_tree_view_draws_the_sensors_frames_and_marks_the_unplaceable():
    """The tf view: the tree from its root down to each sensor's frame, the sensor named at
    its frame, a frame that could not be placed in the failure colour, a frame /tf never named
    listed under the tree."""
    from pepper_interface_tests.outputs.report.blocks import Details, Table
    from pepper_interface_tests.outputs.report.context import View
    from pepper_interface_tests.outputs.report.views import tf
    from pepper_interface_tests.results import PASS, FramePlacement, RunResult
    from pepper_interface_tests.sensors.values.tf import TfLink, TfValues
    links = [TfLink('base_link', 'odom'), TfLink('torso', 'base_link'), TfLink('Neck', 'torso'),
             TfLink('CameraTop_frame', 'Head'), TfLink('CameraTop_optical_frame', 'CameraTop_frame'),
             TfLink('Tibia', 'torso'), TfLink('base_footprint', 'Tibia'), TfLink('LHand', 'torso')]
    values = TfValues(messages=10, pairs=len(links), roots=['Head', 'odom'], links=links)
    run = RunResult(platform='robot', mode='parallel', start=0.0)
    for name, frame, placed in [('frontCamera', 'CameraTop_optical_frame', 0), ('laser', 'base_footprint', 5),
                                ('rs', 'camera_color_optical_frame', 0)]:
        r = result(name)
        r.verdict = PASS if placed else FAIL
        r.frame = FramePlacement(frame_id=frame, target='base_footprint', judged=5, placed=placed)
        run.sensors.append(r)
    blocks = tf.render(result('tf'), values, View(files=None, run=run))  # type: ignore[arg-type]
    table = [b for b in blocks if isinstance(b, Table)][0]
    frames = [text(row[0]).replace('\u00a0', ' ') for row in table.rows]
    assert frames[:3] == ['Head', '  \u2514 CameraTop_frame', '    \u2514 CameraTop_optical_frame']
    assert 'LHand' not in ''.join(frames)             # not on a sensor's path: only in the whole tree
    marks = {text(row[0]).strip('\u00a0\u2514 '): row[1] for row in table.rows}
    assert marked(marks['CameraTop_optical_frame']) == ['frontCamera']
    assert text(marks['base_footprint']) == 'laser' and not marked(marks['base_footprint'])
    assert marked(table.rows[-1][0]) == ['camera_color_optical_frame (not in /tf)']
    whole = [b for b in blocks if isinstance(b, Details)][0]
    assert any('LHand' in text(row[0]) for row in whole.blocks[0].rows)


def test_a_number_that_rounds_to_zero_shows_no_minus_sign():
    from pepper_interface_tests.outputs.report.views.fmt import num
    assert num(-0.0001, 3, 's') == '0.000 s'       # a /tf stamp 0.1 ms ahead of its arrival
    assert num(-0.0, 2) == '0.00'
    assert (num(-0.001, 3), num(-1.5, 1), num(0.04, 1)) == ('-0.001', '-1.5', '0.0')
