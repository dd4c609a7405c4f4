"""sensorTest's options are declared once (plan/options.py OPTIONS): the command-line flags, the
private ROS params, the Options fields and the option reference docs/options.md must all name the
same options. A field without a flag, a flag that fills no field, a param nobody reads or an option
the reference does not list fails here (the page is generated: tools/gen_options.py). Pure: no ROS master.
"""
import dataclasses
import os
import re
import typing
from typing import Optional, Tuple, Union

import pytest

from pepper_interface_tests import cli
from pepper_interface_tests.plan import options, settings
from pepper_interface_tests.plan.options import OPTIONS, Options

FIELDS = [f.name for f in dataclasses.fields(Options)]
# a valid value of each kind, as typed on the command line / as a ROS param, and what Options holds
VALUES = {options.TEXT: ('robot', 'robot', 'robot'), options.SECONDS: ('2.5', 2.5, 2.5),
          options.NAMES: ('laser,imu', ['laser', 'imu'], ('laser', 'imu'))}
TYPES = {options.TEXT: Optional[str], options.SECONDS: Optional[float],
         options.NAMES: Optional[Tuple[str, ...]], options.ON: Optional[bool]}


def test_every_options_field_has_a_flag_and_every_flag_a_field():
    declared = {o.name for o in OPTIONS if o.field}
    assert set(FIELDS) - declared == set(), 'Options fields without a row in OPTIONS'
    assert declared - set(FIELDS) == set(), 'OPTIONS rows (field=True) without an Options field'
    runs_the_node = {o.name for o in OPTIONS if not o.field}
    assert runs_the_node == {'end_launch', 'node_name'}
    assert not runs_the_node & set(FIELDS)


def test_each_field_is_typed_as_its_flag_reads_it():
    hints = typing.get_type_hints(Options)
    for name, kind in options.KINDS.items():
        off_too = kind == options.TEXT and any(o.name == name and o.kind == options.OFF for o in OPTIONS)
        # a value that can also be switched off (--baseline RUN / --no-baseline) holds False then
        assert hints[name] == (Optional[Union[str, bool]] if off_too else TYPES[kind]), name
        assert Options.__dataclass_fields__[name].default is None, '%s: None means "not given"' % name


def test_flags_are_unique_and_spelled_from_their_name():
    flags = [o.flag for o in OPTIONS]
    assert len(flags) == len(set(flags))
    for o in OPTIONS:
        expected = ('--no-' if o.kind == options.OFF else '--') + o.name.replace('_', '-')
        assert o.flag == expected, o
        assert o.group in ('files', 'run', 'media', 'results') and o.help
        assert o.kind not in options.SWITCHES or o.metavar is None, '%s takes no value' % o.flag


def test_params_are_the_fields_a_param_may_set():
    assert options.PARAMS == tuple(n for n in FIELDS if n != 'bag')   # --bag: command line only
    assert options.BOOL_PARAMS == tuple(n for n in options.PARAMS if options.KINDS[n] == options.ON)
    assert set(options.BOOL_PARAMS) == {o.name for o in OPTIONS if o.kind in options.SWITCHES and o.param}


def test_the_parser_has_exactly_the_declared_flags_in_their_sections():
    parser = cli.build_parser()
    got = {flag: (a.dest, a.const) for a in parser._actions for flag in a.option_strings
           if flag.startswith('--') and flag != '--help'}
    assert got == {o.flag: (o.name, {options.ON: True, options.OFF: False}.get(o.kind)) for o in OPTIONS}
    text = parser.format_help()
    sections = [line[:-1] for line in text.splitlines() if re.match(r'^[a-z]+:$', line)]
    assert sections[:5] == ['options', 'files', 'run', 'media', 'results']
    for o in OPTIONS:
        assert o.flag in text and o.help.split()[0] in text


@pytest.mark.parametrize('opt', [o for o in OPTIONS if o.field], ids=lambda o: o.flag)
def test_each_flag_sets_its_field_and_nothing_else(opt):
    argv = [opt.flag] if opt.kind in options.SWITCHES else [opt.flag, VALUES[opt.kind][0]]
    got = options.from_args(cli.build_parser().parse_args(argv))
    value = {options.ON: True, options.OFF: False}.get(opt.kind)
    expected = Options(**{opt.name: value if value is not None else VALUES[opt.kind][2]})
    assert got == expected


@pytest.mark.parametrize('name', options.PARAMS)
def test_each_param_sets_its_field_and_nothing_else(name):
    kind = options.KINDS[name]
    given = {'~' + name: 'false' if kind == options.ON else VALUES[kind][1]}
    asked = []

    def get(key, default=None):
        asked.append(key)
        return given.get(key, default)

    got = options.from_params(get)
    assert got == Options(**{name: False if kind == options.ON else VALUES[kind][2]})
    assert asked == ['~' + n for n in options.PARAMS]


def test_options_from_settings_are_the_declared_ones():
    assert settings.Options is Options and settings.TestPlan.options == Options()


def test_the_option_reference_lists_every_flag_with_its_param():
    """docs/options.md: one row per option, its flags in the first column, `~name` in the second
    exactly when it is a ROS param too."""
    with open(os.path.join(settings.package_dir(), 'docs', 'options.md'), encoding='utf-8') as f:
        rows = [line for line in f if line.startswith('| `--')]
    readme = {}
    for row in rows:
        cells = row.split('|')
        for flag in re.findall(r'`(--[a-z-]+)', cells[1]):
            readme[flag] = set(re.findall(r'`~([a-z_]+)`', cells[2]))
    assert set(readme) == {o.flag for o in OPTIONS}
    for o in OPTIONS:
        assert readme[o.flag] == ({o.name} if o.param else set()), o.flag
