"""When the motion check may move, and when it must stop (pure functions of a record.Recording).

Before moving (`base_blocked`, `head_blocked`), from the robot's own sensors:
- free space: nothing within `clearance` (0.5 m) of the laser or the sonars; a 0.5 rad turn in
  place sweeps Pepper's base (about 0.25 m half-width), and ALMotion's own collision
  protection refuses or cuts a move near an obstacle anyway (ALMotion "external collision
  protection", security distance about 0.1-0.2 m): better said before than seen as a refusal;
- no bumper pressed (naoqi_driver's bumper events, src/event/touch.cpp);
- robot health not failing (an ERROR status of naoqi_driver on /diagnostics:
  src/converters/diagnostics.cpp:176-191, e.g. a joint "Too hot");
- joints stiff: naoqi_driver's per-joint Stiffness in /diagnostics
  (src/converters/diagnostics.cpp:164-170). A resting robot (rest() / Autonomous Life off:
  stiffness 0) ignores every motion command, so the person is asked to wake it up.
If the base may not move, the base part is SKIPPED with that reason and the head part still
runs (unless the head itself is not stiff).

While moving (`stop_reason`): a bumper pressed, or anything closer than `stop_distance` (0.3 m)
to the laser or a sonar, stops the base at once.
"""
import math
from typing import List, Optional, Sequence

from .record import Recording

BUMPERS = {0: 'right', 1: 'left', 2: 'back'}      # naoqi_bridge_msgs/Bumper constants
HEAD_JOINTS = ('HeadYaw', 'HeadPitch')
BASE_JOINTS = ('WheelFL', 'WheelFR', 'WheelB')


def where(angle: float) -> str:
    deg = math.degrees(angle)
    side = 'ahead' if abs(deg) < 20 else ('to the left' if deg > 0 else 'to the right')
    return '%s (%+.0f deg)' % (side, deg)


def nearest(rec: Recording, within: float) -> Optional[str]:
    """The nearest thing within `within` m, in words; None when the space is free (or unseen)."""
    found: List[str] = []
    with rec.lock:
        if rec.laser_nearest is not None and rec.laser_nearest[1] < within:
            found.append('the laser sees something %.2f m away %s'
                         % (rec.laser_nearest[1], where(rec.laser_nearest[2])))
        for name, (_, r) in sorted(rec.sonar.items()):
            if r < within:
                found.append('the %s sonar sees something %.2f m away'
                             % ('front' if name == 'frontSonar' else 'back', r))
    return '; '.join(found) or None


def pressed(rec: Recording) -> Optional[str]:
    with rec.lock:
        on = [BUMPERS.get(b, str(b)) for b, p in sorted(rec.bumpers.items()) if p]
    return ('the %s bumper is pressed' % ' and '.join(on)) if on else None


def not_stiff(rec: Recording, joints: Sequence[str], min_stiffness: float) -> Optional[str]:
    with rec.lock:
        limp = ['%s %.2f' % (j, rec.stiffness[j]) for j in joints
                if j in rec.stiffness and rec.stiffness[j] < min_stiffness]
    if not limp:
        return None
    return ('the robot is resting: stiffness %s in /diagnostics (below %.2f), so ALMotion ignores '
            'motion commands; wake it up (press the chest button once, or ALMotion.wakeUp / '
            'ALAutonomousLife) and run again' % (', '.join(limp), min_stiffness))


def base_blocked(rec: Recording, clearance: float, min_stiffness: float, heard_laser: bool,
                 heard_sonar: bool) -> Optional[str]:
    """Why the base may not turn; None: it may."""
    limp = not_stiff(rec, BASE_JOINTS + HEAD_JOINTS, min_stiffness)
    if limp:
        return limp
    hit = pressed(rec)
    if hit:
        return hit + ': free the robot first'
    with rec.lock:
        health = rec.health_error
    if health:
        return 'robot health is failing (%s)' % health
    if not heard_laser and not heard_sonar:
        return ('no laser scan and no sonar reading arrived: the space around the base cannot be '
                'checked, so the base does not move')
    obstacle = nearest(rec, clearance)
    if obstacle:
        return 'not enough free space (nothing may be within %.2f m): %s' % (clearance, obstacle)
    return None


def head_blocked(rec: Recording, min_stiffness: float) -> Optional[str]:
    return not_stiff(rec, HEAD_JOINTS, min_stiffness)


def stop_reason(rec: Recording, stop_distance: float) -> Optional[str]:
    """Why a base motion must stop now; None: it may go on."""
    hit = pressed(rec)
    if hit:
        return hit
    obstacle = nearest(rec, stop_distance)
    if obstacle:
        return 'obstacle closer than %.2f m: %s' % (stop_distance, obstacle)
    return None
