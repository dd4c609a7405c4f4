"""Unit: what a witness measured (motion/estimate.py): yaw, unwrapped changes, the integrated
gyro, a scan's turn and its sign under naoqi_driver's beam order, a picture's sideways shift."""
import math

import numpy as np
import pytest

from pepper_interface_tests.motion import estimate

INC = (2 * 2.0944) / 61


def test_yaw_of_a_quaternion_and_a_change_across_pi_is_unwrapped():
    assert estimate.yaw_of(0, 0, math.sin(0.25), math.cos(0.25)) == pytest.approx(0.5)
    series = [(0.0, 3.0), (1.0, -3.0)]          # +0.28 rad across +-pi, not -6 rad
    assert estimate.change(series, 0.0, 1.0) == pytest.approx(2 * math.pi - 6.0)
    assert estimate.change(series, 0.0, 1.0, angle=False) == pytest.approx(-6.0)


def test_integrated_gyro_per_axis():
    gyro = [(t * 0.1, 0.0, 0.0, 0.25) for t in range(21)]
    assert estimate.integrated_gyro(gyro, 0.0, 2.0) == pytest.approx((0.0, 0.0, 0.5))
    assert estimate.integrated_gyro(gyro[:1], 0.0, 2.0) is None


def test_scan_turn_sign_follows_the_beam_order():
    room = 1.0 + np.abs(np.sin(np.arange(61) * 0.41)) + 0.01 * np.arange(61)
    after = np.interp(np.arange(61) + 0.5 / INC, np.arange(61), room, left=np.nan, right=np.nan)
    assert estimate.scan_turn(room, after, INC) == pytest.approx(0.5, abs=0.05)
    # the same scans stored in the reverse order (left first) turn the other way
    assert estimate.scan_turn(room[::-1], after[::-1], INC) == pytest.approx(-0.5, abs=0.05)
    assert estimate.scan_turn(room, room, INC) == pytest.approx(0.0, abs=0.01)


def test_blind_slots_and_readings_below_range_min_take_no_part():
    r = estimate.valid_ranges([-1.0, 0.05, 2.0, 9.0, float('nan')], 0.1)
    assert np.isnan(r[[0, 1, 4]]).all() and list(r[[2, 3]]) == [2.0, 9.0]


def test_picture_shift_right_is_positive_and_floorboards_do_not_alias():
    x = np.arange(400)
    scene = np.sin(x / 23.0) + 0.6 * np.sin(x / 7.0 + 1) + 0.4 * np.sin(2 * np.pi * x / 5.5)  # boards
    a = np.tile(scene[100:180], (30, 1))
    b = np.tile(scene[88:168], (30, 1))         # the scene moved 12 px to the right
    assert estimate.picture_shift(a, b) == pytest.approx(12, abs=1)
    assert estimate.picture_shift(b, a) == pytest.approx(-12, abs=1)
    assert estimate.picture_shift(np.zeros((30, 80)), a) is None     # flat: nothing to follow


@pytest.mark.integration     # small_grey imports OpenCV: 0.6 s of CPU, a tenth of the unit tier's budget
def test_small_grey_averages_blocks():
    img = np.zeros((4, 8, 3), np.uint8)
    img[:, ::2] = 255                               # one-pixel stripes
    # each block's mean, 127.5, within the half grey level OpenCV's area reduction rounds to
    assert estimate.small_grey(img, width=4) == pytest.approx(np.full((2, 4), 127.5), abs=0.5)
