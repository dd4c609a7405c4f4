"""The emulator's dead laser board and odometry spike, end to end: the real emulator publishes
with `~faults`, the real sensorTest listens for a short window, its JSON gives the verdicts."""
import pytest

from pepper_interface_tests.emulator import fault_table
from pepper_interface_tests.emulator.faults import FaultError, format_faults, parse_faults
from test_data_faults import reason_with, run


def test_dead_and_nan_boards_and_the_spike_fail_by_name(master, tmp_path):
    res, _ = run(master, tmp_path, ['_audio:=off', '_camera_resolution:=QQVGA',
                                    '_faults:=laser:dead_board=front;odometry:spike'],
                 ['laser', 'odometry'], duration=3)
    # naoqi_driver turns the stopped front board's x = y = 0 into its offset (laser.cpp:185-186)
    reason_with(res['laser'], 'front board (slots 23-37) dead', '0.056 m in every slot')
    assert not [r for r in res['laser']['reasons'] if 'right board' in r or 'left board' in r]
    text = reason_with(res['odometry'], 'pose jumps:', 'the largest 25')
    assert ' jumps, ' in text, text
    res, _ = run(master, tmp_path, ['_audio:=off', '_camera_resolution:=QQVGA',
                                    '_faults:=laser:nan_board=left'], ['laser'], duration=3, tag='nan')
    reason_with(res['laser'], 'left board (slots 46-60) dead', 'NaN in every slot')


def test_board_faults_parse_and_are_listed():
    f = parse_faults('laser:dead_board=Front;odometry:spike')
    assert f['laser'].dead_board == 'front' and f['odometry'].spike
    assert parse_faults(format_faults(f)) == f
    with pytest.raises(FaultError, match='valid boards: right, front, left'):
        parse_faults('laser:dead_board=back')
    with pytest.raises(FaultError, match='dead_board=front'):
        parse_faults('laser:dead_board')
    with pytest.raises(FaultError, match='does not apply to imu'):
        parse_faults('imu:spike')
    table = fault_table.table()
    for name in ('dead_board=VALUE', 'nan_board=VALUE', 'spike'):
        assert name in table
    assert max(len(line) for line in table.splitlines()) <= 80
