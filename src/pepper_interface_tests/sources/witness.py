"""A listener that watches one topic for another part of a run, not for a sensor's own window:
the laser's stiffness witness on the driver's /diagnostics (sensors/stiffness.py), the motion
rules' witnesses of a recorded turn (motion/recorded.py). It decodes each message of its type
and hands it to take(); it has no window, no clock of its own and counts no publishers."""
from typing import Any, Callable, Dict, Optional

from . import messages
from .handling import Handling


class TopicWitness:
    """A sources.Listener of `topic` for messages of `type_name`; a subclass implements take()."""

    queue_size = 10         # subscriber queue (messages)
    buff_size = 1 << 16     # subscriber receive buffer (bytes); images need more

    def __init__(self, topic: str, type_name: str) -> None:
        self._topic = topic
        self.type_name = type_name

    @property
    def topic(self) -> str:
        return self._topic

    @property
    def listens(self) -> bool:
        return True

    def feed_raw(self, type_name: str, buff: bytes, t_recv: float, ros_now: float,
                 conn: Optional[Dict[str, Any]] = None, own: Optional[Handling] = None) -> None:
        if type_name != self.type_name:
            return      # another type on the topic: that sensor's own row says so
        try:
            msg = messages.message_class(type_name)().deserialize(bytes(buff))   # a Ros2Image too
        except Exception:   # a broken message: that sensor's own row says so
            return
        self.take_full(msg, t_recv, ros_now, conn)

    def take_full(self, msg: Any, t_recv: float, ros_now: float, conn: Optional[Dict[str, Any]]) -> None:
        """A decoded message with its clock and connection; most witnesses need take()'s two."""
        self.take(msg, t_recv)

    def take(self, msg: Any, t_recv: float) -> None:
        raise NotImplementedError

    def use_sim_clock(self, sim_clock: Callable[[], float]) -> None:
        pass

    def use_record_clock(self) -> None:
        pass

    def observe_connections(self, n: int, now: float) -> None:
        pass
