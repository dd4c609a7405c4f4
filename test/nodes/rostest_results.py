"""Shared by the rostest checker nodes: wait until the sensorTest node of the launch has written
its results and left, then load them."""
import json
import os
import time
import xml.etree.ElementTree as ET

import rosgraph

FILES = ('sensorTestOutput.dat', 'sensorTestResults.json', 'sensorTestResults.xml')


def node_running(name='/sensorTest', caller='/rostest_results'):
    """True while `name` is registered with the master."""
    try:
        state = rosgraph.Master(caller).getSystemState()   # publishers, subscribers, services
    except Exception:
        return False
    return any(name in nodes for group in state for _, nodes in group)


def wait_for_results(output_dir, timeout, node='/sensorTest'):
    """(missing file paths, results) once all three files exist and `node` has left.

    results: {'json': dict, 'dat': str, 'junit': ElementTree root, 'sensors': {name: dict}}.
    """
    paths = [os.path.join(output_dir, f) for f in FILES]
    deadline = time.time() + timeout
    while time.time() < deadline:
        if all(os.path.isfile(p) for p in paths) and not node_running(node):
            break
        time.sleep(0.5)
    missing = [p for p in paths if not os.path.isfile(p)]
    if missing:
        return missing, None
    with open(paths[1]) as f:
        data = json.load(f)
    with open(paths[0]) as f:
        dat = f.read()
    return [], {'json': data, 'dat': dat, 'junit': ET.parse(paths[2]).getroot(),
                'sensors': {s['name']: s for s in data['sensors']}}
