"""`pepperEmulator --list-faults`: the faults of faults.FAULTS as a table that fits 80 columns:
fault (with its value), the sensors it applies to, and what it does. The effects are the short
form of docs/emulator.md's table; a fault added to faults.py without one here still gets a row
(pointing at the docs), so the table never hides one."""
import textwrap
from typing import Optional, Sequence

from . import faults

EFFECTS = {
    'silent': 'topic advertised, never published',
    'rate': 'the rate times VALUE (on top of ~rate_factor)',
    'die_after': 'publishes until VALUE s after the start, then unregisters',
    'wrong_type': 'std_msgs/String on the sensor\'s topic',
    'frozen': 'the same image bytes in every frame',
    'black': 'all-zero image',
    'wrong_encoding': 'encoding label does not match the data',
    'wrong_step': 'step half of width x bytes per pixel',
    'nan': 'NaN in the values (laser beams, range, joints, pose, rates)',
    'out_of_range': 'physically impossible values',
    'broken_quaternion': 'orientation of norm 1.8',
    'nan_attitude': 'orientation NaN (covariance[0] still -1)',
    'all_blind': 'every laser slot blind',
    'no_returns': 'simulator: every laser slot NaN (no return)',
    'stuck': 'one message\'s data republished with new stamps',
    'after': 'stuck, frozen, black or silent_channel begin VALUE s after the first '
                   'subscriber (a partial failure)',
    'dead_accelerometer': 'linear acceleration 0, 0, 0',
    'gyro_overrange': '12 rad/s about z, beyond the gyrometer\'s range',
    'joint_jump': 'HeadYaw jumps -2 / +2 rad every 0.25 s',
    'pose_jump': 'x jumps by 1 m every 2 s',
    'twist_mismatch': 'twist 0.4 m/s whatever the pose does',
    'far_depth': 'every pixel about 20 m',
    'flat_depth': 'every pixel 1.5 m, no noise',
    'dead_board': 'board VALUE (right, front or left) stopped: naoqi_driver turns its x = y = 0 '
                  'into the mounting offset (0.056 m front, 0.092 m sides) in every slot',
    'nan_board': 'board VALUE NaN in every slot, as yohatad/naoqi_driver2 publishes a board '
                 'whose frame counter stopped',
    'spike': 'the pose leaps 25 m for one message in every eight and comes back',
    'silent_channel': 'channel VALUE all zeros: rearLeft, rearRight, frontLeft or frontRight '
                      '(several: a|b); needs ~audio direct (with the bridge: the launch arg '
                      'silent_channel)',
    'copied_channels': 'rearLeft\'s samples in all four channels: a bridge filling every '
                       'channel from one buffer; needs ~audio direct',
    'planar_as_interleaved': 'each buffer\'s planar samples read as interleaved: channel c '
                             'gets samples c, c+4, ... of one microphone; needs ~audio direct',
    'blur': 'out of focus: a 5 x 5 box blur (passes; a drift of its sharpness)',
    'dim': 'brightness times VALUE, e.g. 0.6: a dusty lens (passes; a drift)',
    'gyro_bias': 'VALUE rad/s added about x: a drifting gyrometer (passes; a drift)',
    'noisy': 'four times the noise of a sonar or the joint encoders (passes; a drift)',
    'scratched': 'board VALUE\'s window scratched: a third of its points read as a stopped '
                 'board\'s, each scan (passes; a drift of its valid share)',
    'quiet_channel': 'channel VALUE 12 dB quieter: a clogged grille; needs ~audio direct '
                     '(passes; a drift)',
    'gyro_inverted': 'angular velocity of the opposite sign (all three axes)',
    'dead_gyro': 'angular velocity 0, 0, 0 whatever the base does',
    'swapped_axes': 'x and z exchanged (gyro and accelerometer)',
    'frozen_pose': 'pose and twist of the start while the wheels turn',
    'stuck_joint': 'joint VALUE (e.g. HeadYaw) reads its start angle whatever it does',
    'reversed': 'the beams in the opposite order (left first)',
    'not_following': 'a live picture that does not pan with the head',
    'glass': 'a glass pane 0.8 m away (ahead, behind for the back sonar): the sonar sees '
             'it, the laser sees through',
    'clock_offset': 'header stamps VALUE s (signed) off the other sensors\'',
    'resting': 'stiffness 0 in /diagnostics, every motion command ignored',
    'base_blocked': 'awake, the head obeys, the base refuses to move',
    'obstacle': 'a box 0.35 m in front of the base (laser and sonars)',
    'no_description': 'naoqi_driver without its robot description: /tf carries odom -> base_link alone',
    'second_publisher': 'a second node publishes Head -> CameraTop_frame 1 cm off the driver\'s',
    'stale': '/tf stamps 0.8 s behind their publication',
    'future_stamps': '/tf stamps 1.0 s ahead of their publication',
}
KIND_NAMES = {'camera': 'cameras', 'depth': 'depth cameras', 'range': 'sonars', 'laser': 'laser',
              'audio': 'microphone', 'joints': 'jointState',
              'odometry': 'odometry', 'imu': 'imu', 'touch': 'touch, bumper',
              'health': 'robotHealth', 'robot': 'robot (conditions)', 'tf': 'tf'}


def applies_to(kinds: Optional[Sequence[str]]) -> str:
    if kinds is None:
        return 'every sensor'
    return ', '.join(KIND_NAMES.get(k, k) for k in kinds)


def table(width: int = 79) -> str:
    rows = [(name + ('=VALUE' if takes else ''), applies_to(kinds),
             EFFECTS.get(name, 'see docs/emulator.md'))
            for name, (takes, kinds) in faults.FAULTS.items()]
    w1 = max(len('fault'), *(len(r[0]) for r in rows))
    w2 = min(24, max(len(r[1]) for r in rows))
    w3 = max(20, width - w1 - w2 - 4)
    lines = ['usage: ~faults "sensor:fault[=VALUE][,fault...][;sensor:...]"',
             '  e.g. "frontCamera:frozen;laser:nan;jointState:die_after=3"', '',
             '%-*s  %-*s  %s' % (w1, 'fault', w2, 'applies to', 'effect'),
             '%s  %s  %s' % ('-' * w1, '-' * w2, '-' * min(w3, 30))]
    for fault, where, effect in rows:
        left = textwrap.wrap(where, w2) or ['']
        right = textwrap.wrap(effect, w3, break_long_words=False) or ['']
        for i in range(max(len(left), len(right))):
            lines.append(('%-*s  %-*s  %s' % (w1, fault if i == 0 else '', w2,
                                              left[i] if i < len(left) else '',
                                              right[i] if i < len(right) else '')).rstrip())
    lines += ['', 'sensors: ' + faults.valid_sensors()]
    return '\n'.join(textwrap.fill(ln, width, subsequent_indent='  ') if ln.startswith('sensors:')
                     else ln for ln in lines)
