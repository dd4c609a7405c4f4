"""Where messages come from: a live ROS graph (live.LiveSource) or a recorded bag
(bag.BagSource). The runner sees either through the `Source` protocol below; a source feeds
a sensor's window through the `Listener` protocol (sensors/window.py implements it)."""
from typing import Any, Callable, Dict, List, NamedTuple, Optional, Protocol, Set, Tuple

from .handling import Handling

# (advertised type or None, publisher node names or None when the topic is unknown to the source)
TopicInfo = Tuple[Optional[str], Optional[List[str]]]


class Graph(NamedTuple):
    """How a run speaks of the graph it listens on, where ROS 1 and ROS 2 differ: 'nothing is
    published' names it and what puts a driver out of its reach."""
    place: str          # 'on the ROS master' | 'in ROS 2 DDS domain 0'
    address: str        # ' at http://host:11311' | ' (rmw_cyclonedds_cpp)'
    other: str          # short: 'another master' | 'another ROS_DOMAIN_ID'
    other_cause: str    # long: 'ROS_MASTER_URI names another master' | ...


def ros1_graph(uri: str) -> Graph:
    return Graph('on the ROS master', ' at %s' % uri if uri else '', 'another master',
                 'ROS_MASTER_URI names another master')


class SourceLost(Exception):
    """The data source went away (e.g. the ROS master vanished); ends the run like Ctrl-C."""


class Listener(Protocol):
    """What a source needs from a sensor's listening window."""

    @property
    def topic(self) -> str:
        """The topic to deliver."""

    @property
    def listens(self) -> bool:
        """False for a window whose check drives itself (speech): nothing to subscribe to."""

    @property
    def queue_size(self) -> int:
        """Subscriber queue, in messages."""

    @property
    def buff_size(self) -> int:
        """Subscriber receive buffer, in bytes."""

    def feed_raw(self, type_name: str, buff: bytes, t_recv: float, ros_now: float,
                 conn: Optional[Dict[str, Any]] = None, own: Optional[Handling] = None) -> None:
        """One message as it came off the wire or out of a bag, with its connection header;
        `own`: how this process handled it, for every listener of a live source (ROS 1 and
        ROS 2 alike: sources/handling.begin), None from a bag."""

    def use_sim_clock(self, sim_clock: Callable[[], float]) -> None:
        """The source runs on simulation time: windows and rates on `sim_clock`."""

    def use_record_clock(self) -> None:
        """The source replays record times (a bag): rates are measured on them."""

    def observe_connections(self, n: int, now: float) -> None:
        """How many publishers are connected now."""


class Source(Protocol):
    """What the runner asks of a source of messages."""

    live: bool          # False for a bag: the runner then runs every sensor at once, at bag speed

    def attach(self, run: Listener) -> None:
        """Start delivering `run`'s topic to run.feed_raw (subscribe, or select the bag's topic)."""

    def detach(self, run: Listener) -> None:
        """Stop delivering `run`'s topic."""

    def poll(self, run: Listener, now: float) -> None:
        """Called every tick while `run` listens (connection counts, the master's health, bag
        playback); raises SourceLost when the source is gone."""

    def lookup(self, topic: str) -> Optional[TopicInfo]:
        """(advertised type or None, publisher node names other than this node) of a topic;
        None when unknown."""

    def published_topics(self) -> Optional[Set[str]]:
        """Topics that have a publisher other than this node now (it publishes /diagnostics
        itself); None when the source cannot tell."""

    def sleep(self, dt: float) -> None:
        """Wait `dt` seconds on the source's clock (a bag may not wait at all)."""

    @property
    def graph_words(self) -> Optional[Graph]:
        """The graph the source listens on, in words (None for a bag)."""
