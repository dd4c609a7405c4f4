"""The benchmark's publisher process (rospy): waits until every topic has its subscribers,
publishes the streams of workload.STREAMS for `--publish` seconds, prints one JSON line with
the exact counts, and stays connected until told to stop (SIGINT or SIGTERM).

    python tools/benchmark/publisher.py --publish 10 --subscribers 2
"""
import argparse
import json
import signal
import sys
import threading
import time
from typing import Any, Dict, List, Optional, Sequence

import numpy as np
from workload import RING, STREAMS


def frames(encoding: str, w: int, h: int) -> List[bytes]:
    """RING distinct frames: moving gradients with noise (rgb8) or a depth ramp in mm (16UC1)."""
    rng = np.random.default_rng(7)
    yy, xx = np.mgrid[0:h, 0:w]
    out = []
    for i in range(RING):
        if encoding == 'rgb8':
            noise = rng.integers(0, 24, (h, w, 3), dtype=np.uint8)
            px = np.dstack([(xx + 6 * i) % 256, (yy + 3 * i) % 256, ((xx + yy) // 2 + 5 * i) % 256]).astype(np.uint8)
            out.append((px + noise).tobytes())
        else:
            mm = (800 + (xx * 3000) // w + 40 * i + rng.integers(0, 30, (h, w))).astype(np.uint16)
            mm[: h // 12] = 0
            out.append(mm.tobytes())
    return out


def _audio(samples: int) -> List[List[List[int]]]:
    """RING buffers of four sine channels (500, 1000, 1500, 2500 Hz at 48 kHz)."""
    t = np.arange(samples * RING) / 48000.0
    chans = [(3000 * np.sin(2 * np.pi * f * t)).astype(np.int16) for f in (500, 1000, 1500, 2500)]
    return [[c[i * samples:(i + 1) * samples].tolist() for c in chans] for i in range(RING)]


def _missing(pubs: Dict[str, Any], subscribers: int, wait: float) -> List[str]:
    """Wait up to `wait` s for `subscribers` subscriptions on every topic; the streams still short."""
    deadline = time.monotonic() + wait
    while any(p.get_num_connections() < subscribers for p in pubs.values()):
        if time.monotonic() > deadline:
            return [n for n, p in pubs.items() if p.get_num_connections() < subscribers]
        time.sleep(0.05)
    return []


def _stream(pub: Any, ring: List[Any], stream: Sequence[Any], start: float, end: float,
            counts: Dict[str, int]) -> None:
    """Publish one stream at its rate from `start` until `end` (monotonic), counting messages."""
    import rospy
    from sensor_msgs.msg import Image

    from pepper_interface_tests.msg import AudioCustomMsg
    name, _topic, enc, w, h, rate = stream
    period = 1.0 / rate
    k = 0
    while start + k * period < end:
        delay = start + k * period - time.monotonic()
        if delay > 0:
            time.sleep(delay)
        if enc == 'audio':
            msg = AudioCustomMsg(*ring[k % RING])
        else:
            msg = Image(width=w, height=h, encoding=enc, is_bigendian=0,
                        step=w * (3 if enc == 'rgb8' else 2), data=ring[k % RING])
            msg.header.stamp = rospy.Time.now()
            msg.header.frame_id = name
        pub.publish(msg)
        counts[name] += 1
        k += 1


def publish(seconds: float, wait: float, subscribers: int = 1) -> int:
    """Wait for `subscribers` subscriptions per topic, publish for `seconds`, print the counts."""
    import rospy
    from sensor_msgs.msg import Image

    from pepper_interface_tests.msg import AudioCustomMsg
    rospy.init_node('sensor_test_benchmark_publisher', disable_signals=True)
    pubs = {s[0]: rospy.Publisher(s[1], AudioCustomMsg if s[2] == 'audio' else Image, queue_size=60)
            for s in STREAMS}
    payloads = {s[0]: _audio(s[3]) if s[2] == 'audio' else frames(s[2], s[3], s[4]) for s in STREAMS}
    missing = _missing(pubs, subscribers, wait)
    if missing:
        print(json.dumps({'error': 'no subscriber on: ' + ', '.join(missing)}), flush=True)
        return 1
    time.sleep(0.3)
    counts = {name: 0 for name in pubs}
    start = time.monotonic() + 0.05
    end = start + seconds
    threads = [threading.Thread(target=_stream, args=(pubs[s[0]], payloads[s[0]], s, start, end, counts))
               for s in STREAMS]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    late = time.monotonic() - end
    print(json.dumps({'published': counts, 'seconds': seconds, 'finished_late_s': round(late, 3)}), flush=True)
    _linger()
    return 0


def _linger() -> None:
    """Stay up (and connected) until told to stop (at most 120 s), so nothing is cut off in flight."""
    stop = threading.Event()
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    signal.signal(signal.SIGINT, lambda *_: stop.set())
    stop.wait(120)


def main(argv: Optional[Sequence[str]] = None) -> int:
    p = argparse.ArgumentParser(prog='publisher.py', description=__doc__.split('\n\n')[0])
    p.add_argument('--publish', type=float, required=True, help='seconds of publishing')
    p.add_argument('--subscribers', type=int, default=1, help='subscriptions to wait for on every topic')
    p.add_argument('--wait', type=float, default=30.0, help='seconds to wait for them (default 30)')
    args = p.parse_args(argv)
    return publish(args.publish, wait=args.wait, subscribers=args.subscribers)


if __name__ == '__main__':
    sys.exit(main())
