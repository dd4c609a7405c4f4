"""A small synthetic world that every emulated sensor observes, so the streams agree.

The robot stands in a rectangular room (driving slowly in a circle unless commanded: body.py);
a person walks to and fro along the far wall; a pillar stands in a corner. From the room at
time t, seen from the body's pose, come:

- laser and sonar ranges (ray casting against the walls, the person and the pillar),
- depth images (per image column the same ray cast, the floor plane below the horizon, a
  bouncing ball in front, a few invalid 0 pixels),
- colour images (a room panorama panned with the head's heading, the person drawn where the
  laser sees it, a bouncing ball, a frame counter), and the stereo pair (two shifted views).

The world is a pure function of t (plus a seeded noise generator per caller); the robot's pose
comes from its body (emulator/body.py), which the motion commands change: each function takes
the pose to look from (`pose`, x y yaw in the odom frame; default robot_pose(t), the idle
circle) and the obstacles the body brings (`circles`). Cheap enough for all cameras at their
nominal rates: see docs/emulator.md for the measured cost.
"""
import math
from typing import Optional, Sequence, Tuple, Union

import numpy as np

# ---------------------------------------------------------------- world

ROOM = (-2.2, 4.6, -1.6, 2.4)          # x_min, x_max, y_min, y_max (m): the far wall lies
                                       # beyond the laser's advertised 3 m and the sonar's 2.55 m
CIRCLE_RADIUS = 0.5                    # m
ANGULAR_SPEED = 0.15                   # rad/s, counter-clockwise
LINEAR_SPEED = CIRCLE_RADIUS * ANGULAR_SPEED
PILLAR = (1.9, -0.9, 0.15)             # x, y, radius
PERSON_Y, PERSON_RADIUS = 1.8, 0.22
PERSON_X = (-1.4, 1.8)
PERSON_SPEED = 0.35                    # m/s
GRAVITY = 9.80665
# the `frontSonar:glass` fault: a glass pane across the start heading (x, y_min, y_max in the
# odom frame), which the sonar's ultrasound meets and the laser's infrared passes through
GLASS_PANE = (0.8, -0.6, 0.6)

Pose = Tuple[float, float, float]
Circles = Sequence[Tuple[float, float, float]]
Panes = Sequence[Tuple[float, float, float]]


def robot_pose(t: float) -> Pose:
    """(x, y, yaw) at time t of the idle drive (body.py): a circle of CIRCLE_RADIUS through
    the origin, starting along +x."""
    a = ANGULAR_SPEED * t
    return (CIRCLE_RADIUS * math.sin(a), CIRCLE_RADIUS * (1.0 - math.cos(a)),
            math.atan2(math.sin(a), math.cos(a)))


def person_position(t: float) -> Tuple[float, float]:
    lo, hi = PERSON_X
    span = hi - lo
    s = (PERSON_SPEED * t) % (2 * span)
    return (lo + (s if s < span else 2 * span - s), PERSON_Y)


def yaw_quaternion(yaw: float) -> Tuple[float, float, float, float]:
    """(x, y, z, w) of a rotation about z."""
    return (0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0))


def raycast(x: float, y: float, angles: Union[np.ndarray, Sequence[float]], t: float,
            circles: Circles = (), panes: Panes = ()) -> np.ndarray:
    """Distances from (x, y) along world angles to the first wall, person or pillar, or one of
    `circles` (x, y, radius) or `panes` (x, y_min, y_max: a pane across the x axis)."""
    angles = np.asarray(angles, dtype=np.float64)
    dx, dy = np.cos(angles), np.sin(angles)
    x0, x1, y0, y1 = ROOM
    with np.errstate(divide='ignore', invalid='ignore'):
        tx = np.where(dx > 0, (x1 - x) / dx, np.where(dx < 0, (x0 - x) / dx, np.inf))
        ty = np.where(dy > 0, (y1 - y) / dy, np.where(dy < 0, (y0 - y) / dy, np.inf))
    dist = np.minimum(tx, ty)
    px, py = person_position(t)
    for cx, cy, r in ((px, py, PERSON_RADIUS), PILLAR) + tuple(circles):
        ox, oy = cx - x, cy - y
        along = ox * dx + oy * dy
        perp2 = ox * ox + oy * oy - along * along
        hit = (along > 0) & (perp2 < r * r)
        d = along - np.sqrt(np.maximum(r * r - perp2, 0.0))
        dist = np.where(hit & (d < dist), d, dist)
    for gx, g0, g1 in panes:
        with np.errstate(divide='ignore', invalid='ignore'):
            d = np.where(dx != 0, (gx - x) / dx, np.inf)
        cross = y + d * dy
        dist = np.where((d > 0) & (cross >= g0) & (cross <= g1) & (d < dist), d, dist)
    return dist


# ---------------------------------------------------------------- colour images

def _hsv_colour(h: float, s: int = 200, v: int = 220) -> Tuple[int, ...]:
    import cv2  # OpenCV takes half a second to import: only where the emulator draws
    px = np.uint8([[[int(h) % 180, s, v]]])  # type: ignore[arg-type]  # numpy accepts nested lists
    return tuple(int(c) for c in cv2.cvtColor(px, cv2.COLOR_HSV2RGB)[0, 0])


class _Panorama:
    """A 360-degree strip of the room for one view size, panned by the robot's heading."""

    def __init__(self, width: int, height: int, hfov: float, floor_view: bool = False) -> None:
        import cv2  # OpenCV takes half a second to import: only where the emulator draws
        self.width, self.height = width, height
        self.full = max(int(round(width * 2 * math.pi / hfov)), width + 1)
        # the gradients change in bands of rows (like a lightly compressed video): flat bands
        # keep recorded bags small (lz4 finds the repeated rows) and cost nothing to render
        band = max(2, height // 30)
        rows = ((np.arange(height) // band * band) / float(max(height - 1, 1))).astype(np.float32)[:, None]
        horizon = 0.15 if floor_view else 0.55
        strip = np.zeros((height, self.full + width, 3), np.uint8)
        # wall: warm vertical gradient with hue drifting around the room
        cols = np.linspace(0.0, 1.0, self.full, endpoint=False, dtype=np.float32)[None, :]
        wall_r = 150 + 60 * (1 - rows) + 20 * np.sin(2 * np.pi * cols)
        wall_g = 140 + 50 * (1 - rows) + 20 * np.sin(2 * np.pi * cols + 2)
        wall_b = 120 + 40 * (1 - rows) + 20 * np.sin(2 * np.pi * cols + 4)
        wall = np.stack(np.broadcast_arrays(wall_r, wall_g, wall_b), axis=-1)
        # floor: darker, wooden stripes
        stripes = 0.5 + 0.5 * np.sin(2 * np.pi * cols * 90)
        floor = np.stack(np.broadcast_arrays(90 + 30 * rows + 15 * stripes,
                                             60 + 20 * rows + 10 * stripes,
                                             40 + 10 * rows + 0 * stripes), axis=-1)
        is_floor = rows >= horizon
        room = np.where(is_floor[..., None], floor, wall)
        strip[:, :self.full] = np.clip(room, 0, 255).astype(np.uint8)
        # doors and pictures at fixed headings
        for pos, hue, tall in (((0.08, 10, 0.7), (0.3, 100, 0.3), (0.47, 60, 0.4),
                                              (0.66, 140, 0.65), (0.85, 25, 0.3))):
            cx = int(pos * self.full)
            half = max(2, int(width * 0.06))
            top = int(height * (horizon - tall))
            bottom = int(height * horizon) if tall > 0.5 else int(height * (horizon - 0.12))
            if bottom > top >= -height:
                cv2.rectangle(strip, (cx - half, max(top, 0)), (cx + half, bottom),
                              _hsv_colour(hue, 160, 200), -1)
                cv2.rectangle(strip, (cx - half, max(top, 0)), (cx + half, bottom),
                              (40, 40, 40), max(1, width // 160))
        strip[:, self.full:] = strip[:, :width]
        self.strip = strip
        self.horizon_row = int(height * horizon)

    def view(self, yaw: float, shift: int = 0) -> np.ndarray:
        offset = int(round((-yaw / (2 * math.pi)) * self.full + shift)) % self.full
        return np.ascontiguousarray(self.strip[:, offset:offset + self.width])


class ColourCamera:
    """rgb8 frames of one camera (front, bottom, realsense) at one size."""

    def __init__(self, width: int, height: int, hfov: float, view: str = 'front', seed: int = 0) -> None:
        self.width, self.height, self.hfov, self.view_name = width, height, hfov, view
        self.pano = _Panorama(width, height, hfov, floor_view=(view == 'bottom'))
        self.focal = (width / 2.0) / math.tan(hfov / 2.0)
        self.frame = 0
        self.hue = {'front': 0, 'bottom': 45, 'realsense': 90, 'stereo': 130}.get(view, 0)

    def render(self, t: float, shift: int = 0, disparity_scale: float = 0.0,
               view: Optional[Pose] = None) -> np.ndarray:
        """The picture from `view` (x, y and the yaw the camera looks along: base + head)."""
        import cv2  # OpenCV takes half a second to import: only where the emulator draws
        x, y, yaw = view or robot_pose(t)
        img = self.pano.view(yaw, shift)
        w, h = self.width, self.height
        # the person, where the laser sees it
        if self.view_name != 'bottom':
            px, py = person_position(t)
            dx, dy = px - x, py - y
            dist = math.hypot(dx, dy)
            bearing = math.atan2(dy, dx) - yaw
            bearing = math.atan2(math.sin(bearing), math.cos(bearing))
            if abs(bearing) < self.hfov / 2 + 0.2 and dist > 0.3:
                u = int(w / 2 - self.focal * math.tan(bearing) + disparity_scale / dist)
                half = max(2, int(self.focal * PERSON_RADIUS / dist))
                tall = int(self.focal * 1.2 / dist)
                base = self.pano.horizon_row + int(self.focal * 0.9 / dist)
                cv2.rectangle(img, (u - half, base - tall), (u + half, base), (40, 70, 150), -1)
                cv2.circle(img, (u, base - tall - half), half, (220, 180, 150), -1)
        # a ball bouncing through the picture
        period = 4.0 + self.hue / 60.0
        phase = (t % period) / period
        sweep = 2 * phase if phase < 0.5 else 2 * (1.0 - phase)
        bx = int(w * (0.1 + 0.8 * sweep))
        by = int(h * (0.85 - 0.45 * abs(math.sin(math.pi * 2 * t / 1.7))))
        r = max(3, w // 24)
        cv2.circle(img, (bx + int(disparity_scale / 1.5), by), r, _hsv_colour(self.hue + 100), -1)
        # frame counter and clock
        self.frame += 1
        scale = max(0.3, w / 640.0)
        cv2.putText(img, '%s %05d t=%.1f' % (self.view_name, self.frame, t), (4, int(14 * scale * 1.5)),
                    cv2.FONT_HERSHEY_SIMPLEX, 0.5 * scale, (255, 255, 255), 1, cv2.LINE_AA)
        return img


class InfraredCamera:
    """An infrared camera's 16-bit frames (naoqi_driver's camera/ir, 16UC1: camera.cpp:215-224):
    the room's grey as the colour cameras see it, in 10 bits (0-1023, the Xtion's IR range),
    lit by the camera's own projector (no room light needed)."""

    BITS = 10

    def __init__(self, width: int, height: int, hfov: float, view: str = 'ir') -> None:
        self.colour = ColourCamera(width, height, hfov, view=view)

    def render(self, t: float, view: Optional[Pose] = None) -> np.ndarray:
        rgb = self.colour.render(t, view=view).astype(np.uint16)
        grey = (rgb[:, :, 0] * 77 + rgb[:, :, 1] * 150 + rgb[:, :, 2] * 29) >> 8     # BT.601 luma, 0-255
        return (grey << (self.BITS - 8)).astype(np.uint16)


class StereoCamera:
    """Pepper's stereo camera: two views side by side (each half the width), slightly shifted."""

    BASELINE_PX = 6

    def __init__(self, width: int, height: int, hfov: float) -> None:
        self.half = width // 2
        self.width, self.height = width, height
        self.left = ColourCamera(self.half, height, hfov, view='stereo')

    def render(self, t: float, view: Optional[Pose] = None) -> np.ndarray:
        out = np.empty((self.height, self.width, 3), np.uint8)
        out[:, :self.half] = self.left.render(t, shift=0, disparity_scale=0.0, view=view)
        self.left.frame -= 1
        out[:, self.half:] = self.left.render(t, shift=self.BASELINE_PX,
                                              disparity_scale=-self.BASELINE_PX * 3.0, view=view)
        return out


# ---------------------------------------------------------------- depth images

class DepthCamera:
    """16UC1 depth in millimetres: walls and obstacles by ray casting, floor plane, a ball,
    and a few invalid (0) pixels, as a structured-light sensor gives."""

    HEIGHT_M = 1.0        # camera height above the floor
    MIN_MM, MAX_MM = 400, 6000

    def __init__(self, width: int, height: int, hfov: float, seed: int = 0) -> None:
        self.width, self.height = width, height
        self.focal = (width / 2.0) / math.tan(hfov / 2.0)
        cols = np.arange(width, dtype=np.float64)
        self.col_angles = np.arctan((width / 2.0 - cols) / self.focal)   # left of centre = +
        self.cos_cols = np.cos(self.col_angles)
        self.horizon = int(height * 0.35)
        rows = np.arange(height, dtype=np.float64)
        below = rows - self.horizon
        with np.errstate(divide='ignore'):
            floor = np.where(below > 0, self.HEIGHT_M * self.focal / np.maximum(below, 1e-9), np.inf)
        self.floor_mm = (floor * 1000.0).astype(np.float32)[:, None]
        self.rng = np.random.default_rng(seed)
        self.n_invalid = max(1, width * height // 300)

    def render(self, t: float, view: Optional[Pose] = None, circles: Circles = ()) -> np.ndarray:
        import cv2  # OpenCV takes half a second to import: only where the emulator draws
        x, y, yaw = view or robot_pose(t)
        dist = raycast(x, y, yaw + self.col_angles, t, circles)
        wall_mm = (dist * self.cos_cols * 1000.0).astype(np.float32)[None, :]
        depth = np.minimum(self.floor_mm, wall_mm)
        img = np.clip(depth, 0, self.MAX_MM).astype(np.uint16)
        # a ball bouncing 1.2 m in front
        w, h = self.width, self.height
        bx = int(w * (0.5 + 0.35 * math.sin(2 * math.pi * t / 5.0)))
        by = int(h * (0.6 - 0.25 * abs(math.sin(math.pi * t / 1.7))))
        cv2.circle(img, (bx, by), max(3, w // 16), 1200, -1)
        img[img < self.MIN_MM] = 0
        # speckle of invalid pixels
        idx = self.rng.integers(0, w * h, self.n_invalid)
        img.reshape(-1)[idx] = 0
        return img


# ---------------------------------------------------------------- range sensors

# Pepper's three laser devices (right, front, left) as (yaw, x, y) in base_footprint, the static
# transforms naoqi_driver's converter applies (ros-naoqi/naoqi_driver src/converters/laser.cpp):
# right rotated by -1.757 rad and shifted by (-0.018, -0.090) (:170-171), front shifted by
# (0.056, 0) (:185-186), left rotated by +1.757 rad and shifted by (-0.018, +0.090) (:199-200);
# 15 rays over +-0.5236 rad each, here right to left (pepperGazeboCPU.xacro:778-871, the
# simulator's lasers at the same frames).
LASERS = ((-1.757, -0.018, -0.090), (0.0, 0.056, 0.0), (1.757, -0.018, 0.090))
LASER_RAYS = np.linspace(-0.5235987755982988, 0.5235987755982988, 15)
GAZEBO_LASER_MIN, GAZEBO_LASER_MAX = 0.3, 7.0


def laser_device_points(t: float, bias: float, noise: float, rng: np.random.Generator,
                        pose: Optional[Pose] = None, circles: Circles = ()) -> Tuple[np.ndarray, np.ndarray]:
    """Each device's 15 rays cast from its own position and heading: the points (x, y) in the
    device's own frame, arrays of shape (3, 15), devices as LASERS, rays as LASER_RAYS. The
    range along each ray carries `bias` plus Gaussian noise of sd `noise`."""
    x, y, yaw = pose or robot_pose(t)
    c, s_ = math.cos(yaw), math.sin(yaw)
    ranges = np.empty((len(LASERS), LASER_RAYS.size))
    for k, (sensor_yaw, ox, oy) in enumerate(LASERS):
        wx, wy = x + c * ox - s_ * oy, y + s_ * ox + c * oy
        ranges[k] = raycast(wx, wy, yaw + sensor_yaw + LASER_RAYS, t, circles)
    ranges += bias + rng.normal(0.0, noise, ranges.shape)
    return ranges * np.cos(LASER_RAYS), ranges * np.sin(LASER_RAYS)


def laser_to_base(lx: np.ndarray, ly: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Device-frame points (rows as LASERS) in base_footprint: rotated by the device's yaw, then
    shifted by its position, as laser.cpp:170-171, 185-186, 199-200 do."""
    yaws, ox, oy = (np.array(col)[:, None] for col in zip(*LASERS))
    c, s_ = np.cos(yaws), np.sin(yaws)
    return lx * c - ly * s_ + ox, lx * s_ + ly * c + oy


def laser_ranges(t: float, blind_mask: Union[np.ndarray, Sequence[bool]], noise: float,
                 rng: np.random.Generator, dead: Optional[int] = None,
                 pose: Optional[Pose] = None, circles: Circles = ()) -> np.ndarray:
    """naoqi_driver's 61-slot scan, built as laser.cpp:165-205 builds it: ALMemory holds each
    device's Seg01..Seg15 as X/Y in the device's frame, ordered left to right (:158-161); the
    driver converts each point to base_footprint and writes its raw distance (no clipping),
    reversed per device ("segments are internally flipped": Seg15 first, result_value[28-i],
    [58-i], [88-i] at :168, :183, :197) into the device's 15 slots, 8 blind slots between
    (:178, :193) that keep -1.0 (reset(), :221). `dead` (a row of LASERS): that board stopped,
    its X and Y read 0 in ALMemory, so the driver writes the board's mounting offset."""
    lx, ly = laser_device_points(t, 0.0, noise, rng, pose, circles)
    if dead is not None:
        lx[dead], ly[dead] = 0.0, 0.0
    seg_x, seg_y = lx[:, ::-1], ly[:, ::-1]            # ALMemory's Seg01..Seg15: left to right
    bx, by = laser_to_base(seg_x, seg_y)
    dist = np.hypot(bx, by)
    blind = np.asarray(blind_mask, dtype=bool)
    slots = np.flatnonzero(~blind).reshape(len(LASERS), LASER_RAYS.size)   # 0-14, 23-37, 46-60
    d = np.full(blind.size, -1.0)
    d[slots] = dist[:, ::-1]                           # slot pos <- Seg(15 - pos): 28-i, 58-i, 88-i
    return d.astype(np.float32)


def gazebo_laser_points(t: float, noise: float, rng: np.random.Generator, pose: Optional[Pose] = None,
                        circles: Circles = ()) -> Tuple[np.ndarray, np.ndarray]:
    """The simulator's 45 laser points as (distance, angle) from base_footprint: each ray's
    range with Gazebo's noise (mean 0.01, sd `noise`), moved into base_footprint as
    laser_publisher.py:308-362 does (do_transform_cloud with each laser's static transform).
    A ray that hits nothing within 7 m gives no point: NaN here, which pc_to_laser skips
    (laser_publisher.py:464-477, `if not isnan(angle)` ... "nan, not adding anything to
    scan"), so its slot stays NaN (an infinite point would give atan2 = +-pi/4, a real slot)."""
    lx, ly = laser_device_points(t, 0.01, noise, rng, pose, circles)
    miss = np.hypot(lx, ly) > GAZEBO_LASER_MAX
    lx, ly = np.where(miss, np.nan, lx), np.where(miss, np.nan, ly)
    bx, by = laser_to_base(lx, ly)
    return np.hypot(bx, by).reshape(-1), np.arctan2(by, bx).reshape(-1)


def sonar_range(t: float, back: bool, noise: float, rng: np.random.Generator, pose: Optional[Pose] = None,
                circles: Circles = (), panes: Panes = ()) -> float:
    """Pepper's raw sonar distance (ALMemory .../Sonar/Sensor/Value), not clipped to the 2.55 m
    naoqi_driver advertises: the nearest of a few rays in the cone."""
    x, y, yaw = pose or robot_pose(t)
    heading = yaw + (math.pi if back else 0.0)
    d = float(np.min(raycast(x, y, heading + np.array([-0.2, 0.0, 0.2]), t, circles, panes)))
    return d + float(rng.normal(0.0, noise))


def gazebo_sonar_range(t: float, back: bool, range_max: float, noise: float, rng: np.random.Generator,
                       pose: Optional[Pose] = None, circles: Circles = (), panes: Panes = ()) -> float:
    """gazebo_ros_range: the nearest of 5x5 rays over +-0.52 rad, plus Gaussian noise, limited
    to range_max (ros-simulation/gazebo_ros_pkgs gazebo_plugins/src/gazebo_ros_range.cpp)."""
    x, y, yaw = pose or robot_pose(t)
    heading = yaw + (math.pi if back else 0.0)
    d = float(np.min(raycast(x, y, heading + np.linspace(-0.52, 0.52, 5), t, circles, panes)))
    d = min(d, range_max)
    if d < range_max:
        d = min(d + float(rng.normal(0.0, noise)), range_max)
    return d
