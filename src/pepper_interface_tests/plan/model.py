"""The typed plan of a run: what settings.load_plan builds from the files and options, and
every later stage reads (value types only: this module imports nothing of the plan's readers)."""
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import List, Optional, Tuple, cast

from . import catalog, expectations
from .expectations import SpeechExpect
from .options import Options


@dataclass(frozen=True)
class SensorPlan:
    """One sensor of the run: what to listen to and what to expect."""
    sensor: catalog.Sensor
    topic: Optional[str]
    expect: expectations.Expect
    skip_reason: Optional[str] = None

    @property
    def name(self) -> str:
        return self.sensor.name


@dataclass(frozen=True)
class TestPlan:
    platform: str
    mode: str
    duration: float
    wait: float
    quick: bool
    cameras: Optional[str]      # --cameras, None: the input file decides
    output_dir: str
    sensors: Tuple[SensorPlan, ...]
    files: MappingProxyType = field(default_factory=lambda: MappingProxyType({}))
    options: Options = Options()
    selection_notes: Tuple[str, ...] = ()   # what is left out and why (selection.py)
    # every sensor's topic from the topics file (selected or not): the motion check's witnesses
    topics: MappingProxyType = field(default_factory=lambda: MappingProxyType({}))

    @property
    def active(self) -> Tuple[SensorPlan, ...]:
        return tuple(s for s in self.sensors if s.skip_reason is None)

    @property
    def notes(self) -> Tuple[str, ...]:
        """Lines for the run header: what is tested, what is left out and why, and every
        sensor whose window is not `duration` (computed now: cli.run_bag changes duration)."""
        return tuple(self.selection_notes) + tuple(window_notes(self))


def window_notes(plan: TestPlan) -> List[str]:
    """How long each sensor listens, where that is not `duration`: the microphone in
    --mic-mode sequential (4 x duration: each microphone in turn, as the spec says), and speech
    (not a listening window: one sentence, then the microphones listen for it)."""
    notes: List[str] = []
    names = {p.name: p for p in plan.active}
    mode = plan.options.mic_mode or 'together'
    if 'microphone' in names and mode == 'sequential':
        notes.append('microphone listens %g s: --mic-mode sequential, each of the 4 microphones '
                     'for %g s' % (round(4 * plan.duration, 1), round(plan.duration, 1)))
    speech = names.get('speech')
    if speech is not None and not plan.options.bag:
        e = cast(SpeechExpect, speech.expect)
        wait, after = e.subscriber_wait, e.listen_after
        if 'microphone' in names:
            notes.append('speech: one sentence (up to %g s waiting for a subscriber), then the '
                         'microphones listen %g s for it' % (wait, after))
        else:
            notes.append('speech: one sentence (up to %g s waiting for a subscriber); whether it '
                         'is heard is not checked: no microphone in the run' % wait)
    return notes
