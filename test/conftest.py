import os
import sys

import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rosmaster import Master  # noqa: E402


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
