"""The emulated robot's body: a state that the motion commands change, advanced in time.

What ALMotion would do with the three commands naoqi_driver forwards (emulator/commands.py):

- move(vx, vy, vth) (/cmd_vel, ros-naoqi/naoqi_driver src/subscribers/teleop.cpp:44-53): the
  base keeps that velocity, in its own frame, until the next command; a zero twist stops it.
  "motion clamps the velocities internally" (teleop.cpp:46): to MAX_VEL_XY and MAX_VEL_THETA.
- moveTo(x, y, yaw) (/move_base_simple/goal, src/subscribers/moveto.cpp:104-121): a pose
  relative to where the base stands; the base drives there and stops by itself (bounded). A
  moveTo replaces a running move() and the other way round: ALMotion runs one locomotion task.
- setAngles / changeAngles (/joint_angles, teleop.cpp:55-65): each named joint goes towards its
  target (changeAngles: the current angle plus the change) at `speed` x its maximum velocity
  (pepper.urdf `<limit velocity>`, sensors/joint_limits.py), clipped to its limits.

Velocities and accelerations of the base are ALMotion's default move config on Pepper
(doc.aldebaran.com/2-5/naoqi/motion/control-walk.html, "Move config", Pepper: MaxVelXY 0.35 m/s,
MaxVelTheta 1.0 rad/s, MaxAccXY 0.3 m/s^2, MaxAccTheta 0.75 rad/s^2). The wheels are Pepper's
three omni wheels (pepper.urdf:1398-1456, ros-naoqi/pepper_robot 60d4e08): WheelFL at
(0.09, 0.155) turned 1.07517 rad, WheelFR at (0.09, -0.155) turned -1.07517 rad, WheelB at
(-0.17, 0) turned pi, each spinning about its own x axis (axis 1 0 0), all three pointing
outwards from the centre, radius 0.07 m (wheel centres at z -0.264, base_footprint at -0.334 from
Tibia, pepper.urdf:143; the Gazebo drive's wheelDiameter 0.140, :2323). A wheel's spin is the
base's velocity at the wheel along its rolling direction (axis x z) over the radius: turning in
place, all three spin the same way.

Robot conditions (the `robot:` faults): resting (ALMotion.rest(): stiffness off; "when at zero
Stiffness, you can send any commands to the motors, but he will not move",
doc.aldebaran.com/2-0/naoqi/motion/control-stiffness.html; the rest posture has the head down,
doc.aldebaran.com/2-0/family/juliette_technical/wake_rest_juliette.html), base_blocked (awake,
the head obeys, locomotion refused: power hatch open, "ALMotion API are prohibited if power
hatch is open", control-walk.html; or the Secure Move API that does not launch a move towards
an obstacle, reflexes-external-collision.html), obstacle (a bin in front of the start pose;
the robot then stands there, no idle drive).

The idle drive: unless ~condition still, the robot starts driving slowly in a circle (someone
else's move(): scene.robot_pose is its closed form). It stops, as a zero move() would stop it,
as soon as a publisher connects to one of the command topics or a command arrives: a run that
commands the robot starts on a still robot.

Every reader calls snapshot(t): the state advanced to scene time t (steps of STEP s), under a
lock, so all streams see one body.
"""
import math
import threading
from dataclasses import dataclass
from typing import Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np

from ..sensors import joint_limits
from . import scene

MAX_VEL_XY, MAX_VEL_THETA = 0.35, 1.0       # m/s, rad/s: Pepper's default move config
MAX_ACC_XY, MAX_ACC_THETA = 0.3, 0.75       # m/s^2, rad/s^2
STEP = 0.01                                 # s of scene time per integration step
GOAL_XY, GOAL_THETA = 0.002, 0.002          # m, rad: a moveTo is done within these
WHEEL_RADIUS = 0.07
# name -> (x, y, yaw of the wheel's axis) in the base frame (pepper.urdf:1401, 1453, 1427)
WHEELS = {'WheelFL': (0.09, 0.155, 1.07517), 'WheelFR': (0.09, -0.155, -1.07517),
          'WheelB': (-0.17, 0.0, -3.14159)}
# standing pose (rad; hands 0..1 open); every joint ALMotion.setAngles may move on Pepper
STAND = {'HeadYaw': 0.0, 'HeadPitch': -0.2, 'HipRoll': 0.0, 'HipPitch': -0.03, 'KneePitch': 0.0,
         'LShoulderPitch': 1.56, 'LShoulderRoll': 0.14, 'LElbowYaw': -1.22, 'LElbowRoll': -0.52,
         'LWristYaw': -0.86, 'LHand': 0.6, 'RShoulderPitch': 1.56, 'RShoulderRoll': -0.14,
         'RElbowYaw': 1.22, 'RElbowRoll': 0.52, 'RWristYaw': 0.86, 'RHand': 0.6}
REST_HEAD_PITCH = 0.5                       # resting: the head down (pitch > 0 is down)
# ALMotion's chain names (doc.aldebaran.com/2-5/family/pepper_technical/bodyparts_pep.html)
CHAINS = {'Head': ('HeadYaw', 'HeadPitch'),
          'LArm': ('LShoulderPitch', 'LShoulderRoll', 'LElbowYaw', 'LElbowRoll', 'LWristYaw', 'LHand'),
          'RArm': ('RShoulderPitch', 'RShoulderRoll', 'RElbowYaw', 'RElbowRoll', 'RWristYaw', 'RHand'),
          'Leg': ('HipRoll', 'HipPitch', 'KneePitch')}
CHAINS['Body'] = tuple(STAND)
OBSTACLE = (0.47, 0.0, 0.12)     # x, y, radius in the start frame: its near side 0.35 m ahead


class CommandError(ValueError):
    """A command ALMotion would reject (unknown joint, lengths that differ, NaN)."""


@dataclass(frozen=True)
class Snapshot:
    """The body at one instant: base pose in the odom frame, velocities in the base frame."""
    t: float
    x: float
    y: float
    yaw: float
    vx: float
    vy: float
    wz: float
    ax: float                   # specific force in the base frame, gravity apart (m/s^2)
    ay: float
    joints: Dict[str, float]    # the 17 joints of STAND
    joint_velocities: Dict[str, float]
    wheels: Dict[str, float]    # wheel angles, wrapped to [-pi, pi)
    wheel_velocities: Dict[str, float]
    stiffness: float

    @property
    def view_yaw(self) -> float:
        """Where the head cameras look: the base's yaw plus HeadYaw."""
        return self.yaw + self.joints['HeadYaw']


def wheel_speeds(vx: float, vy: float, wz: float) -> Dict[str, float]:
    """Each wheel's spin (rad/s about its own axis) for a base velocity (base frame): the
    velocity of the wheel's centre, (vx - wz y, vy + wz x), along the rolling direction
    axis x z = (sin a, -cos a), over the radius."""
    out = {}
    for name, (px, py, a) in WHEELS.items():
        cx, cy = vx - wz * py, vy + wz * px
        out[name] = (cx * math.sin(a) - cy * math.cos(a)) / WHEEL_RADIUS
    return out


def _wrap(a: float) -> float:
    return (a + math.pi) % (2 * math.pi) - math.pi


def _approach(value: float, target: float, step: float) -> float:
    return target if abs(target - value) <= step else value + math.copysign(step, target - value)


class Body:
    """The state; every method takes the scene time t (seconds, Clock.now())."""

    def __init__(self, idle: bool = True, seed: int = 0, resting: bool = False,
                 base_blocked: bool = False, obstacle: bool = False) -> None:
        self.lock = threading.Lock()
        self.resting, self.base_blocked, self.obstacle = resting, base_blocked, obstacle
        self.t = 0.0
        self.x = self.y = self.yaw = 0.0
        # a robot that cannot drive, or that stands before an obstacle, does not drive around
        idle = idle and not resting and not base_blocked and not obstacle
        self.cmd: Optional[Tuple[float, float, float]] = \
            (scene.LINEAR_SPEED, 0.0, scene.ANGULAR_SPEED) if idle else None
        self.idle = idle
        self.v = list(self.cmd) if self.cmd else [0.0, 0.0, 0.0]
        self.acc = [0.0, 0.0]
        self.goal: Optional[Tuple[float, float, float]] = None     # moveTo's goal, odom frame
        self.wheels = {w: 0.0 for w in WHEELS}
        # the joints' sway (Autonomous Life's breathing) until a command takes a joint over
        rng = np.random.default_rng(seed)
        n = len(STAND)
        self.amp = dict(zip(STAND, 0.02 + 0.08 * rng.random(n)))
        self.freq = dict(zip(STAND, 0.1 + 0.3 * rng.random(n)))
        self.phase = dict(zip(STAND, 2 * math.pi * rng.random(n)))
        self.held: Dict[str, float] = {}            # joint -> angle it is held at / moving from
        self.targets: Dict[str, Tuple[float, float]] = {}   # joint -> (target, rad/s)
        self.joint_v: Dict[str, float] = {}
        if resting:
            self.held = dict(STAND, HeadPitch=REST_HEAD_PITCH)
        self.expected: Optional[Callable[[], bool]] = None
        self.next_watch = 0.0
        self.log: Callable[[str], None] = lambda text: None

    # ------------------------------------------------------------ commands
    def _stop_idle(self, why: str) -> None:
        if self.idle:
            self.idle = False
            self.cmd = None
            self.log('the idle drive stops (%s)' % why)

    def move(self, t: float, vx: float, vy: float, wz: float) -> bool:
        """ALMotion.move: False when refused (resting, base blocked)."""
        if not all(math.isfinite(v) for v in (vx, vy, wz)):
            raise CommandError('move(%r, %r, %r): not a number' % (vx, vy, wz))
        with self.lock:
            self._advance(t)
            self._stop_idle('a move() command')
            if self.resting or self.base_blocked:
                return False
            speed = math.hypot(vx, vy)
            if speed > MAX_VEL_XY:
                vx, vy = vx * MAX_VEL_XY / speed, vy * MAX_VEL_XY / speed
            wz = max(-MAX_VEL_THETA, min(MAX_VEL_THETA, wz))
            self.goal = None                    # a move() replaces a running moveTo
            self.cmd = (vx, vy, wz) if (vx, vy, wz) != (0.0, 0.0, 0.0) else None
            return True

    def move_to(self, t: float, dx: float, dy: float, dyaw: float, frame: str = 'base_footprint') -> bool:
        """ALMotion.moveTo(dx, dy, dyaw) relative to the base (frame 'odom': the goal is a pose
        of the odom frame, as naoqi_driver transforms it to base_footprint first)."""
        if not all(math.isfinite(v) for v in (dx, dy, dyaw)):
            raise CommandError('moveTo(%r, %r, %r): not a number' % (dx, dy, dyaw))
        with self.lock:
            self._advance(t)
            self._stop_idle('a moveTo() command')
            if self.resting or self.base_blocked:
                return False
            if frame == 'odom':
                self.goal = (dx, dy, _wrap(dyaw))
            else:
                c, s = math.cos(self.yaw), math.sin(self.yaw)
                self.goal = (self.x + c * dx - s * dy, self.y + s * dx + c * dy, _wrap(self.yaw + dyaw))
            self.cmd = None                     # a moveTo replaces a running move()
            return True

    def set_angles(self, t: float, names: Sequence[str], angles: Sequence[float], speed: float,
                   relative: bool = False) -> bool:
        """ALMotion.setAngles (changeAngles when relative): False when refused (resting)."""
        joints: List[str] = []
        for name in names:
            if name in CHAINS:
                joints.extend(CHAINS[name])
            elif name in STAND:
                joints.append(name)
            else:
                raise CommandError('unknown joint or chain "%s" (ALMotion knows %s and the '
                                   'chains %s)' % (name, ', '.join(STAND), ', '.join(CHAINS)))
        if len(angles) != len(joints):
            raise CommandError('%d angles for %d joints (%s)' % (len(angles), len(joints), ', '.join(joints)))
        if not all(math.isfinite(a) for a in angles) or not math.isfinite(speed):
            raise CommandError('an angle or the speed is not a number')
        fraction = max(0.0, min(1.0, speed))
        with self.lock:
            self._advance(t)
            if self.resting:
                return False
            now = self._joints(self.t)
            for joint, angle in zip(joints, angles):
                lo, hi, vmax, _ = joint_limits.LIMITS[joint]
                target = now[joint] + angle if relative else angle
                if lo is not None and hi is not None:
                    target = max(lo, min(hi, target))
                self.held.setdefault(joint, now[joint])
                self.targets[joint] = (target, fraction * vmax)
            return True

    # ------------------------------------------------------------ time
    def _joints(self, t: float) -> Dict[str, float]:
        return {j: self.held[j] if j in self.held else
                STAND[j] + self.amp[j] * math.sin(2 * math.pi * self.freq[j] * t + self.phase[j])
                for j in STAND}

    def _sway_velocity(self, j: str, t: float) -> float:
        w = 2 * math.pi * self.freq[j]
        return self.amp[j] * w * math.cos(w * t + self.phase[j])

    def _base_target(self) -> Tuple[float, float, float]:
        if self.goal is None:
            return self.cmd or (0.0, 0.0, 0.0)
        gx, gy, gyaw = self.goal
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        ex, ey = c * (gx - self.x) + s * (gy - self.y), -s * (gx - self.x) + c * (gy - self.y)
        eth = _wrap(gyaw - self.yaw)
        dist = math.hypot(ex, ey)
        if dist < GOAL_XY and abs(eth) < GOAL_THETA:
            self.goal = None
            return (0.0, 0.0, 0.0)
        # the fastest speed from which the base still stops at the goal (0.9: a margin for the steps)
        vxy = min(MAX_VEL_XY, math.sqrt(2 * 0.9 * MAX_ACC_XY * dist)) if dist >= GOAL_XY else 0.0
        w = math.copysign(min(MAX_VEL_THETA, math.sqrt(2 * 0.9 * MAX_ACC_THETA * abs(eth))), eth) \
            if abs(eth) >= GOAL_THETA else 0.0
        return (ex / dist * vxy if dist else 0.0, ey / dist * vxy if dist else 0.0, w)

    def _step(self, dt: float) -> None:
        if self.expected is not None and self.idle and self.t >= self.next_watch:
            self.next_watch = self.t + 0.1
            if self.expected():
                self._stop_idle('a command publisher connected')
        tx, ty, tw = self._base_target()
        old = list(self.v)
        self.v[0] = _approach(self.v[0], tx, MAX_ACC_XY * dt)
        self.v[1] = _approach(self.v[1], ty, MAX_ACC_XY * dt)
        self.v[2] = _approach(self.v[2], tw, MAX_ACC_THETA * dt)
        vx, vy, wz = self.v
        # specific force in the base frame: dv/dt plus the turning of the frame
        self.acc = [(vx - old[0]) / dt - wz * vy, (vy - old[1]) / dt + wz * vx]
        mid = self.yaw + wz * dt / 2
        self.x += (vx * math.cos(mid) - vy * math.sin(mid)) * dt
        self.y += (vx * math.sin(mid) + vy * math.cos(mid)) * dt
        self.yaw = _wrap(self.yaw + wz * dt)
        for name, w in wheel_speeds(vx, vy, wz).items():
            self.wheels[name] = _wrap(self.wheels[name] + w * dt)
        self.joint_v = {}
        for joint, (target, speed) in list(self.targets.items()):
            before = self.held[joint]
            self.held[joint] = _approach(before, target, speed * dt)
            self.joint_v[joint] = (self.held[joint] - before) / dt
            if self.held[joint] == target:
                del self.targets[joint]
        self.t += dt

    def _advance(self, t: float) -> None:
        while self.t < t - 1e-9:
            self._step(min(STEP, t - self.t))

    def snapshot(self, t: float) -> Snapshot:
        with self.lock:
            self._advance(t)
            joints = self._joints(self.t)
            jv = {j: self.joint_v.get(j, 0.0) if j in self.held else self._sway_velocity(j, self.t)
                  for j in STAND}
            vx, vy, wz = self.v
            return Snapshot(self.t, self.x, self.y, self.yaw, vx, vy, wz, self.acc[0], self.acc[1],
                            joints, jv, dict(self.wheels), wheel_speeds(vx, vy, wz),
                            0.0 if self.resting else 1.0)

    def moving(self) -> bool:
        """True while a base motion or a joint motion is under way (tests, logs)."""
        with self.lock:
            return bool(self.targets) or self.goal is not None or any(abs(v) > 1e-6 for v in self.v)

    def circles(self) -> Tuple[Tuple[float, float, float], ...]:
        """Obstacles of the world (x, y, radius in the odom frame) that the body brings: the
        `robot:obstacle` bin."""
        return (OBSTACLE,) if self.obstacle else ()
