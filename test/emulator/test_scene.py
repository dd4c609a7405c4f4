"""Every head camera of the emulated world pans with the view's yaw the right way (a view turned
left moves the room to the right of the picture, by about focal x angle pixels), and the ray
cast meets the body's obstacles and the glass pane only where they are (emulator/scene.py).
Pure: no ROS."""
import math

import numpy as np
import pytest

from driver_views import shift_right
from pepper_interface_tests.emulator import scene

TURN = 0.15                 # rad: the view turned left


def profile(img):
    """Mean of the top quarter of the rows, per column (the wall, above the floor and ball)."""
    top = img[: img.shape[0] // 4].astype(np.float64)
    return top.mean(axis=(0, 2)) if top.ndim == 3 else top.mean(axis=0)


# Colour pictures are cut from a cylindrical panorama, width / hfov pixels per radian across the
# whole picture (the real pinhole camera's focal length, (width / 2) / tan(hfov / 2), is 8 %
# less at the centre); depth is cast per column through a pinhole, so a column moves by about
# focal x angle, and the planar depth of a wall changes as it moves off-centre (a looser match).
@pytest.mark.parametrize('make, width, hfov, pinhole', [
    (lambda: scene.ColourCamera(320, 240, 0.9826, view='front'), 320, 0.9826, False),
    (lambda: scene.ColourCamera(320, 240, 0.9826, view='bottom'), 320, 0.9826, False),
    (lambda: scene.StereoCamera(640, 180, 1.0123), 320, 1.0123, False),
    (lambda: scene.DepthCamera(320, 240, 1.0123), 320, 1.0123, True)])
def test_each_head_camera_pans_with_the_view(make, width, hfov, pinhole):
    cam = make()
    t = 3.0
    before = cam.render(t, view=(0.0, 0.0, 0.4))
    after = cam.render(t, view=(0.0, 0.0, 0.4 + TURN))
    if before.ndim == 3 and before.shape[1] == 2 * width:       # the stereo pair: its left view
        before, after = before[:, :width], after[:, :width]
    moved = shift_right(profile(before), profile(after))
    if pinhole:
        assert moved == pytest.approx((width / 2.0) / math.tan(hfov / 2.0) * TURN, rel=0.3)
    else:
        assert moved == pytest.approx(width / hfov * TURN, abs=2)


def test_obstacles_and_panes_are_met_where_they_are():
    angles = [0.0, math.pi / 2]
    free = scene.raycast(0.0, 0.0, angles, 0.0)
    with_bin = scene.raycast(0.0, 0.0, angles, 0.0, circles=[(0.47, 0.0, 0.12)])
    assert with_bin[0] == pytest.approx(0.35) and with_bin[1] == free[1]
    glass = scene.raycast(0.0, 0.0, angles, 0.0, panes=[scene.GLASS_PANE])
    assert glass[0] == pytest.approx(0.8) and glass[1] == free[1]
    # looking back from beyond the pane, or past its end: no pane
    assert scene.raycast(1.0, 0.0, [0.0], 0.0, panes=[scene.GLASS_PANE])[0] > 1.0
    assert scene.raycast(0.0, 1.0, [0.0], 0.0, panes=[scene.GLASS_PANE])[0] > 1.0
