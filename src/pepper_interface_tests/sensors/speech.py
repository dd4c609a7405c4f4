"""Speech (loudspeaker): publish the test sentence once to the speech topic, delivered to a
subscriber (naoqi_driver speaks what arrives on /speech).

Pass condition: a subscriber was connected (waited for at most `subscriber_wait` s) and the
sentence was handed to it; nobody listening fails. When the
microphones are in the same run, a level monitor is offered in ctx.services.microphone_levels
(sensors/audio.py); the check then compares the level while speaking
with the level before and reports whether the sentence was heard (required with require_heard).

On a busy PC or a bursty WiFi the microphones' buffers can come late (issue 41): the monitor
places them at their stamps where they have them (sensors/audio.py LevelMonitor), and the check
listens on after `listen_after` until the stream has reached its end, for at most CATCH_UP s
more. A sentence not heard while the microphones' stream said nothing for PAUSE s or more of
the listening window is not judged (NOT JUDGED with require_heard, else a warning), naming the
pause and the PC's load: whether the loudspeaker spoke cannot be told from a silent stream,
and the microphone row says whether that stream is at fault.
"""
import time
from dataclasses import replace
from typing import TYPE_CHECKING, Any, List, Optional, Tuple

from .. import rosapi
from .base import Check
from .lag import load_now
from .values.speech import SpeechValues

if TYPE_CHECKING:
    import genpy

    from ..plan.expectations import SpeechExpect
    from ..plan.settings import SensorPlan
    from .base import RunContext


# s the check waits beyond listen_after for the microphones' stream to reach the listening
# window's end: sensorTest's own backlog beside six busy loops on 2 cores reached 5.6 s (issue 41)
CATCH_UP = 6.0
# s of silence from the microphones within the listening window that could hide a sentence:
# the default sentence lasts about 2 s, and a pause of half of it leaves too little to hear
PAUSE = 1.0


class SpeechCheck(Check):
    family = 'speech'
    expect: 'SpeechExpect'

    def __init__(self, plan: 'SensorPlan', ctx: 'RunContext') -> None:
        super().__init__(plan, ctx)
        self.text = self.expect.text
        self.subscriber_wait = self.expect.subscriber_wait
        self.listen_after = self.expect.listen_after
        self.pub = None
        self.sent_at: Optional[float] = None
        self.sent_elapsed: Optional[float] = None
        self.started: Optional[float] = None
        self._done = False
        self.subscribers: List[str] = []
        self.found: Optional[SpeechValues] = None    # once the sentence was delivered

    def window(self, duration: float) -> float:
        """Long enough to wait for a subscriber, speak, listen and catch up (CATCH_UP); the check
        ends itself sooner."""
        return max(duration, self.subscriber_wait + self.listen_after + CATCH_UP)

    def fields(self, msg: 'genpy.Message') -> List[Tuple[str, Any]]:
        return [('Text', msg.data)]

    def start(self) -> None:
        self.started = time.monotonic()
        self.pub = rosapi.publisher(self.plan.topic or '/speech', 'std_msgs/String', queue_size=1, latch=False)

    def _monitor(self):
        return self.ctx.services.microphone_levels

    def poll(self, elapsed: float) -> None:
        if self._done or self.pub is None:
            return
        if self.sent_at is None:
            if self.pub.get_num_connections() > 0:
                monitor = self._monitor()
                if monitor is not None and not monitor.has_baseline():
                    if elapsed < self.subscriber_wait:
                        return   # let the microphones collect a baseline first
                msg = rosapi.msg('std_msgs/String')(data=self.text)
                self.pub.publish(msg)
                self.sent_at, self.sent_elapsed = time.monotonic(), elapsed
                self.feed(msg, elapsed)
                self.subscribers = rosapi.subscriber_nodes(self.plan.topic)
            elif elapsed >= self.subscriber_wait:
                self._done = True
            return
        monitor = self._monitor()
        since = time.monotonic() - self.sent_at
        if monitor is None:
            self._done = since >= 0.3          # let the message leave before unregistering
        elif since >= self.listen_after + CATCH_UP or (
                since >= self.listen_after and monitor.covered(self.sent_at + self.listen_after)):
            self._done = True       # the microphones' stream reached the window's end (CATCH_UP)
        elif self.ctx.options.quick and since >= 0.3 and \
                monitor.heard(self.sent_at, time.monotonic()).get('heard'):
            self._done = True                  # --quick: heard is settled, no need to listen on

    def done(self) -> bool:
        return self._done

    def finish(self) -> None:
        if self.pub is not None:
            if self.sent_at is not None and self.sent_elapsed is not None:
                time.sleep(max(0.0, 0.2 - (time.monotonic() - self.sent_at)))
            self.pub.unregister()
        if self.sent_at is None:
            self.fail('no subscriber on %s after %.1f s: is naoqi_driver running?'
                      % (self.plan.topic, self.subscriber_wait))
            return
        self.found = SpeechValues(self.text, list(self.subscribers))
        self.notes.append('Sentence "%s" delivered to %s' % (
            self.text, ', '.join(self.subscribers) or 'a subscriber'))
        monitor = self._monitor()
        if monitor is None:
            return
        heard = monitor.heard(self.sent_at, self.sent_at + self.listen_after)
        self.found = replace(self.found, heard=heard.get('heard'), level_rise_db=heard.get('rise_db'))
        if heard.get('heard'):
            self.notes.append('Heard by the microphones: level rose %.1f dB over the baseline'
                              % heard['rise_db'])
            return
        t0, t1 = self.sent_at, self.sent_at + self.listen_after
        pause = monitor.longest_pause(t0, t1)
        if pause >= PAUSE:
            text = ('not judged whether the sentence was heard: the microphones\' stream said nothing for '
                    '%.1f s of the %.1f s listened (%s; %s): a busy PC or '
                    'network held it, or the microphones stopped (see their row)'
                    % (pause, self.listen_after, heard.get('why', 'no level rise'), load_now()))
            if self.ctx.options.require_heard:
                self.not_judged('PC busy or microphones silent: ' + text)
            else:
                self.warnings.add('unheard', text)
            return
        text = 'sentence not heard by the microphones (%s)' % heard.get('why', 'no level rise')
        if self.ctx.options.require_heard:
            self.fail(text)
        else:
            self.warnings.add('unheard', text)
