"""A running sensor window as observers see it: a frozen snapshot taken by the runner every
tick (sensors/window.py SensorRun.progress), never the window itself or its lock."""
from dataclasses import dataclass
from typing import Callable, Iterator, List, Optional, Sequence, Tuple, overload


@dataclass(frozen=True)
class Progress:
    """A running window as it stands at one tick: what the terminal and /diagnostics show."""
    name: str
    family: str
    topic: Optional[str]
    msg_type: str
    drives_itself: bool          # the check acts instead of listening (speech: `count` = sent)
    window: float                # seconds the window lasts
    wait: float                  # seconds allowed for the first message
    elapsed: float               # seconds since the window opened (wall clock)
    count: int                   # messages received (sent, for a check that drives itself)
    received: int                # messages received on the topic
    rate: Optional[float]        # Hz so far (None for a check that drives itself)
    stamp_rate: Optional[float]
    rate_band: Optional[Tuple[float, float]]   # the expected band, when the family has one
    nominal: Optional[float]
    problems: Tuple[str, ...]    # provisional problems: bad headers, the check's failures so far
    wrong_type: bool             # a message of another type arrived
    periodic: bool = True        # False: an event topic (touch), where silence is normal
    asking: bool = False         # the check waits for a person's answer on the terminal (--move's
    #                              Enter): nothing else is printed meanwhile (outputs/terminal.py)

    @property
    def left(self) -> float:
        """Seconds the window still runs."""
        return max(0.0, self.window - self.elapsed)


class Snapshots(Sequence[Progress]):
    """The running windows' snapshots at one tick, taken on first use: observers read them
    only when they show something (the terminal every 0.5 s or 5 s, /diagnostics every
    second), and a recording's run ticks every 50 ms of record time, 1,200 ticks a minute of
    a dozen windows each (a snapshot formats the window's provisional problems).
    `len()` and truth need no snapshot."""

    def __init__(self, take: Sequence[Callable[[float], Progress]], now: float) -> None:
        self._take, self._now = list(take), now
        self._items: Optional[List[Progress]] = None

    def _all(self) -> List[Progress]:
        if self._items is None:
            self._items = [take(self._now) for take in self._take]
        return self._items

    def __len__(self) -> int:
        return len(self._take)

    @overload
    def __getitem__(self, i: int) -> Progress: ...

    @overload
    def __getitem__(self, i: slice) -> Sequence[Progress]: ...

    def __getitem__(self, i):  # type: ignore[no-untyped-def]
        return self._all()[i]

    def __iter__(self) -> Iterator[Progress]:
        return iter(self._all())
