"""A media check (camera, depth, microphone) fed directly with real serialized messages at explicit
times, without a window: the data rules' unit tests (sensors/test_depth.py,
sensors/test_audio.py)."""
from fake_pepper import serialized


def wire(msg):
    """The message as a subscriber receives it: serialised, then deserialised."""
    return type(msg)().deserialize(serialized(msg))


def feed(check, msgs, rate=10.0, start=0.05):
    for i, m in enumerate(msgs):
        check.feed(wire(m), start + i / rate)
    check.close()
    return check
