"""Is the robot resting? The joints' stiffness naoqi_driver publishes on /diagnostics, as a
witness a check may ask (ctx.services.stiffness).

Why (line numbers: yohatad/naoqi_driver2 at 9506ea2, ros-naoqi/naoqi_driver at aed1b87):
Pepper's laser boards stop sampling while the robot rests (yohatad/naoqi_driver2
src/converters/laser.hpp:72-75, "The boards stop sampling entirely whenever the robot is at
rest, and a stalled board keeps returning its last values forever"), and stock naoqi_driver
goes on reading the last values from ALMemory and stamping them with the current time
(ros-naoqi/naoqi_driver src/converters/laser.cpp:148 getListData, :154 `ros::Time::now()`). A
frozen scan is then a resting robot far more often than three broken boards; the joints'
stiffness tells which.

What the driver publishes (ros-naoqi/naoqi_driver src/converters/diagnostics.cpp): one status
per joint named `naoqi_driver_joints:<joint>` (:162) carrying "Stiffness" (:170), read from
ALMemory's `Device/SubDeviceList/<joint>/Hardness/Actuator/Value` (:80, :165): 0 when the motor
is off, up to 1. A robot at rest has every motor off ("Rest mode: all motors are turned off",
SoftBank's Pepper NAOqi 2.9 "Daily use" guide), so it is resting exactly when every joint's
latest stiffness is 0; any joint above 0 is a motor on, an awake robot.

The witness is a `sources.Listener`: the runner attaches it to the run's source next to the
sensors' windows (live: a subscriber; a bag: the recorded /diagnostics), so it works alike live
and from recordings. It listens to the robotHealth topic of the run's topics file
(`RobotHealth /diagnostics` in data/pepperTopics.dat); a run whose topics file has none (the
simulator, naoqi_driver2) has no witness, and a check then says the robot's state is unknown.
This node's own statuses on /diagnostics never reach it (sources/live.py drops them), and other
nodes' statuses are not the driver's joints, so they are left out by name.
"""
import threading
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Tuple

from ..sources.witness import TopicWitness
from .families import traits

if TYPE_CHECKING:
    from ..plan.model import TestPlan
    from .base import RunContext

JOINT_PREFIX = 'naoqi_driver_joints:'       # diagnostics.cpp:162
JOINTS_STATUS = 'naoqi_driver_joints:Status'    # the aggregate (:210): not a joint
DIAGNOSTICS_TYPE = 'diagnostic_msgs/DiagnosticArray'
HEALTH_SENSOR = 'robotHealth'               # the catalog's name of the driver's /diagnostics


class StiffnessWitness(TopicWitness):
    """The latest stiffness of each joint the driver reported on `topic` (thread-safe)."""

    def __init__(self, topic: str) -> None:
        super().__init__(topic, DIAGNOSTICS_TYPE)
        self._lock = threading.Lock()
        self._stiffness: Dict[str, float] = {}
        self.arrays = 0                 # arrays that carried at least one joint's stiffness

    def take(self, msg: Any, t_recv: float) -> None:
        self.add(msg)

    # --- what a check asks (sensors.base.RestWitness) -----------------------------------------
    def add(self, msg: Any) -> None:
        """One DiagnosticArray: keep each driver joint's "Stiffness"."""
        found: List[Tuple[str, float]] = []
        for status in msg.status:
            name = status.name
            if not name.startswith(JOINT_PREFIX) or name == JOINTS_STATUS:
                continue
            for kv in status.values:
                if kv.key == 'Stiffness':
                    try:
                        found.append((name[len(JOINT_PREFIX):], float(kv.value)))
                    except ValueError:
                        pass
        if found:
            with self._lock:
                self._stiffness.update(found)
                self.arrays += 1

    def stiffness(self) -> Optional[Tuple[int, float]]:
        """(joints reported, highest latest stiffness), or None before the driver gave any."""
        with self._lock:
            if not self._stiffness:
                return None
            return len(self._stiffness), max(self._stiffness.values())


def witness_topic(plan: 'TestPlan') -> Optional[str]:
    """The driver's /diagnostics topic of this run: robotHealth's topic in the plan, else in the
    run's topics file; None when neither names one."""
    for s in plan.sensors:
        if s.name == HEALTH_SENSOR and s.topic:
            return s.topic
    path = plan.files.get('topics')
    if not path:
        return None
    from ..plan.settings import read_topics
    try:
        return read_topics(path).get(HEALTH_SENSOR)
    except Exception:   # the plan read the file already; a broken one means no witness here
        return None


def witnesses(plan: 'TestPlan', ctx: 'RunContext') -> List[StiffnessWitness]:
    """The witnesses this run's checks ask for, offered on ctx.services (the runner attaches
    them to the source): a stiffness witness when a check asks whether the robot rests
    (Traits.asks_rest) and the run has the driver's /diagnostics topic."""
    if not any(traits(s.sensor).asks_rest for s in plan.active):
        return []
    topic = witness_topic(plan)
    if topic is None:
        return []
    witness = StiffnessWitness(topic)
    ctx.services.stiffness = witness
    return [witness]
