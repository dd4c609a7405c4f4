#!/usr/bin/env python3
"""sensorTest's verdicts live on ROS 2 against naoqi_driver2 beside the ROS 1 reference: the real
naoqi_driver's golden recordings of the same fake NAOqi world judged with --bag (tools/real-
driver2/live.sh). A row's reference is the recording that carries its topic; a difference is
printed by name and exits 1.

    compare_live.py LIVE.json NAME=REF.json [NAME=REF.json ...]

Which recording is a row's reference (test/fixtures/real-driver/manifest.json): the microphone
is in `audio` alone (the healthy recordings were made without the audio relay), `motion` is
judged from `move` (a recording has no motion row: its witnesses carry the recorded turn, and
pass), everything else from `healthy_<head>`. `speech` has none: a command sensorTest publishes,
which no recording of the driver's topics holds (the ROS 1 driver subscribes /speech as
naoqi_driver2 does: naoqi_driver src/naoqi_driver.cpp, registerSubscriber "speech";
naoqi_driver2 src/subscribers/speech.cpp:37)."""
import json
import sys
from typing import Dict, List, Tuple

WITNESSES = ('odometry', 'imu', 'laser', 'jointState', 'frontCamera')


def rows(path: str) -> Dict[str, dict]:
    with open(path) as f:
        return {s['name']: s for s in json.load(f)['sensors']}


def reference(name: str, refs: Dict[str, Dict[str, dict]]) -> Tuple[str, str]:
    """(verdict, which recording) of the ROS 1 reference for a row; ('', why) when none."""
    if name == 'speech':
        return '', 'a command: no recording holds it'
    if name == 'microphone' and 'audio' in refs:
        return refs['audio'][name]['verdict'], 'audio.bag'
    if name == 'motion':
        if 'move' not in refs:
            return '', 'no move recording given'
        move = refs['move']
        turned = any('recorded base turn' in n for n in move['odometry'].get('notes', []))
        ok = turned and all(move[w]['verdict'] == 'PASS' for w in WITNESSES)
        return ('PASS' if ok else 'FAIL'), 'move.bag (its witnesses, the turn %sfound)' % ('' if turned else 'not ')
    healthy = [k for k in refs if k.startswith('healthy_')]
    if not healthy or name not in refs[healthy[0]]:
        return '', 'not in the healthy recording'
    return refs[healthy[0]][name]['verdict'], healthy[0] + '.bag'


def main(argv: List[str]) -> int:
    live = rows(argv[0])
    refs = {a.split('=', 1)[0]: rows(a.split('=', 1)[1]) for a in argv[1:]}
    print('%-14s %-12s %-12s %s' % ('sensor', 'ROS 2 live', 'ROS 1 ref', 'reference'))
    differ = []
    for name, row in live.items():
        want, where = reference(name, refs)
        same = not want or want == row['verdict']
        mark = '' if same else '   <- DIFFERENT'
        warn = ' (%d warning%s)' % (len(row['warnings']), 's' * (len(row['warnings']) > 1)) if row['warnings'] else ''
        print('%-14s %-12s %-12s %s%s%s' % (name, row['verdict'], want or '-', where, warn, mark))
        if not same:
            differ.append('%s: %s live, %s in %s: %s' % (name, row['verdict'], want, where, '; '.join(row['reasons'])))
    for line in differ:
        print('DIFFERENT ' + line)
    print('%d rows, %d with a ROS 1 reference, %d different'
          % (len(live), sum(1 for n in live if reference(n, refs)[0]), len(differ)))
    return 1 if differ else 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
