"""The guided check's operator: asks a person for one zone at a time (sensors/touch.py).

Each prompt goes three ways: a line on the terminal, a latched std_msgs/String on
/sensorTest/prompt beginning with the zone's id in brackets ("[headTouch/front] Touch the front
of my head"; "[done]" when the guided part ends), so that a tablet page, a remote operator or a
test rig can follow, and the sentence on the robot's speech topic (naoqi_driver speaks what
arrives on /speech: src/naoqi_driver.cpp:939). The person skips the zone being asked by typing
s and Enter; the touch checks ask in turn (one sensor at a time, also in parallel mode).
A zone given up without its touch (its --touch-wait ended, or it is held down) is said on the
terminal and on /sensorTest/prompt before the next zone is asked, so that the person knows the
robot has moved on: "[headTouch/front] not pressed within 15 s, next zone" (", no zone left"
after the last one). Such a note ends in one of MOVED_ON: a follower that touches what it is
asked for reads the zone with asked_zone(), which is None for the notes and for "[done]".
"""
import shutil
import sys
import textwrap
import threading
from typing import Any, Iterable, List, Optional, TextIO

from .. import rosapi

PROMPT_TOPIC = '/sensorTest/prompt'
DONE = '[done]'
SKIP_HINT = '(type s and Enter to skip this zone)'
NEXT_ZONE, NO_ZONE_LEFT = 'next zone', 'no zone left'
MOVED_ON = (', ' + NEXT_ZONE, ', ' + NO_ZONE_LEFT)     # the end of a "moved on" note


def asked_zone(text: str) -> Optional[str]:
    """The zone id a /sensorTest/prompt message asks to touch ("[headTouch/front] Touch the front
    of my head" -> "headTouch/front"); None for "[done]", the "moved on" notes and anything else."""
    if not text.startswith('[') or ']' not in text or text == DONE or text.endswith(MOVED_ON):
        return None
    return text[1:text.index(']')] or None


def _isatty(stream: Any) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):
        return False


def guided_mode(option: Optional[bool], stdin: Any = None, stdout: Any = None,
                launched: bool = False) -> bool:
    """--guided / --no-guided, else: a person is there when stdin and stdout are a terminal and
    the node was not started by a launch file (`launched`: roslaunch hands its terminal on)."""
    if option is not None:
        return option
    if launched:
        return False
    stdin = sys.stdin if stdin is None else stdin
    stdout = sys.stdout if stdout is None else stdout
    return _isatty(stdin) and _isatty(stdout)


class Guide:
    """The Operator of a guided run (sensors/base.py Operator)."""

    def __init__(self, budget: float, speech_topic: Optional[str], out: Optional[TextIO] = None,
                 keys: Optional[TextIO] = None, prompt_topic: str = PROMPT_TOPIC,
                 owners: Iterable[str] = ()) -> None:
        self.budget = budget
        self.pending = set(owners)      # the sensors that may still ask (their zones not all asked)
        self.out = out or sys.stdout
        self.keys = keys if keys is not None else sys.stdin
        self.owner: Optional[str] = None
        self.lock = threading.Lock()
        self._skip = False
        self._asking = False
        self._zone = ''
        self.prompts = rosapi.publisher(prompt_topic, 'std_msgs/String', queue_size=10, latch=True)
        self.speech = rosapi.publisher(speech_topic, 'std_msgs/String', queue_size=10) if speech_topic else None
        self.reader = threading.Thread(target=self._read_keys, daemon=True, name='guide-keys')
        self.reader.start()

    def _read_keys(self) -> None:
        try:
            for line in iter(self.keys.readline, ''):
                self._heard(line.strip().lower())
        except (OSError, ValueError):   # stdin closed: no keyboard, prompts go on
            return

    def _heard(self, typed: str) -> None:
        """A line typed: the terminal echoed it onto the progress line; that row is cleared and
        the answer written in its place."""
        if _isatty(self.out) and _isatty(self.keys):
            self.out.write('\033[F\033[K')     # back to the row the echo spoilt, cleared
        if typed not in ('s', 'skip'):
            if typed:
                self._line('  >>> "%s" is not an answer %s' % (typed[:20], SKIP_HINT))
            return
        with self.lock:
            asking, zone = self._asking, self._zone
            self._skip = asking
        self._line('  >>> [%s] skipped by the operator' % zone if asking
                   else '  >>> nothing to skip: no zone is being asked')

    def _line(self, text: str) -> None:
        tty = _isatty(self.out)
        width = max(40, shutil.get_terminal_size((80, 24)).columns)
        lines = textwrap.wrap(text, width, subsequent_indent=' ' * 6, break_on_hyphens=False) or [text]
        self.out.write(('\r\033[K' if tty else '') + '\n'.join(lines) + '\n')
        self.out.flush()

    def turn(self, owner: str) -> bool:
        if self.owner in (None, owner):
            self.owner = owner
            return True
        return False

    def publishing(self, topic: str, timeout: float = 1.0) -> Optional[bool]:
        """Asked in a thread of its own for at most `timeout` s: a stalled master must not hold
        the run's loop (it is the master watch's business, sources/live.py); None: unknown."""
        answer: List[Optional[bool]] = []

        def ask() -> None:
            published = rosapi.published_topics()     # None: the master went away
            answer.append(None if published is None else any(t == topic for t, _ in published))
        t = threading.Thread(target=ask, daemon=True, name='guide-lookup')
        t.start()
        t.join(timeout)
        return answer[0] if answer else None

    def ask(self, zone_id: str, text: str) -> None:
        with self.lock:
            self._skip, self._asking, self._zone = False, True, zone_id
        self._line('  >>> [%s] %s %s' % (zone_id, text, SKIP_HINT))
        self.prompts.publish(rosapi.msg('std_msgs/String')(data='[%s] %s' % (zone_id, text)))
        if self.speech is not None:
            self.speech.publish(rosapi.msg('std_msgs/String')(data=text))

    def moved_on(self, zone_id: str, why: str, more: bool) -> None:
        """The zone being asked is given up without its touch: said before the next is asked."""
        owner = zone_id.split('/')[0]
        with self.lock:
            self._asking, self._zone = False, ''
            others = any(o != owner for o in self.pending)
        note = '[%s] %s, %s' % (zone_id, why, NEXT_ZONE if more or others else NO_ZONE_LEFT)
        self._line('  >>> ' + note)
        self.prompts.publish(rosapi.msg('std_msgs/String')(data=note))

    def skipped(self) -> bool:
        with self.lock:
            if self._skip:
                self._skip, self._asking = False, False
                return True
            return False

    def finished(self, owner: str) -> None:
        with self.lock:
            self._asking, self._zone = False, ''
            self.pending.discard(owner)
        if self.owner == owner:
            self.owner = None

    def ended(self, owner: str) -> None:
        """Sensor `owner`'s window has ended (asked or not): it will ask nothing more."""
        with self.lock:
            self.pending.discard(owner)

    def done(self) -> None:
        """The guided part has ended."""
        self.prompts.publish(rosapi.msg('std_msgs/String')(data=DONE))
        self._line('  >>> %s guided check finished' % DONE)

    def close(self) -> None:
        for pub in (self.prompts, self.speech):
            if pub is not None:
                pub.unregister()


def budget(zone_counts: Iterable[int], touch_wait: float, max_press: float) -> float:
    """Seconds the guided part may take: every zone of every touch sensor waited for in full,
    then held up to the stuck limit, plus a few seconds to start."""
    return sum(zone_counts) * (touch_wait + max_press) + 5.0
