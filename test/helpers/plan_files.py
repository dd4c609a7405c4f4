"""A complete, valid set of sensorTest's input files in a temporary folder, for the tests of
the configuration, input, topics and expectations files (test_settings, test_expectations):
each test overwrites the one file it is about."""

import pytest

from pepper_interface_tests.plan import catalog
from pepper_interface_tests.plan.settings import ConfigError, Options, load_plan

ALL = [n for n, s in catalog.SENSORS.items() if not s.opt_in]   # opt-in rows (motion: --move) aside


def write(path, text, encoding='utf-8'):
    """`text` (str, written in `encoding`, or bytes as they are) into `path`; returns the path."""
    with open(str(path), 'wb') as f:
        f.write(text.encode(encoding) if isinstance(text, str) else text)
    return str(path)


def topics_text(names=ALL, prefix='/t'):
    return ''.join('%s %s/%s\n' % (n, prefix, n) for n in names)


class Files:
    """A test module's `files` fixture returns Files(tmp_path)."""

    def __init__(self, tmp_path):
        self.config = write(tmp_path / 'config.ini', 'platform robot\nrobotTopics topics.dat\n'
                                                     'simulatorTopics sim.dat\nmode sequential\n')
        self.input = write(tmp_path / 'input.ini', ''.join('%s true\n' % n for n in ALL))
        self.topics = write(tmp_path / 'topics.dat', topics_text())
        self.sim = write(tmp_path / 'sim.dat', topics_text(prefix='/sim'))
        self.expectations = write(tmp_path / 'expect.yaml', 'defaults:\n  min_messages: 3\n')
        self.out = str(tmp_path / 'out')
        self.dir = str(tmp_path)

    def options(self, **kw):
        base = dict(config=self.config, input=self.input, expectations=self.expectations,
                    topics_dir=self.dir, output_dir=self.out)
        base.update(kw)
        return Options(**base)


def error_of(options):
    with pytest.raises(ConfigError) as info:
        load_plan(options)
    return info.value
