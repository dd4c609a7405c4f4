#!/usr/bin/env python3
"""Test helper: a NAOqi client that subscribes modules to ALAudioDevice and records buffers.

  audio_qi_probe.py --port P --out OUT.npz --seconds S [--module NAME:FLAG:DEINT ...]
                    [--say-at T --say TEXT] [--check-unsubscribe]

Each module is a real qi service registered on the endpoint's service directory. OUT.npz holds,
per module NAME: NAME_meta (rows nch, nsamp, ts_sec, ts_usec, recv_time) and NAME_data (all
buffers' bytes, concatenated, as uint8); NAME_after_unsub (buffers received after unsubscribe
returned, with --check-unsubscribe); say_time (wall clock when say() returned, or -1).
"""
import argparse
import os
import sys
import threading
import time

import numpy as np
import qi


class Recorder:
    def __init__(self):
        self.meta, self.data, self.lock = [], [], threading.Lock()

    @qi.bind(qi.Void, (qi.Int32, qi.Int32, qi.Dynamic, qi.Buffer))
    def processRemote(self, nch, nsamp, ts, buf):
        now = time.time()
        with self.lock:
            self.meta.append((nch, nsamp, ts[0], ts[1], now))
            self.data.append(bytes(buf))


def main():
    p = argparse.ArgumentParser()
    p.add_argument('--port', type=int, required=True)
    p.add_argument('--out', required=True)
    p.add_argument('--seconds', type=float, default=2.0)
    p.add_argument('--module', action='append', default=[])
    p.add_argument('--say-at', type=float, default=-1)
    p.add_argument('--say', default='Hello, this is the Pepper microphone test.')
    p.add_argument('--check-unsubscribe', action='store_true')
    args = p.parse_args()
    app = qi.Application([sys.argv[0], '--qi-url=tcp://127.0.0.1:%d' % args.port,
                          '--qi-log-level=warning'])
    app.start()
    session = app.session
    device = session.service('ALAudioDevice')
    recorders = {}
    for spec in args.module or ['ProbeModule:0:1']:
        name, flag, deint = spec.split(':')
        recorders[name] = Recorder()
        session.registerService(name, recorders[name])
        device.setClientPreferences(name, 48000 if flag == '0' else 16000, int(flag), int(deint))
    for name in recorders:
        device.subscribe(name)
    start, say_time = time.time(), -1.0
    while time.time() - start < args.seconds:
        if args.say_at >= 0 and say_time < 0 and time.time() - start >= args.say_at:
            session.service('ALTextToSpeech').say(args.say)
            say_time = time.time()
        time.sleep(0.01)
    out = {'say_time': np.array(say_time)}
    for name in recorders:
        device.unsubscribe(name)
    if args.check_unsubscribe:
        counts = {n: len(r.meta) for n, r in recorders.items()}
        time.sleep(0.6)
        for n, r in recorders.items():
            out[n + '_after_unsub'] = np.array(len(r.meta) - counts[n])
    for name, r in recorders.items():
        with r.lock:
            out[name + '_meta'] = np.array(r.meta, dtype=np.float64).reshape(-1, 5)
            out[name + '_data'] = np.frombuffer(b''.join(r.data), dtype=np.uint8)
    np.savez(args.out, **out)
    print('saved', flush=True)
    sys.stderr.flush()
    os._exit(0)  # libqi-python can deadlock in interpreter teardown


if __name__ == '__main__':
    main()
