import os
import subprocess
import sys

import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rosmaster import Master, script  # noqa: E402


@pytest.fixture
def master():
    """A fresh real roscore on a free port for one test."""
    with Master() as m:
        yield m


@pytest.fixture(scope='module')
def module_master():
    """One real roscore shared by the tests of a module."""
    with Master() as m:
        yield m


BAG_SECONDS = 5.0


@pytest.fixture(scope='session')
def recorded_bags(tmp_path_factory):
    """The four bags of recordTestBags (robot/simulator, good/faulty), recorded once per session
    from the emulator with its own roscore: {variant name: path}."""
    out_dir = tmp_path_factory.mktemp('bags')
    run = subprocess.run(script('recordTestBags') + ['--out', str(out_dir), '--seconds', str(BAG_SECONDS)],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
    assert run.returncode == 0, run.stdout
    return {name[:-4]: str(out_dir / name) for name in os.listdir(str(out_dir)) if name.endswith('.bag')}
