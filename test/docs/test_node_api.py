"""Unit: docs/node-api.md, the nodes' ROS interface in the ROS wiki's Node API form, against the
code. The source is read with `ast`: every rospy.Publisher, rospy.Subscriber and rospy.Service call (and the
diagnostic_updater that publishes /diagnostics), every rospy.get_param / has_param /
search_param / set_param, and every long option a program's parser declares. Each must be listed
under its node, with the message type the code names where it names one, and nothing listed may
be gone from the code.

A call whose topic or param the source names by a literal, a module constant or a constant
table entry is resolved here; a call that computes it (a topic from the topics file, params from a
table) is in DYNAMIC with the code that says which ones it can be. A new call of either kind that
this file does not know fails: say which node makes it (OWNERS) and list what it does in the page.
"""
import ast
import functools
import os
import re
from typing import Callable, Dict, List, Optional, Set, Tuple

import pytest

import codebase_files

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))   # test/docs/ -> the repository
SRC = os.path.join(ROOT, 'src', 'pepper_interface_tests')
PAGE = os.path.join(ROOT, 'docs', 'node-api.md')

TOPIC_CALLS = {'Publisher': 'published', 'Subscriber': 'subscribed', 'Service': 'services'}
# rosapi.py, the ROS seam (rospy on ROS 1, rclpy on ROS 2): its publisher() and subscriber()
# count as rospy's, with the type named by its second argument ('pkg/Type'); the seam's own
# forwarding calls are no node's
SEAM_CALLS = {'publisher': 'published', 'subscriber': 'subscribed', 'any_subscriber': 'subscribed'}
SEAM = {'rosapi.py'}
PARAM_CALLS = ('get_param', 'has_param', 'search_param', 'set_param')

# the modules that make ROS calls, by the node that runs them
OWNERS = {
    'sensorTest': ('node.py', 'sources/live.py', 'sources/identity.py', 'sensors/audio.py',
                   'sensors/guide.py', 'sensors/motion.py', 'sensors/speech.py', 'motion/commands.py',
                   'motion/witnesses.py', 'outputs/diagnostics.py'),
    'pepperEmulator': ('emulator/node.py', 'emulator/commands.py', 'emulator/events.py', 'emulator/info.py',
                       'emulator/publishers.py', 'emulator/tf_publisher.py', 'emulator/second_publisher.py',
                       'emulator/camera_info.py'),
    'naoqiAudioPublisher': ('audio_bridge/publisher.py', 'audio_bridge/publisher2.py'),
}
# the programs and the modules whose parsers declare their command lines
COMMAND_LINES = {
    'sensorTest': ('plan/options.py',),
    'pepperEmulator': ('emulator/node.py',),
    'naoqiAudioPublisher': ('audio_bridge/publisher.py', 'audio_bridge/publisher2.py'),
    'naoqiAudio': ('audio_bridge/capture.py',),
    'sensorTestLaunch': ('launch/wrapper.py',),
    'sensorTestHistory': ('history_cli.py',),
}


def _sensor_topics(drives_itself: Optional[bool]) -> Set[Tuple[str, Optional[str]]]:
    """Each sensor's topic in the shipped topics files (robot and simulator) with its type; only
    the sensors listened to (False), only those that drive themselves (True), or all (None)."""
    from pepper_interface_tests.plan import catalog, settings
    from pepper_interface_tests.sensors.families import FAMILIES
    out = set()
    for name in ('pepperTopics.dat', 'simulatorTopics.dat'):
        for sensor, topic in settings.read_topics(os.path.join(ROOT, 'data', name)).items():
            s = catalog.SENSORS[sensor]
            if drives_itself is None or FAMILIES[s.family].traits.drives_itself == drives_itself:
                out.add((topic, s.msg_type))
    return out


def _emulator_topics() -> Set[Tuple[str, Optional[str]]]:
    from pepper_interface_tests.emulator.profiles import build_profile
    from pepper_interface_tests.plan import catalog
    out: Set[Tuple[str, Optional[str]]] = set()
    for kw in (dict(name='robot', realsense=True, audio='direct', touch=True),
               dict(name='robot', head='xtion', realsense=True, audio='direct', touch=True),
               dict(name='robot-stock', realsense=True, audio='direct', touch=True), dict(name='simulator')):
        for spec in build_profile(**kw).sensors:
            types = catalog.accepted_types(catalog.SENSORS[spec.name])
            for topic in [spec.topic] + [t for t, _ in spec.extra]:
                out.add((topic, types[0] if len(types) == 1 else None))
    return out


def _speech_topic() -> Set[Tuple[str, Optional[str]]]:
    return {(t, 'std_msgs/String') for t, _ in _sensor_topics(True) if t == '/speech'}


def _option_params() -> Set[Tuple[str, Optional[str]]]:
    from pepper_interface_tests.plan.options import PARAMS
    return {('~' + n, None) for n in PARAMS}


def _table_params(module: str, table: str, skip: Tuple[str, ...] = ()) -> Callable[[], Set[Tuple[str, Optional[str]]]]:
    def params() -> Set[Tuple[str, Optional[str]]]:
        import importlib
        values = getattr(importlib.import_module('pepper_interface_tests.' + module), table)
        return {('~' + n, None) for n in values if n not in skip}
    return params


# (module, the call's first argument as written) -> what it can be, from the code's own tables
DYNAMIC: Dict[Tuple[str, str], Callable[[], Set[Tuple[str, Optional[str]]]]] = {
    # every listened-to sensor, and /tf's static companion (sensors/tree.py TreeWitness)
    ('sources/live.py', 'run.topic'): lambda: _sensor_topics(False) | {('/tf_static', 'tf2_msgs/TFMessage')},
    ('motion/witnesses.py', 'topic'): lambda: {(t, None) for t, _ in _sensor_topics(False)},   # a subset
    ('sensors/audio.py', 'self.topic'): lambda: {(t, None) for t, ty in _sensor_topics(False) if 'Audio' in ty},
    ('sources/identity.py', 'topic'): lambda: {('/naoqi_driver/info', 'naoqi_bridge_msgs/StringStamped')},
    ('sensors/speech.py', "self.plan.topic or '/speech'"): _speech_topic,
    ('sensors/motion.py', 'topic'): _speech_topic,
    ('sensors/guide.py', 'prompt_topic'): lambda: {('/sensorTest/prompt', 'std_msgs/String')},
    ('sensors/guide.py', 'speech_topic'): _speech_topic,
    ('node.py', 'key'): _option_params,
    ('node.py', 'other'): lambda: {('/sensorTest/<param>', None)},
    ('emulator/publishers.py', 'topic'): _emulator_topics,
    ('emulator/node.py', 'topic'): _speech_topic,
    ('emulator/second_publisher.py', 'topic'): lambda: {('/tf', 'tf2_msgs/TFMessage')},   # tf:second_publisher
    # ROS 2: beside each of naoqi_driver2's camera images (emulator/camera_info.py)
    ('emulator/camera_info.py', 'info_topic(image_topic)'):
        lambda: {('/camera/%s/camera_info' % c, 'sensor_msgs/CameraInfo')
                 for c in ('front', 'bottom', 'depth', 'stereo', 'ir')},
    ('emulator/tf_publisher.py', "static_topic(self.spec) or '/tf_static'"):
        lambda: {('/tf_static', 'tf2_msgs/TFMessage')},
    ('emulator/node.py', "'~' + key"): _table_params('emulator.node', 'DEFAULTS'),
    ('audio_bridge/publisher.py', "opts['topic']"):
        lambda: {('/naoqi_driver/audio', 'pepper_interface_tests/AudioCustomMsg')},
    ('audio_bridge/publisher.py', "'~' + name"): _table_params('audio_bridge.publisher', 'DEFAULTS', skip=('token',)),
    # ROS 2 (publisher2.py): --topic, default /audio; the type by --message (AudioBuffer or AudioCustomMsg)
    ('audio_bridge/publisher2.py', 'args.topic'): lambda: {('/audio', None)},
}


@functools.lru_cache(maxsize=None)
def _source(rel: str) -> str:
    with open(os.path.join(SRC, rel), encoding='utf-8') as f:
        return f.read()


def _parse(rel: str) -> ast.Module:
    """The module's tree, the one the codebase gates parsed (one parse of each file per run)."""
    return codebase_files.parse(os.path.join(SRC, rel))


def _text(rel: str, node: ast.AST) -> str:
    """An expression as written in the module (ast.unparse is Python 3.9+)."""
    return ast.get_source_segment(_source(rel), node) or ''


def _constants(rel: str) -> Dict[str, object]:
    """Module-level NAME = literal (a string, or a dict of strings) of a module, and the names it
    imports from the package's other modules, resolved there."""
    out: Dict[str, object] = {}
    tree = _parse(rel)
    for node in tree.body:
        if isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name):
            try:
                out[node.targets[0].id] = ast.literal_eval(node.value)
            except ValueError:
                pass
        elif isinstance(node, ast.ImportFrom) and node.level == 1 and node.module:
            other = node.module.replace('.', '/') + '.py'
            other = os.path.join(os.path.dirname(rel), other)
            if os.path.exists(os.path.join(SRC, other)):
                theirs = _constants(other)
                out.update({a.asname or a.name: theirs[a.name] for a in node.names if a.name in theirs})
    return out


def _msg_imports(tree: ast.Module) -> Dict[str, str]:
    """{name: 'pkg/Type'} for every `from pkg.msg import Type` anywhere in the module."""
    return {a.asname or a.name: '%s/%s' % (n.module[:-4], a.name) for n in ast.walk(tree)
            if isinstance(n, ast.ImportFrom) and n.module and n.module.endswith('.msg') for a in n.names}


@functools.lru_cache(maxsize=None)
def ros_calls(rel: str) -> List[Tuple[str, str, Set[Tuple[str, Optional[str]]]]]:
    """(what, 'file:line', {(name, type)}) for each ROS call of a module: what is 'published',
    'subscribed', 'services' or 'param'."""
    tree = _parse(rel)
    consts, msgs = _constants(rel), _msg_imports(tree)
    out = []
    for n in ast.walk(tree):
        if isinstance(n, ast.ImportFrom) and n.module == 'diagnostic_updater':
            out.append(('published', '%s:%d' % (rel, n.lineno), {('/diagnostics', 'diagnostic_msgs/DiagnosticArray')}))
        if not (isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute) and isinstance(n.func.value, ast.Name)
                and n.func.value.id in ('rospy', 'rosapi') and n.args) or rel in SEAM:
            continue
        call = n.func.attr
        seam = n.func.value.id == 'rosapi'
        if seam and call not in SEAM_CALLS or not seam and call not in TOPIC_CALLS and call not in PARAM_CALLS:
            continue
        what = SEAM_CALLS[call] if seam else TOPIC_CALLS.get(call, 'param')
        arg = n.args[0]
        name = None
        if isinstance(arg, ast.Constant) and isinstance(arg.value, str):
            name = arg.value
        elif isinstance(arg, ast.Name) and isinstance(consts.get(arg.id), str):
            name = consts[arg.id]                                               # type: ignore[assignment]
        elif (isinstance(arg, ast.Subscript) and isinstance(arg.value, ast.Name)
              and isinstance(consts.get(arg.value.id), dict)):
            key = ast.literal_eval(arg.slice if not isinstance(arg.slice, ast.Index) else arg.slice.value)  # type: ignore[attr-defined]
            name = consts[arg.value.id][key]                                    # type: ignore[index]
        where = '%s:%d' % (rel, n.lineno)
        if name is not None:
            type_arg = n.args[1] if len(n.args) > 1 and what != 'param' else None
            msg = msgs.get(type_arg.id) if isinstance(type_arg, ast.Name) else None
            if seam and isinstance(type_arg, ast.Constant) and isinstance(type_arg.value, str):
                msg = type_arg.value
            out.append((what, where, {(name, msg)}))
        else:
            key2 = (rel, _text(rel, arg))
            assert key2 in DYNAMIC, ('%s: rospy.%s(%s, ...) computes its %s: add it to DYNAMIC in %s and list '
                                     'what it can be in docs/node-api.md' % (where, call, key2[1],
                                                                              'param' if what == 'param' else 'topic',
                                                                              os.path.relpath(__file__, ROOT)))
            out.append((what, where, DYNAMIC[key2]()))
    return out


def page_entries(text: str) -> Dict[str, Dict[str, Dict[str, Optional[str]]]]:
    """{node: {'subscribed'|'published'|'services'|'param'|'command': {name: type or None}}}: the
    list items '- `name` (`pkg/Type`) ...' under each '## node' and its '### ...' headings."""
    out: Dict[str, Dict[str, Dict[str, Optional[str]]]] = {}
    node = section = None
    kinds = {'subscribed topics': 'subscribed', 'published topics': 'published', 'services': 'services',
             'parameters': 'param', 'command line': 'command'}
    for line in text.splitlines():
        m = re.match(r'## `?(\w+)`?\s*$', line)
        if m:
            node, section = m.group(1), None
            out[node] = {k: {} for k in kinds.values()}
            continue
        m = re.match(r'### (.+?)\s*$', line)
        if m:
            section = kinds.get(m.group(1).lower())
            continue
        m = re.match(r'- `([^`]+)`(?: \(`([\w/]+)`)?', line)
        if m and node and section:
            out[node][section][m.group(1)] = m.group(2)
    return out


def read_page() -> Dict[str, Dict[str, Dict[str, Optional[str]]]]:
    with open(PAGE, encoding='utf-8') as f:
        return page_entries(f.read())


def code_entries(node: str) -> Dict[str, Dict[str, Set[Optional[str]]]]:
    """{'subscribed'|'published'|'services'|'param': {name: {types the code names}}} of one node."""
    out: Dict[str, Dict[str, Set[Optional[str]]]] = {'subscribed': {}, 'published': {}, 'services': {}, 'param': {}}
    for rel in OWNERS[node]:
        for what, _, found in ros_calls(rel):
            for name, msg in found:
                out[what].setdefault(name, set()).add(msg)
    return out


def stale(node: str, page: Dict[str, Dict[str, Dict[str, Optional[str]]]]) -> List[str]:
    """What the page lacks, has wrong, or has that the code no longer does, for one node."""
    if node not in page:
        return ['no "## %s" section' % node]
    problems = []
    for what, found in code_entries(node).items():
        listed = page[node][what]
        for name in sorted(set(found) - set(listed)):
            problems.append('%s: %s %s is not listed' % (node, what, name))
        for name in sorted(set(listed) - set(found)):
            problems.append('%s: %s %s is listed but the code no longer has it' % (node, what, name))
        for name in sorted(set(found) & set(listed)):
            named = found[name] - {None}
            if what != 'param' and named and listed[name] not in named:
                problems.append('%s: %s %s is listed as %s, the code uses %s'
                                % (node, what, name, listed[name], ' or '.join(sorted(named))))
    return problems


def long_options(rel: str) -> Set[str]:
    """The long options and subcommands a module's parser declares by literal."""
    out = set()
    for n in ast.walk(_parse(rel)):
        if isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute) and n.args:
            first = n.args[0]
            if not (isinstance(first, ast.Constant) and isinstance(first.value, str)):
                continue
            if n.func.attr == 'add_argument' and first.value.startswith('--'):
                out.add(first.value)
            elif n.func.attr == 'add_parser':
                out.add(first.value)
    if rel == 'plan/options.py':
        from pepper_interface_tests.plan.options import OPTIONS
        out |= {o.flag for o in OPTIONS}
    return out


def installed_programs() -> List[str]:
    with open(os.path.join(ROOT, 'CMakeLists.txt'), encoding='utf-8') as f:
        return re.findall(r'^\s*scripts/(\w+)', f.read(), re.M)


@pytest.mark.parametrize('node', sorted(OWNERS))
def test_the_page_lists_every_topic_and_param_of_the_node(node):
    assert stale(node, read_page()) == []


def test_every_module_that_talks_to_ros_has_an_owner():
    owned = {rel for mods in OWNERS.values() for rel in mods}
    unowned = []
    for root, _, files in os.walk(SRC):
        for fn in files:
            rel = os.path.relpath(os.path.join(root, fn), SRC)
            if not fn.endswith('.py') or rel in owned:
                continue
            with open(os.path.join(root, fn), encoding='utf-8') as f:
                text = f.read()
            if ('rospy.' in text or 'rosapi.' in text or 'diagnostic_updater' in text) and ros_calls(rel):
                unowned.append(rel)
    assert unowned == [], 'say in OWNERS which node runs these, and list their topics in docs/node-api.md'
    for rel in owned:
        assert ros_calls(rel), '%s makes no ROS call any more: take it out of OWNERS' % rel
    assert not set(DYNAMIC) - {(rel, _text(rel, n.args[0])) for rel in owned for n in ast.walk(_parse(rel))
                                 if isinstance(n, ast.Call) and n.args}, 'a DYNAMIC call is gone'


def test_every_installed_program_has_a_section_with_its_command_line():
    page = read_page()
    with open(PAGE, encoding='utf-8') as f:
        text = f.read()
    for program in installed_programs():
        assert program in page, 'docs/node-api.md has no "## %s" section' % program
    for program, modules in COMMAND_LINES.items():
        section = text.split('\n## %s\n' % program, 1)[1].split('\n## ', 1)[0]
        missing = sorted(o for rel in modules for o in long_options(rel) if '`%s' % o not in section)
        assert missing == [], '%s: docs/node-api.md does not name %s' % (program, ', '.join(missing))


def test_a_stale_page_is_caught():
    """What the tests above rely on: a topic dropped from the page, one the code no longer
    publishes, a wrong type and a param gone are each named."""
    with open(PAGE, encoding='utf-8') as f:
        text = f.read()
    assert stale('sensorTest', page_entries(text)) == []
    broken = (text.replace('- `/sensorTest/prompt` (', '- `/sensorTest/asked` (')
                  .replace('- `/naoqi_driver/laser` (`sensor_msgs/LaserScan`)',
                           '- `/naoqi_driver/laser` (`sensor_msgs/Range`)')
                  .replace('- `~duration` (', '- `~length` ('))
    assert stale('sensorTest', page_entries(broken)) == [
        'sensorTest: subscribed /naoqi_driver/laser is listed as sensor_msgs/Range, '
        'the code uses sensor_msgs/LaserScan',
        'sensorTest: published /sensorTest/prompt is not listed',
        'sensorTest: published /sensorTest/asked is listed but the code no longer has it',
        'sensorTest: param ~duration is not listed',
        'sensorTest: param ~length is listed but the code no longer has it']
