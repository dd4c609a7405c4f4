"""Fixtures of the audio bridge's tests."""
import pytest

from audio_chain import Procs


@pytest.fixture
def procs(tmp_path, master):
    """The test's processes; stopped before its roscore (``master``) goes."""
    p = Procs(tmp_path)
    yield p
    p.stop_all()
    print(p.logs())  # shown by pytest only when the test failed
