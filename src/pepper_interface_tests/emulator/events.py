"""naoqi_driver's touch events and diagnostics, as the driver publishes them, and an emulated
operator who touches the robot when sensorTest's guided check asks (/sensorTest/prompt).

Touch (ros-naoqi/naoqi_driver src/event/touch.cpp:172-243, src/naoqi_driver.cpp:838-894): one
naoqi_bridge_msgs message per change, pressed (1) or released (0), only while someone subscribes
(touch.cpp:186), nothing while nobody touches; the index is the event's position in the driver's
list (sensors/touch.py DRIVER_ZONES). Faults: dead_zone=ZONE (the zone sends nothing),
jammed=ZONE (the zone is pressed 1 s after the first subscriber and never released: a bumper
caught on something; touching it again changes nothing).

Diagnostics (src/converters/diagnostics.cpp:134-313, 1 Hz: share/boot_config.json "diag"): one
status per joint (naoqi_driver_joints:<joint>: Temperature, Stiffness and the joint's limits;
OK, WARN "Hot" from 68 °C, ERROR "Too hot" from 74 °C), the aggregate naoqi_driver_joints:Status,
naoqi_driver_battery:Status (Percentage, Charging, Fully Charged; OK charging or above 60 %,
WARN discharging above 30 %, ERROR almost empty), naoqi_driver_battery:Current and
naoqi_driver_computer:CPU (Temperature -1). Faults: hot_joint=C (HipPitch at C °C),
empty_battery (12 %, not charging). Stiffness 1 on every joint (an awake robot), 0 under the
~condition resting (every motor off).
"""
import threading
import time
from typing import TYPE_CHECKING, Any, Dict, List, Tuple, Type

from .. import rosapi
from ..sensors import guide, joint_limits, touch
from ..sources import naoqi_msgs
from .fake_memory import joint_temperature
from .profiles import JOINT_NAMES
from .publishers import StreamPublisher

if TYPE_CHECKING:
    import genpy

DiagnosticArray = rosapi.msg('diagnostic_msgs/DiagnosticArray')
DiagnosticStatus = rosapi.msg('diagnostic_msgs/DiagnosticStatus')
KeyValue = rosapi.msg('diagnostic_msgs/KeyValue')
String = rosapi.msg('std_msgs/String')

PROMPT_TOPIC = '/sensorTest/prompt'
PRESS_S = 0.4           # how long the emulated operator presses
REACTION_S = 0.8        # from the prompt to the press (reading, reaching)
JAM_AFTER_S = 1.0       # a jammed zone is pressed this long after the first subscriber
HOT_JOINT = 'HipPitch'  # the joint heated by hot_joint=C
HEALTHY_BATTERY, EMPTY_BATTERY = 85, 12
# getBodyNames("JointActuators") on Pepper (diagnostics.cpp:76), in the URDF's order
# diagnostics.cpp:76 lists the joints as ALMotion.getBodyNames("JointActuators") answers: the
# order of the joint_states names (profiles.JOINT_NAMES), as the real driver showed against the
# fake NAOqi (test/fixtures/real-driver/)
JOINTS = JOINT_NAMES


class TouchPublisher(StreamPublisher):
    """One touch topic; `touch(zone_id)` presses a zone for PRESS_S s (the operator)."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.field, self.zones = touch.zones_of(self.spec.msg_type)
        self.ids = [z.id for z in self.zones]
        self.pressed = [False] * len(self.zones)
        self.pending: List[Tuple[float, int, int]] = []    # (monotonic due, index, state)
        self.lock = threading.Lock()

    def msg_class(self) -> type:
        return naoqi_msgs.known_class(self.spec.msg_type)

    def touch(self, zone_id: str) -> None:
        if zone_id not in self.ids:
            return
        i = self.ids.index(zone_id)
        if zone_id in self.faults.dead_zone or zone_id in self.faults.jammed:
            return       # dead: nothing; jammed: already pressed, no change to send
        now = time.monotonic()
        with self.lock:
            self.pending += [(now, i, 1), (now + PRESS_S, i, 0)]

    def tick(self) -> None:
        if self.faults.wrong_type:
            super().tick()
            return
        t = self.clock.now()
        if self.faults.silent or not self.wanted():
            return      # the driver publishes only while someone subscribes (touch.cpp:186)
        if self.first_wanted is None:
            self.first_wanted = t
            now = time.monotonic()
            with self.lock:
                self.pending += [(now + JAM_AFTER_S, self.ids.index(z), 1) for z in self.faults.jammed]
        now = time.monotonic()
        with self.lock:
            due = sorted(e for e in self.pending if e[0] <= now)
            self.pending = [e for e in self.pending if e[0] > now]
        cls = self.msg_class()
        for _, i, state in due:
            if self.pressed[i] == bool(state):
                continue            # one message per change
            self.pressed[i] = bool(state)
            msg = cls()
            setattr(msg, self.field, i)
            msg.state = state
            for pub, _ in self.outputs:
                pub.publish(msg)
            self.published += 1


def _status(name: str, hardware_id: str, level: int, message: str,
            values: List[Tuple[str, str]]) -> Any:
    return DiagnosticStatus(level=level, name=name, message=message, hardware_id=hardware_id,
                            values=[KeyValue(key=k, value=v) for k, v in values])


def _num(v: float) -> str:
    return '%g' % v     # std::stringstream << double (DiagnosticStatusWrapper::add)


class HealthPublisher(StreamPublisher):
    """naoqi_driver's DiagnosticArray on /diagnostics."""

    def msg_class(self) -> type:
        return DiagnosticArray

    def temperatures(self, t: float) -> Dict[str, float]:
        temps = {j: joint_temperature(i, t) for i, j in enumerate(JOINTS)}
        if self.faults.hot_joint is not None:
            temps[HOT_JOINT] = self.faults.hot_joint
        return temps

    def build(self, t: float, frame_id: str, index: int) -> 'genpy.Message':
        pct = EMPTY_BATTERY if self.faults.empty_battery else HEALTHY_BATTERY
        # Device/SubDeviceList/<joint>/Hardness/Actuator/Value (diagnostics.cpp:79-80, 165-170):
        # 1 awake, 0 resting (the body: robot:resting or ~condition resting)
        stiffness = self.snapshot(t).stiffness
        return driver_array(self.temperatures(t), pct, charging=False, stiffness=stiffness)


def driver_array(temperatures: Dict[str, float], percent: int, charging: bool,
                 fully_charged: bool = False, stiffness: float = 1.0) -> Any:
    """The DiagnosticArray naoqi_driver builds (diagnostics.cpp:134-313) from joint temperatures
    (°C), every joint's stiffness (0 motor off .. 1) and the battery's charge (%) and flags."""
    msg = DiagnosticArray()
    worst, hottest, hot = 0, 0.0, ''
    for joint, temp in temperatures.items():
        level, words = (0, 'OK') if temp < 68 else (1, 'Hot') if temp < 74 else (2, 'Too hot')
        lo, hi, vel, _ = joint_limits.LIMITS.get(joint, (0.0, 0.0, 0.0, 0))
        msg.status.append(_status('naoqi_driver_joints:' + joint, joint, level, words, [
            ('Temperature', _num(temp)), ('Stiffness', _num(stiffness)), ('minAngle', _num(lo or 0.0)),
            ('maxAngle', _num(hi or 0.0)), ('maxVelocity', _num(vel)), ('maxTorque', '0')]))
        worst, hottest = max(worst, level), max(hottest, temp)
        if level >= 1:
            hot += '\n%s: %s°C' % (joint, _num(temp))
    msg.status.append(_status('naoqi_driver_joints:Status', 'joints', worst, ('OK', 'WARN', 'ERROR')[worst], [
        ('Highest Temperature', _num(hottest)), ('Highest Stiffness', _num(stiffness)),
        ('Lowest Stiffness', _num(stiffness)), ('Lowest Stiffness without Hands', _num(stiffness)),
        ('Hot Joints', hot)]))
    if charging:
        level, text = 0, 'Charging (%4d%%)' % percent
    elif percent > 60:
        level, text = 0, 'Battery OK (%4d%% left)' % percent
    elif percent > 30:
        level, text = 1, 'Battery discharging (%4d%% left)' % percent
    else:
        level, text = 2, 'Battery almost empty (%4d%% left)' % percent
    if fully_charged:
        level = 0       # :264-268; the message stays the charge's (:270-271)
    msg.status.append(_status('naoqi_driver_battery:Status', 'battery', level, text, [
        ('Percentage', str(percent)), ('Charging', str(charging)), ('Fully Charged', str(fully_charged))]))
    current = 1.5 if charging else -1.2
    msg.status.append(_status('naoqi_driver_battery:Current', 'battery', level,
                              'Total Current: %5g Ampere (%s)' % (current, 'charging' if charging else 'discharging'),
                              [('Current', _num(current))]))
    msg.status.append(_status('naoqi_driver_computer:CPU', '', 0, '', [('Temperature', '-1')]))
    return msg


EVENT_PUBLISHERS: Dict[str, Type[StreamPublisher]] = {'touch': TouchPublisher, 'health': HealthPublisher}


class EmulatedOperator:
    """Follows /sensorTest/prompt: "[sensor/zone] Touch ..." -> that zone is touched REACTION_S s
    later; the guide's notes ("[sensor/zone] not pressed within 15 s, next zone") ask nothing."""

    def __init__(self, publishers: List[StreamPublisher]) -> None:
        self.touch = {p.spec.name: p for p in publishers if isinstance(p, TouchPublisher)}
        self.timers: List[threading.Timer] = []
        self.sub = rosapi.subscriber(PROMPT_TOPIC, 'std_msgs/String', self._on_prompt, queue_size=10)

    def _on_prompt(self, msg: Any) -> None:
        zone_id = guide.asked_zone(msg.data)    # None for "[done]" and the guide's "moved on" notes
        if zone_id is None:
            return
        sensor, _, zone = zone_id.partition('/')
        pub = self.touch.get(sensor)
        if pub is None:
            return
        rosapi.loginfo('pepperEmulator: operator touches %s', zone_id)
        timer = threading.Timer(REACTION_S, pub.touch, args=(zone,))
        timer.daemon = True
        timer.start()
        self.timers.append(timer)

    def close(self) -> None:
        self.sub.unregister()
        for t in self.timers:
            t.cancel()

