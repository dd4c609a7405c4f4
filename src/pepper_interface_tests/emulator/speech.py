"""The emulated loudspeaker: /speech text -> ALTextToSpeech.say on the NAOqi endpoint (libqi),
or straight into the emulator's own AudioSource when it publishes the microphones itself."""
import queue
import threading
from typing import TYPE_CHECKING, Any

from .. import rosapi

if TYPE_CHECKING:
    from .audio_source import AudioSource


class NaoqiSpeech:
    """Calls ALTextToSpeech.say(text) on a NAOqi endpoint from a worker thread.

    The connection is made on the first sentence and retried on later ones; when the endpoint
    cannot be reached one warning is logged and sentences are dropped until it can.
    """

    def __init__(self, url: str) -> None:
        self.url = url
        self.session: Any = None     # qi.Session once connected (libqi ships no type information)
        self.warned = False
        self.spoken = 0
        self.queue: queue.Queue = queue.Queue()
        self.thread = threading.Thread(target=self._run, name='naoqi-speech', daemon=True)
        self.thread.start()

    def say(self, text: str) -> None:
        self.queue.put(text)

    def close(self) -> None:
        self.queue.put(None)

    def _tts(self) -> Any:
        if self.session is None:
            try:
                import qi
                session = qi.Session()
                session.connect(self.url)
                self.session = session
                rosapi.loginfo('pepperEmulator: speech goes to ALTextToSpeech at %s', self.url)
            except Exception as e:          # qi raises RuntimeError; an import may fail too
                if not self.warned:
                    self.warned = True
                    rosapi.logwarn('pepperEmulator: NAOqi endpoint %s not reachable (%s); '
                                  '/speech is ignored until it is', self.url, e)
                return None
        return self.session.service('ALTextToSpeech')

    def _run(self) -> None:
        while True:
            text = self.queue.get()
            if text is None:
                return
            try:
                tts = self._tts()
                if tts is not None:
                    tts.say(text)
                    self.spoken += 1
            except Exception as e:
                self.session = None
                if not self.warned:
                    self.warned = True
                    rosapi.logwarn('pepperEmulator: ALTextToSpeech.say failed at %s: %s', self.url, e)


class DirectSpeech:
    """Mixes the text into the emulator's own microphone stream (AudioSource.say)."""

    def __init__(self, source: 'AudioSource') -> None:
        self.source = source
        self.spoken = 0

    def say(self, text: str) -> None:
        self.source.say(text)
        self.spoken += 1

    def close(self) -> None:
        pass
