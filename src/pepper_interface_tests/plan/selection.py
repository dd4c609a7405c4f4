"""Which sensors a run tests, and what the run header says about it.

The rules (docs/configuration.md "Choosing what runs": `--cameras`, `--require-heard`, `--mic-mode`):
- The input file (or `--sensors`) says which sensors run, in which order.
- `--cameras pepper|realsense|both` (or `~cameras`) selects the cameras it names: without
  `--sensors`, the run tests exactly the named group's cameras (pepper: front, bottom, depth,
  stereo; realsense: RGB and depth; both: all six), whatever the input file's camera lines say;
  a camera the input file enables but the option excludes is SKIPPED ("left out by --cameras").
  With `--sensors`, that list is exact: `--cameras` adds nothing and only leaves out (SKIPPED)
  the named cameras of the other group. Not given: the input file decides, as the spec says.
- `--require-heard` needs the microphone in a live run with speech: otherwise the run is refused
  (exit 2); where speech is not checked (no speech in the run, a bag, the simulator) it has no
  effect and the header says so.
Every choice that leaves something out is said in `notes` (printed under the run header).
"""
from typing import Dict, List, Optional, Sequence, Tuple

from . import catalog
from .model import SensorPlan
from .options import Options
from .textfile import ConfigError

CAMERA_GROUPS: Dict[str, Tuple[str, ...]] = {'pepper': ('pepper',), 'realsense': ('realsense',),
                                              'both': ('pepper', 'realsense')}


def _names(names):
    return ', '.join(names)


def select(file_order: Sequence[Tuple[str, bool]], cameras: Optional[str], input_name: str,
           platform: str = 'robot') -> Tuple[List[str], List[str]]:
    """Input-file order [(name, enabled)] and a --cameras choice (or None) -> (the run's
    sensor names in order, notes). Sensors the file enables but --cameras excludes stay in
    the order (they are SKIPPED with a reason); group cameras missing from the file are
    appended in the catalog's order."""
    notes: List[str] = []
    order: List[str]
    off: List[str]
    if cameras is None:
        order = [n for n, on in file_order if on]
        off = [n for n, on in file_order if not on]
        missing = [n for n, s in catalog.SENSORS.items() if n not in dict(file_order) and not s.opt_in]
        off_rs = [n for n in off + missing if catalog.SENSORS[n].camera == 'realsense']
        if off:
            notes.append('not tested: %s (false in %s)' % (_names(off), input_name))
        if missing:
            notes.append('not tested: %s (not in %s)' % (_names(missing), input_name))
        if off_rs and platform != 'simulator':   # the simulator has no RealSense
            notes.append('the RealSense cameras run with --cameras realsense (only them) or '
                         '--cameras both (with Pepper\'s cameras)')
        return order, notes
    group = CAMERA_GROUPS[cameras]
    listed = dict(file_order)
    order, forced, off = [], [], []
    for name, on in file_order:
        camera = catalog.SENSORS[name].camera
        if camera in group:
            order.append(name)
            if not on:
                forced.append(name)
        elif on:
            order.append(name)            # a non-camera sensor, or a camera SKIPPED below
        else:
            off.append(name)
    added = [n for n, s in catalog.SENSORS.items() if s.camera in group and n not in listed]
    order += added
    chosen = [n for n in order if catalog.SENSORS[n].camera in group]
    notes.append('cameras: %s (--cameras %s%s)' % (
        _names(chosen), cameras, ', whatever %s says' % input_name if forced or added else ''))
    excluded = [n for n in order if catalog.SENSORS[n].camera and catalog.SENSORS[n].camera not in group]
    if excluded:
        notes.append('skipped: %s (left out by --cameras %s)' % (_names(excluded), cameras))
    if off:
        notes.append('not tested: %s (false in %s)' % (_names(off), input_name))
    return order, notes


def excluded_by_cameras(sensor: catalog.Sensor, cameras: Optional[str]) -> Optional[str]:
    """The skip reason of a camera that --cameras leaves out, or None."""
    if cameras is None or not sensor.camera or sensor.camera in CAMERA_GROUPS[cameras]:
        return None
    return 'left out by --cameras %s' % cameras


def sensors_option_notes(order: Sequence[str], cameras: Optional[str]) -> List[str]:
    """Notes for a --sensors run (the user named every sensor): what --cameras does then."""
    notes: List[str] = []
    named = set(order)
    if cameras is not None:
        group = CAMERA_GROUPS[cameras]
        unnamed = [n for n, s in catalog.SENSORS.items() if s.camera in group and n not in named]
        if unnamed:
            notes.append('--cameras %s adds no camera to --sensors (not named: %s)'
                         % (cameras, _names(unnamed)))
    return notes


def rerun_failed(output_dir: str, platform: str, options: Options) -> Tuple[Tuple[str, ...], List[str]]:
    """--rerun-failed: the sensors that did not pass in the latest run of `output_dir` (its
    sensorTestResults.json, the spec's path) -> (sensor names, notes). Same names and rule as
    `sensorTestHistory failed`."""
    import json
    import os

    from .. import results
    path = os.path.join(output_dir, results.JSON_FILE)
    fix = 'run sensorTest once without --rerun-failed, or point --output-dir at the folder of that run'
    if options.sensors:
        raise ConfigError('--rerun-failed and --sensors both choose the sensors',
                          fix='give one of them (sensorTestHistory failed prints the --sensors of the last run)')
    try:
        with open(path, encoding='utf-8') as f:
            data = json.load(f)
    except FileNotFoundError:
        raise ConfigError('--rerun-failed: no previous run in %s (no %s)' % (output_dir, results.JSON_FILE),
                          fix=fix) from None
    except (OSError, ValueError) as e:
        raise ConfigError('--rerun-failed: cannot read %s: %s' % (path, e), fix=fix) from None
    why = results.malformed(data)
    if why:
        raise ConfigError('--rerun-failed: %s is not a sensorTest result (%s)' % (path, why), fix=fix)
    run_id = data.get('run_id') or '?'
    if data.get('platform') not in (None, platform):
        raise ConfigError('--rerun-failed: run %s was on the %s platform, this run is on the %s'
                          % (run_id, data['platform'], platform), fix='add --platform %s' % data['platform'])
    failed = results.not_passed(results.read_run(data))
    if not failed:
        raise ConfigError('--rerun-failed: nothing to re-run: no sensor failed in run %s (%s)' % (run_id, path),
                          fix='run sensorTest without --rerun-failed to test every sensor')
    return tuple(failed), ['re-running what did not pass in run %s: %s' % (run_id, _names(failed))]


def require_heard_notes(plans: Sequence[SensorPlan], options: Options, input_path: str) -> List[str]:
    """--require-heard: refuse a live run with speech but no microphone; a note when it has no
    effect. `plans` are the run's SensorPlans."""
    if not options.require_heard:
        return []
    active = {p.name for p in plans if p.skip_reason is None}
    if options.bag:
        return ['--require-heard has no effect on a bag: speech is not checked from a bag']
    if 'speech' not in active:
        why = 'speech is not available in the simulator' if any(p.name == 'speech' for p in plans) \
            else 'speech is not in this run'
        return ['--require-heard has no effect: %s' % why]
    if 'microphone' not in active:
        raise ConfigError(
            '--require-heard: speech can only be heard by the microphones, and the microphone '
            'is not in this run',
            fix='add microphone to the run (e.g. --sensors speech,microphone, or "microphone true" '
                'in %s), or leave out --require-heard' % input_path)
    return ['speech passes only when the microphones hear the sentence (--require-heard)']
