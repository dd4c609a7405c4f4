"""Test helpers shared by outputs/report/test_page.py, outputs/test_diagnostics_topic.py,
outputs/test_history.py and others: start test/nodes/core_publisher.py publishers against a real
master, run scripts/sensorTest as a user would (a subprocess), and read what it printed."""
import os
import re
import subprocess
import sys

from rosmaster import NODES, kill_group, script, spawn, wait_for_publishers

HERE = NODES   # the node scripts' folder (test/nodes/)
PUBLISHER = os.path.join(NODES, 'core_publisher.py')


def start_publishers(master, specs):
    """specs: [(kind, topic, extra args...)]; returns the processes once each publishes and
    the master knows it (publishers; a `listener` only subscribes)."""
    procs = []
    for kind, topic, *extra in specs:
        p = spawn([sys.executable, PUBLISHER, kind, topic] + list(extra), master.env(),
                  stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        procs.append(p)
    for p in procs:
        line = p.stdout.readline()
        assert line.strip() in ('publishing', 'listening'), 'publisher did not start: %r' % line
    wait_for_publishers(master, [topic for kind, topic, *_ in specs if kind != 'listener'])
    return procs


def stop(procs):
    for p in procs:
        kill_group(p)
        if p.stdout:
            p.stdout.close()


def sensor_test(master, args, timeout=120):
    """Run scripts/sensorTest to its end; returns the CompletedProcess (text output)."""
    return subprocess.run(script('sensorTest') + ['--no-show'] + list(args), env=master.env(),
                          capture_output=True, text=True, timeout=timeout, start_new_session=True)


def printed_path(stdout, label):
    """The path sensorTest printed after `label:` (e.g. 'report'), or None; on the same line
    or, when the line would be too wide for the terminal, alone on the next one."""
    m = re.search(r'^%s:\s+(\S+)' % re.escape(label), stdout, re.M)
    return m.group(1) if m else None
