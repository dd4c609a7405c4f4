"""Play the microphone recording after the window (D4.1 6.6), without ever holding up the run.

* Only when a sound device exists (/proc/asound/cards lists a card, or `aplay -l` does) and the
  CI environment variable is not set; otherwise one line says why playback was skipped.
* A 4-channel recording is played channel by channel in the spec's order (rearLeft, rearRight,
  frontLeft, frontRight): the channels are written one after another into one mono WAV next to
  the recording, which is played by `aplay` (or sox `play` when aplay is missing).
* SENSORTEST_AUDIO_DEVICE names the ALSA device to play on (e.g. "plughw:1,0", or "null" to
  exercise the path without hearing anything); when set, the sound-card probe is skipped.
* The player runs in a background process in the caller's process group (Ctrl-C stops it too);
  `play_channels` returns at once. With delete_after the recording (and the mono copy) are
  removed by that background process after playing.
"""
import os
import shlex
import shutil
import subprocess
from typing import List, Optional, Sequence, Tuple


def sound_device() -> Tuple[bool, str]:
    """(True, '') when a sound card exists, else (False, reason)."""
    try:
        with open('/proc/asound/cards', encoding='utf-8', errors='replace') as f:
            text = f.read()
        if text.strip() and 'no soundcards' not in text:
            return True, ''
    except OSError:
        pass
    if shutil.which('aplay'):
        try:
            out = subprocess.run(['aplay', '-l'], capture_output=True, text=True, timeout=5)
            if 'card ' in out.stdout:
                return True, ''
        except (OSError, subprocess.SubprocessError):
            pass
    return False, 'no sound device'


def player_command(device: Optional[str] = None) -> Optional[List[str]]:
    if shutil.which('aplay'):
        return ['aplay', '-q'] + (['-D', device] if device else [])
    if shutil.which('play') and not device:
        return ['play', '-q']
    return None


def _mono_sequence(path: str, channels: Sequence[str]) -> Tuple[str, float]:
    """Write the channels of `path` one after another into a mono WAV; returns its path and seconds."""
    import numpy as np
    import soundfile
    data, rate = soundfile.read(path, dtype='int16', always_2d=True)
    mono = np.concatenate([data[:, i] for i in range(min(len(channels), data.shape[1]))])
    out = os.path.join(os.path.dirname(path), '.' + os.path.basename(path)[:-4] + '.play.wav')
    soundfile.write(out, mono, rate, subtype='PCM_16')
    return out, len(mono) / float(rate)


def play_channels(path: str, channels: Optional[Sequence[str]] = None,
                  delete_after: bool = False) -> Tuple[Optional[subprocess.Popen], str]:
    """Start playing `path` (channel by channel when `channels` names them).

    Prints and returns one line for the user; returns (process or None, line)."""
    proc, line = _start(path, channels, delete_after)
    print(line, flush=True)
    return proc, line


def _start(path: str, channels: Optional[Sequence[str]],
           delete_after: bool) -> Tuple[Optional[subprocess.Popen], str]:
    if os.environ.get('CI'):
        return None, 'playback off (CI): %s kept' % os.path.basename(path)
    device = os.environ.get('SENSORTEST_AUDIO_DEVICE') or None
    if device is None:
        ok, why = sound_device()
        if not ok:
            return None, '%s: playback skipped' % why
    cmd = player_command(device)
    if cmd is None:
        return None, 'no aplay or sox play found: playback skipped'
    try:
        if channels:
            target, seconds = _mono_sequence(path, channels)
            order = ', '.join(channels)
            remove = [target] + ([path] if delete_after else [])
        else:
            import soundfile
            target, seconds = path, soundfile.info(path).duration
            order = 'as recorded'
            remove = [path] if delete_after else []
        script = ' '.join(shlex.quote(a) for a in cmd + [target])
        if remove:
            script += '; rm -f ' + ' '.join(shlex.quote(p) for p in remove)
        proc = subprocess.Popen(['sh', '-c', script], stdin=subprocess.DEVNULL,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    except Exception as e:   # playback is a courtesy: never fail the run for it
        return None, 'playback failed: %s' % e
    return proc, 'playing %s (%s, %.0f s) with %s%s' % (
        os.path.basename(path), order, seconds, cmd[0], ', deleted afterwards' if delete_after else '')
