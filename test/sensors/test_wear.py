"""Unit: sensors/wear.py, the cheap wear measures the drift from a baseline compares: the noise
of a slowly moving reading (also sampled at an uneven pace), robust to a step; the noise of
every beam of a scan; a frame's sharpness (unchanged by dimming, lost by a blur) and noise."""
import math

import numpy as np

from pepper_interface_tests.emulator.publishers import _box_blur
from pepper_interface_tests.sensors.wear import BeamNoise, Noise, focus_and_noise


def test_noise_of_a_slow_sinusoid_sampled_unevenly_is_its_noise_not_its_motion():
    rng = np.random.default_rng(1)
    t = np.cumsum(0.02 + 0.01 * rng.random(500))         # 50 Hz with jitter of up to 10 ms
    motion = 0.1 * np.sin(2 * math.pi * 0.4 * t)
    still, noisy = Noise(), Noise()
    for ti, x, n in zip(t, motion, rng.normal(0, 0.002, t.size)):
        still.add(float(x), float(ti))
        noisy.add(float(x + n), float(ti))
    assert still.sd() < 0.0002
    assert 0.0017 < noisy.sd() < 0.0023


def test_a_step_is_not_noise_and_a_gap_restarts():
    n = Noise()
    rng = np.random.default_rng(2)
    for i in range(200):
        n.add((1.0 if i < 100 else 2.0) + float(rng.normal(0, 0.01)))
    assert 0.008 < n.sd() < 0.012
    short = Noise()
    for v in (1.0, 2.0, float('nan'), 3.0):
        short.add(v)
    assert short.sd() is None


def test_beam_noise_over_all_beams_of_consecutive_scans():
    rng = np.random.default_rng(3)
    b = BeamNoise()
    for _ in range(30):
        scan = np.linspace(1, 3, 61) + rng.normal(0, 0.01, 61)
        scan[::10] = np.nan                                # not returns: left out
        b.add(scan)
    assert 0.008 < b.sd() < 0.012
    b.add(np.ones(488))                                     # another layout starts again
    assert b.prev2 is None


def test_sharpness_survives_dimming_and_falls_with_a_blur():
    rng = np.random.default_rng(4)
    img = np.kron(rng.integers(0, 255, (30, 40, 3)), np.ones((4, 4, 1))).astype(np.uint8)   # 120x160 detail
    sharp, _ = focus_and_noise(img)
    dim, _ = focus_and_noise((img * 0.6).astype(np.uint8))
    blurred, _ = focus_and_noise(_box_blur(img))
    assert abs(dim - sharp) < 0.1 * sharp
    assert blurred < 0.5 * sharp
    assert focus_and_noise(np.full((10, 10, 3), 7, np.uint8)) == (0.0, 0.0)


def test_image_noise_estimate_follows_added_noise():
    rng = np.random.default_rng(5)
    flat = np.full((240, 320, 3), 120.0)
    _, quiet = focus_and_noise(flat.astype(np.uint8))
    _, loud = focus_and_noise(np.clip(flat + rng.normal(0, 4, flat.shape), 0, 255).astype(np.uint8))
    assert quiet < 0.5 and 1.5 < loud < 4.5


def test_sharpness_of_a_thin_line_does_not_depend_on_the_parity_of_its_column():
    """A 1-pixel line one column to the side is the same picture: its sharpness must not jump
    (sampling every 2nd column made it count or vanish; the still emulator's 1-pixel door
    outlines then read 0.27 or 0.74 by a pixel of HeadYaw noise)."""
    rng = np.random.default_rng(6)
    base = np.clip(120 + rng.normal(0, 2, (120, 160, 3)), 0, 255)
    sharp = []
    for col in (40, 41):
        img = base.copy()
        img[20:100, col] = 30
        sharp.append(focus_and_noise(img.astype(np.uint8))[0])
    assert abs(sharp[0] - sharp[1]) < 0.1 * max(sharp), sharp


def test_the_still_emulators_front_camera_keeps_its_sharpness_when_the_head_moves_a_pixel():
    from pepper_interface_tests.emulator.scene import ColourCamera
    cam = ColourCamera(160, 120, 1.0, 'front')
    values = [focus_and_noise(cam.render(5.0, view=(0.0, 0.0, yaw)))[0] for yaw in np.arange(-0.1, 0.1, 0.01)]
    assert max(values) < 1.3 * min(values), np.round(values, 3)
