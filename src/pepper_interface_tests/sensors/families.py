"""The family registry: one `Family` row per check family, the only table of families.

A family is a kind of sensor judged by one check (sonars are the `range` family, four cameras
the `camera` family). Everything that used to ask "is this the speech sensor?" or "is this a
camera?" asks the family's `Traits` instead, so a new family says once what it is and every
stage (the runner's lanes, the sources, the observers, the report) follows.

Derived from this table or checked against it by a test (test/sensors/test_families.py):
- plan/expectations.py `FAMILIES` (family -> its Expect class; the plan reads the YAML before
  any check exists, so it keeps its own map, and the test checks it names the same families);
- plan/declaration.py (each sensor row names its family; the test checks every name is a row here);
- the report's views (outputs/report/views/<Family.view>.py, found by name);
- the values each family's check hands over (`Family.values`, its dataclass in
  sensors/values/): the JSON is written from them and read back into them (codec.py), and the
  report's views render them;
- the emulator's publishers (emulator/publishers.py names its streams by these family names).

How to add a sensor to an existing family: docs/architecture.md, "Adding a sensor to a family"
(one row in plan/declaration.py). How to add a family (e.g. `bumper`: event messages,
published only on a press or a release):
1. its check module sensors/<family>.py: a `Check` subclass (sensors/base.py) whose docstring
   states each rule with the upstream driver line it follows (the one authoritative statement
   of the rule: docs/checks.md points to it);
2. its values: ONE frozen dataclass in its leaf sensors/values/<family>.py (importing only
   codec.py and sensors/values/__init__.py), every field with a default. A field made with
   codec.optional() is written only when set, codec.nullable() as null when None, codec.series()
   is plot data (the JSON's "series"); enums (with a `description`, as the laser's BeamKind),
   nested dataclasses, lists and dicts need nothing more. The check builds an instance at the
   end of its window (in `finish()`) into `self.found` (typed `Optional[<its dataclass>]`),
   which Check.result_values() hands over (as for every family). codec.py writes it to the
   JSON and reads it back (history, --rerun-failed); there is no serializer to write;
3. its row below, with its traits (an event-driven family sets `periodic=False`: the generic
   stream rules of sensors/stream.py then leave out arrival within --wait, min_messages, the
   rate band and the stopped-publisher and pause rules, and keep type, stamps and publishers)
   and `values=` its dataclass;
4. its `<Family>Expect` in plan/expectations.py (+ its `FAMILIES` entry) and its defaults in
   config/sensorExpectations.yaml;
5. its sensors' rows in plan/declaration.py, each with its drivers' streams (`make docs` then
   writes their lines in data/*Topics.dat, config/sensorTestInput.ini and the docs' tables);
6. its emulator publisher (emulator/publishers.py, or emulator/events.py for event topics)
   shaped after the driver, its place in emulator/profiles.py (PERIODIC, or an event family's
   own loop; its MODEL entry when the emulator adds to the declared stream), and its faults;
7. its report view outputs/report/views/<view>.py (`render(result, values, ctx)`: the values
   dataclass as the check handed it over), found by the row's `view` (nothing else lists it);
8. its rules' pointer in tools/gen_sensors.py FAMILY_RULES (docs/checks.md's family table is
   generated; a test checks it), its prose rows in docs/drivers.md, and its values' keys in
   docs/results.md; then `make docs`;
9. its tests in test/sensors/test_<family>.py (the test tree mirrors the package).
Nothing else (the runner, the sources, the outputs) names a family.
"""
import importlib
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Dict, Optional, Type

from .values.audio import AudioValues
from .values.camera import CameraValues
from .values.depth import DepthValues
from .values.health import HealthValues
from .values.imu import ImuValues
from .values.joints import JointsValues
from .values.laser import LaserValues
from .values.motion import MotionValues
from .values.odometry import OdometryValues
from .values.range import RangeValues
from .values.speech import SpeechValues
from .values.tf import TfValues
from .values.touch import TouchValues

if TYPE_CHECKING:
    from ..plan.catalog import Sensor
    from .base import Check


@dataclass(frozen=True)
class Traits:
    """What a family is, in the words the rest of the package asks about."""
    # messages arrive at a rate (sonars, cameras, ...); False: event-driven (only on a change),
    # so silence is not a failure and the rate rules do not apply
    periodic: bool = True
    # the check drives itself instead of listening to a topic (speech: it publishes a sentence)
    drives_itself: bool = False
    # needs a live robot: not checked from a bag
    live_only: bool = False
    # a heavy image stream: live view windows, Gazebo streams them one at a time
    images: bool = False
    # the microphones: its topic is where other checks can hear the robot
    audio: bool = False
    # listens through the microphones while it runs (speech: was the sentence heard?)
    hears: bool = False
    # asks a person to act (touch sensors): with a person there (an interactive terminal or
    # --guided) a live run offers the check an operator (sensors/guide.py) that prompts
    guided: bool = False
    # the topic is shared by many nodes (/diagnostics): several publishers are normal
    shared_topic: bool = False
    # asks whether the robot rests (the laser: its boards stop sampling at rest): the run offers
    # it the driver's joint stiffness from /diagnostics (sensors/stiffness.py)
    asks_rest: bool = False
    # its WARN or FAIL explains other sensors' failures (the robot's health): shown at the top
    # of the summary
    headline: bool = False
    # runs before every other window (the motion check: the others' windows must not watch the
    # robot move, and its findings go on their rows: RunContext.findings)
    leads: bool = False

    @property
    def records_media(self) -> bool:
        """The family writes a video or a WAV file."""
        return self.images or self.audio


@dataclass(frozen=True)
class Family:
    name: str            # as in plan/catalog.py's rows and plan/expectations.py's FAMILIES
    check: str           # 'module:Class' in sensors/ (imported when first used: OpenCV is slow to load)
    view: str            # the report's view module, outputs/report/views/<view>.py
    traits: Traits = Traits()
    # the frozen dataclass of what its check measured (sensors/values/<family>.py): the
    # sensor's SensorResult.values, written to the JSON and read back by codec.py's rules
    values: Optional[Type[Any]] = None

    def check_class(self) -> Type['Check']:
        module, name = self.check.split(':')
        return getattr(importlib.import_module('.' + module, __package__), name)


FAMILIES: Dict[str, Family] = {f.name: f for f in [
    Family('range', 'range:RangeCheck', 'range', values=RangeValues),
    Family('laser', 'laser:LaserCheck', 'laser', Traits(asks_rest=True), LaserValues),
    Family('camera', 'camera:CameraCheck', 'camera', Traits(images=True), CameraValues),
    Family('depth', 'depth:DepthCheck', 'depth', Traits(images=True), DepthValues),
    Family('audio', 'audio:AudioCheck', 'audio', Traits(audio=True), AudioValues),
    Family('joints', 'joints:JointsCheck', 'joints', values=JointsValues),
    Family('odometry', 'odometry:OdometryCheck', 'odometry', values=OdometryValues),
    Family('imu', 'imu:ImuCheck', 'imu', values=ImuValues),
    Family('speech', 'speech:SpeechCheck', 'speech',
           Traits(periodic=False, drives_itself=True, live_only=True, hears=True), SpeechValues),
    Family('touch', 'touch:TouchCheck', 'touch', Traits(periodic=False, guided=True), TouchValues),
    Family('health', 'health:HealthCheck', 'health',
           Traits(periodic=False, shared_topic=True, headline=True), HealthValues),
    Family('motion', 'motion:MotionCheck', 'motion',
           Traits(periodic=False, drives_itself=True, live_only=True, leads=True), MotionValues),
    # the robot's transform tree: /tf is shared (naoqi_driver, static publishers, others)
    Family('tf', 'tf:TfCheck', 'tf', Traits(shared_topic=True), TfValues),
]}


class UnknownFamily(KeyError):
    """A family name no row of FAMILIES has."""


def family(name: str) -> Family:
    """The row of family `name`, or UnknownFamily naming the known ones."""
    try:
        return FAMILIES[name]
    except KeyError:
        raise UnknownFamily('no check family "%s" (known: %s)' % (name, ', '.join(FAMILIES))) from None


def of(sensor: 'Sensor') -> Family:
    """The family of a catalog row."""
    return family(sensor.family)


def traits(sensor: 'Sensor') -> Traits:
    """The traits of a catalog row's family."""
    return family(sensor.family).traits


def values_of(name: str) -> Optional[Type[Any]]:
    """The values dataclass of family `name`; None for an unknown family or one without values."""
    row = FAMILIES.get(name)
    return row.values if row is not None else None
