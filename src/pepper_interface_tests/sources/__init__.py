"""Where messages come from: a live ROS graph (live.LiveSource) or a recorded bag
(bag.BagSource). The runner sees either through the `Source` protocol below."""
from typing import TYPE_CHECKING, List, Optional, Protocol, Set, Tuple

if TYPE_CHECKING:   # the runner's per-sensor object; only named here for the type checker
    from ..runner import SensorRun


# (advertised type or None, publisher node names or None when the topic is unknown to the source)
TopicInfo = Tuple[Optional[str], Optional[List[str]]]


class SourceLost(Exception):
    """The data source went away (e.g. the ROS master vanished); ends the run like Ctrl-C."""


class Source(Protocol):
    """What the runner asks of a source of messages."""

    live: bool          # False for a bag: the runner then runs every sensor at once, at bag speed

    def attach(self, run: 'SensorRun') -> None:
        """Start delivering `run`'s topic to run.feed_raw (subscribe, or select the bag's topic)."""

    def detach(self, run: 'SensorRun') -> None:
        """Stop delivering `run`'s topic."""

    def poll(self, run: 'SensorRun', now: float) -> None:
        """Called every tick while `run` listens (connection counts, the master's health, bag
        playback); raises SourceLost when the source is gone."""

    def lookup(self, topic: str) -> Optional[TopicInfo]:
        """(advertised type or None, publisher node names) of a topic; None when unknown."""

    def published_topics(self) -> Optional[Set[str]]:
        """Topics that have a publisher now; None when the source cannot tell."""

    def sleep(self, dt: float) -> None:
        """Wait `dt` seconds on the source's clock (a bag may not wait at all)."""

    @property
    def master_uri(self) -> Optional[str]:
        """The ROS master the source listens on (None for a bag)."""
