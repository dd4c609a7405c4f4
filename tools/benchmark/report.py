"""What the benchmark prints: the per-stream table and the CPU and memory lines of a round,
the summary against the targets, a py-spy profile's top entries."""
import argparse
import os
from typing import Any, Dict, List, Optional, Tuple

from workload import STREAMS, Stream

# CPU of sensorTest over its floor: listening (recording off) over `rostopic hz` on the same
# streams at the same time; recording over listening plus the recorders alone (encoders.py)
TARGETS = {'off': 1.1, 'on': 1.1}
FLOORS = {'off': 'rostopic hz', 'on': 'listening + recorders alone'}
TARGET_LAST_FILE_S = 2.0
TARGET_RSS_MB = 300.0


def _recorded(out_dir: str, sensor: str) -> Tuple[Optional[int], Optional[str]]:
    """(frames or samples recorded, the WAV's format) of one sensor's recording, from the file."""
    from pepper_interface_tests.media.recording import ffprobe_frames
    from pepper_interface_tests.plan import catalog
    if sensor == 'microphone':
        path = os.path.join(out_dir, 'microphoneOutput.wav')
        if not os.path.exists(path):
            return None, None
        import soundfile
        info = soundfile.info(path)
        return info.frames, '%d ch %d Hz %s' % (info.channels, info.samplerate, info.subtype)
    video = catalog.SENSORS[sensor].video
    if video is None:       # a sensor that records no video
        return None, None
    path = os.path.join(out_dir, video)
    if not os.path.exists(path):
        return None, None
    return ffprobe_frames(path), None


def _stream_cells(stream: Stream, r: Dict[str, Any], out_dir: str,
                  record: bool) -> Tuple[str, Optional[float], str]:
    """(stream description, recorded messages' worth, video or WAV column) of one row."""
    name, _topic, enc, w, h, rate = stream
    frames, extra = _recorded(out_dir, name) if record else (None, None)
    if name == 'microphone':
        recorded = frames / float(w) if frames is not None else None
        return ('4 x %d int16 @ 48 kHz, %.1f/s' % (w, rate), recorded,
                extra or ('no WAV' if record else 'recording off'))
    v = (r.get('values') or {}).get('video') or {}
    video = '%s %s fps' % (v.get('codec'), v.get('fps')) if v.get('codec') else \
        ('no video' if record else 'recording off')
    if v.get('frames_dropped'):
        video += ', %d dropped' % v['frames_dropped']
    return '%dx%d %s @ %g Hz' % (w, h, enc, rate), frames, video


def stream_table(results: Dict[str, Dict[str, Any]], published: Dict[str, Any], out_dir: str,
                 target: float, record: bool = True) -> Tuple[Dict[str, Dict[str, Any]], bool]:
    """Print published, received and recorded per stream; (the rows, every share >= target)."""
    head = '%-21s %-38s %9s %9s %9s %8s %7s  %-7s %s' % (
        'sensor', 'stream', 'published', 'received', 'recorded', 'recv %', 'Hz', 'verdict', 'video')
    print('\n' + head)
    print('-' * len(head))
    ok = True
    rows = {}
    for stream in STREAMS:
        name = stream[0]
        r = results.get(name, {})
        sent = published['published'].get(name, 0)
        got = r.get('messages', 0)
        description, recorded, video = _stream_cells(stream, r, out_dir, record)
        share_recv = got / float(sent) if sent else 0.0
        share_rec = (recorded or 0) / float(sent) if sent else 0.0
        ok = ok and share_recv >= target and (share_rec >= target or not record)
        rows[name] = {'published': sent, 'received': got, 'recorded': recorded}
        print('%-21s %-38s %9d %9d %9s %7.1f%% %7s  %-7s %s' % (
            name, description, sent, got, ('%.0f' % recorded) if recorded is not None else '-',
            100 * share_recv, '%.2f' % r['rate_hz'] if r.get('rate_hz') else '-', r.get('verdict', '?'), video))
        for reason in r.get('reasons', []):
            print('%21s   reason: %s' % ('', reason))
    return rows, ok


def print_round(m: Dict[str, Any], threads: Optional[Dict[int, float]], main_thread: int) -> None:
    """The round's CPU, memory, ratio, last file and publisher lines (m: the round's measurements)."""
    print('\nsensorTest:  exit %s, wall %.1f s, CPU %.2f s (user %.2f + system %.2f, with its ffmpeg '
          'children%s)'
          % (m['exit'], m['wall'], m['cpu'], m['user'], m['system'],
             ': %.2f s in the encoders, %.2f s in the writer threads' % (m['encoders'], m['writers'])
             if m['mode'] == 'on' else ''))
    print('memory (peaks, sampled every 0.1 s): sensorTest and its children together PSS %.0f MB '
          '(USS %.0f MB), RSS %.0f MB; sensorTest alone RSS %.0f MB, the children RSS %.0f MB'
          % (m['pss_tree'], m['uss_tree'], m['rss_tree'], m['rss'], m['rss_children']))
    print('page faults (minor, with the reaped children): sensorTest %d, rostopic hz %d'
          % (m['faults'], m['hz_faults']))
    print('rostopic hz: CPU %.2f s (user %.2f + system %.2f)' % (m['hz_cpu'], m['hz_user'], m['hz_system']))
    if m['mode'] == 'off':
        print('ratio: %.2fx of rostopic hz (target <= %.1fx)%s' % (
            m['ratio'], TARGETS['off'], '  [profiled: not comparable]' if m['profile'] else ''))
    else:
        print('ratio: %.2fx of rostopic hz (no target: the encoders\' work is not hz\'s); against '
              'listening + the recorders alone in the summary' % m['ratio'])
    if m['mode'] == 'on':
        last_file = m['last_file']
        print('end of window -> last file written: %s' % ('%.2f s' % last_file if last_file is not None
                                                          else 'no file'))
    print('publisher: %s s of publishing, finished %s s late' % (m['publish_s'], m['late']))
    if threads:
        print('CPU per thread (sampled every 0.1 s; the main thread first): %s'
              % ', '.join('%.2f' % threads[t] for t in sorted(threads, key=lambda t: (t != main_thread, -threads[t]))))
    if m['profile'] and os.path.exists(m['profile']):
        print_profile(m['profile'])


def floor_ratios(rounds: List[Dict[str, Any]]) -> None:
    """Each round's floor and its ratio to it (m['floor'], m['floor_ratio']; None when there is
    none): `rostopic hz` for listening; for recording, the listening round of the same run
    (its label's number) plus the recorders alone (m['recorders_alone'])."""
    off = {m['label'].split('-', 1)[1]: m for m in rounds if m['mode'] == 'off'}
    for m in rounds:
        if m['mode'] == 'off':
            m['floor'] = m['hz_cpu']
        else:
            listening = off.get(m['label'].split('-', 1)[1])
            enc = m.get('recorders_alone')
            m['floor'] = listening['cpu'] + enc if listening is not None and enc is not None else None
        m['floor_ratio'] = m['cpu'] / m['floor'] if m['floor'] else None


def summary(rounds: List[Dict[str, Any]], args: argparse.Namespace) -> bool:
    """One line per round against the targets; whether every round met every one."""
    floor_ratios(rounds)
    head = '%-8s %10s %10s %7s %-28s %7s %7s %9s %9s %9s %s' % (
        'round', 'sensorTest', 'floor', 'ratio', 'floor is', 'target', 'hz', 'last file', 'tree PSS',
        'counts', 'met')
    print('\nsummary (CPU seconds of the whole process incl. children; side by side in one round)')
    print(head)
    print('-' * len(head))
    ok = True
    for m in rounds:
        ratio = m['floor_ratio']
        met = [ratio is not None and ratio <= TARGETS[m['mode']], m['pss_tree'] <= TARGET_RSS_MB, m['counts_ok']]
        floor = FLOORS[m['mode']]
        if m['mode'] == 'on':
            met.append(m['last_file'] is not None and m['last_file'] <= TARGET_LAST_FILE_S)
            if m.get('recorders_alone') is not None:
                floor = 'listening + recorders %.2fs' % m['recorders_alone']
        ok = ok and all(met)
        print('%-8s %9.2fs %10s %7s %-28s %6.1fx %6.2fs %9s %6.0f MB %9s %s' % (
            m['label'], m['cpu'], '%.2fs' % m['floor'] if m['floor'] else '-',
            '%.2fx' % ratio if ratio is not None else '-', floor, TARGETS[m['mode']], m['hz_cpu'],
            '%.2f s' % m['last_file'] if m['last_file'] is not None else '-', m['pss_tree'],
            'all' if m['counts_ok'] else 'MISSING', 'yes' if all(met) else 'NO'))
    print('targets: listening (recording off) <= %.1fx of rostopic hz on the same streams at the same '
          'time; recording <= %.1fx of listening + the recorders alone (the same run\'s listening round, '
          'and the package\'s recorders, ffmpeg and writer threads, on the same frames at the same '
          'rates with nothing else running); last file <= %.0f s after '
          'the window; peak memory <= %.0f MB (PSS of sensorTest and its ffmpeg children together: '
          'shared libraries counted once; the RSS sum counts them once per process); >= %.0f%% received '
          'and recorded: %s' % (TARGETS['off'], TARGETS['on'], TARGET_LAST_FILE_S, TARGET_RSS_MB,
                                100 * args.target, 'all met' if ok else 'NOT all met'))
    return ok


def print_profile(path: str, top: int = 15) -> None:
    """Top entries of a py-spy raw (collapsed stacks) profile: self and inclusive samples."""
    own: Dict[str, int] = {}
    incl: Dict[str, int] = {}
    total = 0
    with open(path) as f:
        for line in f:
            stack, _, count = line.rstrip().rpartition(' ')
            if not stack:
                continue
            n = int(count)
            total += n
            frames = [fr.split(' (')[0] + ' (' + fr.split(' (')[1].split(':')[0].split('/')[-1] + ')'
                      if ' (' in fr else fr for fr in stack.split(';')]
            own[frames[-1]] = own.get(frames[-1], 0) + n
            for fr in set(frames):
                incl[fr] = incl.get(fr, 0) + n
    print('profile %s: %d samples' % (path, total))
    print('  top self:')
    for fr, n in sorted(own.items(), key=lambda kv: -kv[1])[:top]:
        print('    %5.1f%%  %s' % (100.0 * n / total, fr))
    print('  top inclusive:')
    for fr, n in sorted(incl.items(), key=lambda kv: -kv[1])[:top]:
        print('    %5.1f%%  %s' % (100.0 * n / total, fr))
