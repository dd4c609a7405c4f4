"""ALMemory's keys for the fake NAOqi (emulator/fake_naoqi.py), read from the emulator's world.

naoqi_driver reads a Pepper's sensors as ALMemory keys (getListData / getData); each value here
comes from the same scene (scene.py) that drives the emulator's own ROS streams, so what the
real driver makes of them can be held against what the emulator publishes. File:line
references are to ros-naoqi/naoqi_driver master (aed1b87e).

- sonar: Device/SubDeviceList/Platform/{Front,Back}/Sonar/Sensor/Value, the raw distance in m
  (src/converters/sonar.cpp:50-51, 104-115) = scene.sonar_range;
- laser: 3 boards x Seg01..Seg15 X and Y in each board's frame, left to right
  (laser.cpp:37-128, read at :148 and reordered at :165-205) = scene.laser_device_points;
- IMU: DCM/Time then InertialSensor[Base] AngleX/Y/Z, GyroscopeX/Y/Z, AccelerometerX/Y/Z
  (imu.cpp:46-69, used at :103-118);
- joints and health: Device/SubDeviceList/<joint>/Temperature/Sensor/Value and
  /Hardness/Actuator/Value, the battery's BatteryChargeChanged, BatteryPowerPluggedChanged,
  BatteryFullChargedFlagChanged, Device/SubDeviceList/Battery/Current/Sensor/Value
  (diagnostics.cpp:77-79, 118-124, read in this order at :143 and :165-260);
  Motion/Velocity/Sensor/<joint> and Motion/Torque/Sensor/<joint> (joint_state.cpp:120-126);
- the robot's identity: RobotConfig/Body/Type, RobotConfig/Body/BaseVersion
  (driver_helpers.cpp:49-50) and the info converter's keys (info.cpp:40-58).

A key this module does not know is missing: getData raises (a FutureUserException in the
driver: joint_state.cpp:128-132 writes NaN) and getListData answers None in its slot, which the
driver's fromAnyValueToFloatVector turns into -1 (src/tools/from_any_value.cpp:186-199).
"""
from dataclasses import dataclass, field
from typing import Any, Dict, FrozenSet, List, Optional

import numpy as np

from . import scene
from .body import Body, Snapshot
from .info import DEFAULT_BODY_ID, identity_values
from .profiles import JOINT_NAMES, JOINTS_WITHOUT_VELOCITY

SONAR_KEY = 'Device/SubDeviceList/Platform/%s/Sonar/Sensor/Value'
LASER_KEY = 'Device/SubDeviceList/Platform/LaserSensor/%s/Horizontal/Seg%02d/%s/Sensor/Value'
LASER_BOARDS = ('Right', 'Front', 'Left')          # rows of scene.LASERS
IMU_KEY = 'Device/SubDeviceList/%s/%s/Sensor/Value'
IMU_FIELDS = ('AngleX', 'AngleY', 'AngleZ', 'GyroscopeX', 'GyroscopeY', 'GyroscopeZ',
              'AccelerometerX', 'AccelerometerY', 'AccelerometerZ')
TEMPERATURE_KEY = 'Device/SubDeviceList/%s/Temperature/Sensor/Value'
HARDNESS_KEY = 'Device/SubDeviceList/%s/Hardness/Actuator/Value'
# standing pose (rad; hands 0..1 open), as the emulator's joint_states (publishers.py _POSE)
POSE = {'HeadYaw': 0.0, 'HeadPitch': -0.2, 'HipRoll': 0.0, 'HipPitch': -0.03, 'KneePitch': 0.0,
        'LShoulderPitch': 1.56, 'LShoulderRoll': 0.14, 'LElbowYaw': -1.22, 'LElbowRoll': -0.52,
        'LWristYaw': -0.86, 'LHand': 0.6, 'RShoulderPitch': 1.56, 'RShoulderRoll': -0.14,
        'RElbowYaw': 1.22, 'RElbowRoll': 0.52, 'RWristYaw': 0.86, 'RHand': 0.6}
HOT = 75.0          # degC: above diagnostics.cpp's error level 74 (:56-57)


def joint_temperature(index: int, t: float) -> float:
    """A joint at work, degC: the emulator's own /diagnostics uses the same (events.py)."""
    return 30.0 + (index % 7) * 1.5 + 0.3 * ((int(t) + index) % 3)


@dataclass(frozen=True)
class WorldSettings:
    """What the fake NAOqi's world is: the head, the NAOqi version and the faults."""
    head: str = 'stereo'                    # stereo (Pepper 1.8, "CameraStereo") or xtion
    naoqi: str = '2.5.10.7'                 # ALSystem.systemVersion(); 2.9.x: no audio, no ALSonar
    missing_keys: FrozenSet[str] = field(default_factory=frozenset)   # ALMemory keys absent
    stuck_laser: Optional[str] = None       # a board (Right, Front, Left) whose keys never change
    hot_joint: Optional[str] = None         # a joint at HOT degC
    battery: float = 87.0                   # percent
    failing_camera: Optional[int] = None    # getImageRemote raises for this camera index
    touch: bool = False                     # FrontTactilTouched pressed and released every 2 s
    body_id: str = DEFAULT_BODY_ID          # Device/DeviceList/ChestBoard/BodyId, the robot's serial


class Memory:
    """ALMemory's values at scene time t (seconds since the fake started)."""

    def __init__(self, settings: WorldSettings, seed: int = 0) -> None:
        self.settings = settings
        self.rng = np.random.default_rng(seed)
        # the robot's state, as the emulator's own streams have it (body.py): the idle drive
        # until ALMotion is told to move (fake_naoqi.ALMotion passes the commands on)
        self.body = Body(idle=True, seed=seed)
        self.stuck: Dict[str, float] = {}
        self._laser_t = -1.0
        self._laser: Dict[str, float] = {}
        self.static: Dict[str, Any] = {
            **identity_values(settings.head, settings.body_id),   # info.py: the keys naoqi_driver's info topic reads
            'BatteryPowerPluggedChanged': 0.0, 'BatteryFullChargedFlagChanged': 0.0,
            'Device/SubDeviceList/Battery/Current/Sensor/Value': -1.2,
        }

    def has(self, key: str) -> bool:
        return key not in self.settings.missing_keys and self.value(key, 0.0) is not None

    def get(self, key: str, t: float) -> Any:
        """The value of `key` at t, or None for a key the robot does not have."""
        if key in self.settings.missing_keys:
            return None
        return self.value(key, t)

    def value(self, key: str, t: float) -> Any:
        if key in self.static:
            return self.static[key]
        if key == 'BatteryChargeChanged':
            return float(self.settings.battery)
        if key == 'DCM/Time':
            return int(t * 1000) % 2**31
        if key.startswith('Device/SubDeviceList/Platform/LaserSensor/'):
            return self._laser_value(key, t)
        for side, back in (('Front', False), ('Back', True)):
            if key == SONAR_KEY % side:
                snap = self.body.snapshot(t)
                return float(scene.sonar_range(t, back, 0.01, self.rng, (snap.x, snap.y, snap.yaw),
                                               self.body.circles()))
        if key.startswith('Device/SubDeviceList/InertialSensor'):
            return self._imu(key, t)
        for i, joint in enumerate(JOINT_NAMES):
            if key == TEMPERATURE_KEY % joint:
                return HOT if joint == self.settings.hot_joint else joint_temperature(i, t)
            if key == HARDNESS_KEY % joint:
                return float(self.body.snapshot(t).stiffness)
            if key in ('Motion/Velocity/Sensor/' + joint, 'Motion/Torque/Sensor/' + joint):
                if joint in JOINTS_WITHOUT_VELOCITY:
                    return None
                return 0.0
        return None

    def _laser_value(self, key: str, t: float) -> Optional[float]:
        if self._laser_t != t:
            snap = self.body.snapshot(t)
            lx, ly = scene.laser_device_points(t, 0.0, 0.01, self.rng, (snap.x, snap.y, snap.yaw),
                                               self.body.circles())
            self._laser = {}
            for row, board in enumerate(LASER_BOARDS):
                seg_x, seg_y = lx[row, ::-1], ly[row, ::-1]     # ALMemory: Seg01..15 left to right
                for i in range(scene.LASER_RAYS.size):
                    self._laser[LASER_KEY % (board, i + 1, 'X')] = float(seg_x[i])
                    self._laser[LASER_KEY % (board, i + 1, 'Y')] = float(seg_y[i])
            self._laser_t = t
        v = self._laser.get(key)
        if v is not None and self.settings.stuck_laser and '/%s/' % self.settings.stuck_laser in key:
            v = self.stuck.setdefault(key, v)       # the board's first reading, for ever
        return v

    def _imu(self, key: str, t: float) -> Optional[float]:
        snap = self.body.snapshot(t)
        n = float(self.rng.normal(0.0, 1.0))
        values = {'AngleX': 0.0, 'AngleY': 0.0, 'AngleZ': float(snap.yaw),
                  'GyroscopeX': 0.002 * n, 'GyroscopeY': 0.002 * n, 'GyroscopeZ': float(snap.wz) + 0.002 * n,
                  'AccelerometerX': float(snap.ax) + 0.02 * n, 'AccelerometerY': float(snap.ay) + 0.02 * n,
                  'AccelerometerZ': scene.GRAVITY + 0.02 * n}
        for board in ('InertialSensor', 'InertialSensorBase'):
            for name, value in values.items():
                if key == IMU_KEY % (board, name):
                    return value
        return None

    def joint_angles(self, t: float) -> List[float]:
        """ALMotion.getAngles("Body", true): the body's joints and wheels (body.py), as the
        emulator's joint_states have them."""
        snap = self.body.snapshot(t)
        return [float(snap.joints[j] if j in snap.joints else snap.wheels[j]) for j in JOINT_NAMES]

    def snapshot(self, t: float) -> Snapshot:
        return self.body.snapshot(t)
