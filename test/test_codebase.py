"""Unit: gates on the package's source read with `ast` (nothing is imported or run).

- Typed API: every public function (name not starting with `_`, at module level or in a class
  whose name does not start with `_`; `__init__` too) has an annotation on each parameter but
  self/cls and a return annotation (`__init__` may leave `-> None` out when a parameter is
  annotated, as mypy does), or a signature type comment (`# type: (int) -> str`) in the Python
  2.7-compatible files. Each offender is named as file:line:function and what it lacks.
- Layering: nothing imports "upward" along
  plan -> sources -> rosapi -> media -> motion -> sensors -> runner -> outputs -> programs
  (rosapi.py, the ROS seam, is built on sources/live2 and ros2wire, so it sits above
  sources: a source that needs a subscription is handed one); results.py, stats.py,
  interrupts.py and progress.py are the base every layer may import; observer.py (the seam
  the runner calls the outputs through) is in the runner's layer. Every import counts:
  function-level ones (they run too) and those under `if TYPE_CHECKING:` (a type a lower
  stage needs from a higher one belongs below both: a protocol or a value type in a leaf).
- No import circle: among the package's modules, no chain of imports (of any kind, as above)
  leads from a module back to itself; each circle found is named, module by module.
"""
import ast
from typing import Set

from codebase_files import parse, source_files

# Not held to the typed-API rule, forever: the capture side runs on the robot's Python 2.7 and
# mypy does not check it (pyproject.toml).
NEVER_TYPED = {'audio_bridge/capture.py'}

# Not held to it YET (a file, or a folder ending in '/', being annotated on another branch);
# empty since issue 13 typed the last four modules: every module but NEVER_TYPED is held to it.
NOT_YET_TYPED: Set[str] = set()

# Layers along the data's path: a module may import its own layer, a lower one and the base.
BASE = {'results', 'stats', 'interrupts', 'progress', 'codec',
        'msg'}    # pepper_interface_tests.msg: the generated message classes (msg/*.msg)
LAYERS = [
    {'plan'},
    {'sources'},
    {'rosapi', 'genmsgs'},   # the ROS seam for publishers and subscriptions (rospy or rclpy), on sources/live2
    {'media'},
    {'motion'},     # the motion check's home (--move): below sensors/, whose motion Check drives it
    {'sensors'},
    {'runner', 'observer'},
    {'outputs'},
    {'cli', 'ros2run', 'history_cli', 'node', 'launch', 'emulator', 'audio_bridge', 'rosmaster'},
]


def exempt(rel):
    return rel in NEVER_TYPED or any(rel == e or (e.endswith('/') and rel.startswith(e))
                                     for e in NOT_YET_TYPED)


# ------------------------------------------------------------------------- typed API

def public_functions(body, in_class=False):
    """(function node, in_class) for the public API in a module or class body: functions,
    methods of public classes (nested ones too), through if/try/with blocks; not the functions
    defined inside a function."""
    for node in body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            if not node.name.startswith('_') or node.name == '__init__':
                yield node, in_class
        elif isinstance(node, ast.ClassDef):
            if not node.name.startswith('_'):
                yield from public_functions(node.body, True)
        else:
            for field in ('body', 'orelse', 'finalbody', 'handlers'):
                yield from public_functions(getattr(node, field, None) or [], in_class)


def missing_annotations(fn, in_class):
    """What `fn`'s signature lacks, as words; [] when it is fully annotated."""
    if fn.type_comment:        # `# type: (...) -> ...`: mypy checks it against the parameters
        return []
    a = fn.args
    params = list(getattr(a, 'posonlyargs', [])) + list(a.args)
    decorators = {d.id for d in fn.decorator_list if isinstance(d, ast.Name)}
    if in_class and 'staticmethod' not in decorators and params:
        params = params[1:]                                  # self / cls
    params += list(a.kwonlyargs)
    names = [p.arg for p in params]
    params += [a.vararg] if a.vararg else []
    params += [a.kwarg] if a.kwarg else []
    names += ['*' + a.vararg.arg] if a.vararg else []
    names += ['**' + a.kwarg.arg] if a.kwarg else []
    lacks = [n for n, p in zip(names, params) if p.annotation is None]
    some_annotated = len(lacks) < len(params)
    if fn.returns is None and not (fn.name == '__init__' and some_annotated):
        lacks.append('return')
    return lacks


def test_missing_annotations_sees_each_kind_of_parameter():
    """The checker itself: each unannotated kind of parameter is named, self/cls are not."""
    def lacks(src, in_class=False):
        return missing_annotations(ast.parse(src, type_comments=True).body[0], in_class)
    assert lacks('def f(a: int, *, b: str = "", **kw: int) -> None: pass') == []
    assert lacks('def f(a, b: int, *args, c, **kw): pass') == ['a', 'c', '*args', '**kw', 'return']
    assert lacks('def f(self, a: int) -> int: pass', in_class=True) == []
    assert lacks('def f(self, a: int): pass', in_class=True) == ['return']
    assert lacks('@staticmethod\ndef f(a): pass', in_class=True) == ['a', 'return']
    assert lacks('def __init__(self, a: int): pass', in_class=True) == []
    assert lacks('def __init__(self): pass', in_class=True) == ['return']
    assert lacks('def __init__(self) -> None: pass', in_class=True) == []
    assert lacks('def f(a, b):\n    # type: (int, str) -> None\n    pass') == []


def test_public_functions_skip_private_names_and_nested_functions():
    src = ('def a(): pass\n'
           'def _b(): pass\n'
           'class C:\n    def __init__(self): pass\n    def m(self): pass\n    def _p(self): pass\n'
           '    def __len__(self): pass\n'
           'class _D:\n    def m(self): pass\n'
           'if True:\n    def e():\n        def inner(): pass\n')
    names = [fn.name for fn, _ in public_functions(ast.parse(src).body)]
    assert names == ['a', '__init__', 'm', 'e']


def test_public_functions_are_fully_annotated():
    """Every public function outside the listed files has full annotations (issue 13)."""
    offenders = []
    for rel, path in source_files():
        if exempt(rel):
            continue
        for fn, in_class in public_functions(parse(path).body):
            lacks = missing_annotations(fn, in_class)
            if lacks:
                offenders.append('%s:%d:%s lacks annotations for %s'
                                 % (rel, fn.lineno, fn.name, ', '.join(lacks)))
    assert not offenders, ('public functions without full type hints (annotate them; Python 2.7 '
                           'files take a `# type: (...) -> ...` comment):\n' + '\n'.join(offenders))


def test_the_not_yet_typed_list_names_existing_files():
    """A renamed or removed file must leave the list, or the list would exempt nothing."""
    rels = [rel for rel, _ in source_files()]
    for e in NOT_YET_TYPED | NEVER_TYPED:
        assert any(rel == e or (e.endswith('/') and rel.startswith(e)) for rel in rels), e


# ------------------------------------------------------------------------- layering

def layer_of(top):
    """The rank of a top-level module or folder of the package; -1 for the base."""
    if top in BASE:
        return -1
    for rank, names in enumerate(LAYERS):
        if top in names:
            return rank
    raise AssertionError('%s is in no layer: add it to LAYERS or BASE in test_codebase.py' % top)


def is_type_checking(test):
    return (isinstance(test, ast.Name) and test.id == 'TYPE_CHECKING'
            or isinstance(test, ast.Attribute) and test.attr == 'TYPE_CHECKING')


def every_import(tree):
    """Every import statement, at any depth (functions, classes, try, with, and under
    `if TYPE_CHECKING:`). Only statements are visited: an import is one."""
    found = []
    stack = list(tree.body)
    while stack:
        node = stack.pop()
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            found.append(node)
            continue
        for field in ('body', 'orelse', 'finalbody', 'handlers', 'cases'):
            stack.extend(getattr(node, field, None) or [])
    return sorted(found, key=lambda n: n.lineno)


def imported_tops(rel, node):
    """Top-level package names (results, plan, outputs, ...) an import node refers to."""
    parts = rel[:-len('.py')].split('/')
    package = parts[:-1]         # the importing module's package, relative to ours
    if isinstance(node, ast.Import):
        return [a.name.split('.')[1] for a in node.names
                if a.name.startswith('pepper_interface_tests.')]
    if node.level == 0:
        if node.module == 'pepper_interface_tests':
            return [a.name for a in node.names]
        if node.module and node.module.startswith('pepper_interface_tests.'):
            return [node.module.split('.')[1]]
        return []
    base = package[:len(package) - (node.level - 1)] if node.level > 1 else package
    target = base + (node.module.split('.') if node.module else [])
    if target:
        return [target[0]]
    return [a.name for a in node.names]       # `from . import x` in the package root


def import_text(node):
    """The import statement as written (ast.unparse is Python 3.9+)."""
    names = ', '.join(a.name + (' as ' + a.asname if a.asname else '') for a in node.names)
    if isinstance(node, ast.Import):
        return 'import ' + names
    return 'from %s%s import %s' % ('.' * node.level, node.module or '', names)


def upward_in(rel, tree):
    """The upward imports of one module (`rel` its path in the package, `tree` its ast), each
    named as file:line, the statement, and where it sits when inside a function."""
    top = rel.split('/')[0]
    if top.endswith('.py'):
        top = top[:-len('.py')]
    if top == '__init__':
        return []
    own = layer_of(top)
    found = []
    inside = enclosing_functions(tree)
    for node in every_import(tree):
        for target in imported_tops(rel, node):
            if target != top and layer_of(target) > own:
                where = ' (inside %s())' % inside[node] if node in inside else ''
                found.append('%s:%d `%s`%s imports %s, a later stage than %s (plan -> sources -> rosapi -> '
                             'media -> motion -> sensors -> runner -> outputs -> programs); move the shared '
                             'part down, or have the caller hand it in (TYPE_CHECKING and function-level '
                             'imports count too)' % (rel, node.lineno, import_text(node), where, target, top))
    return found


def enclosing_functions(tree):
    """{import node: the name of the innermost function it sits in}."""
    out = {}
    for fn in ast.walk(tree):
        if isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
            for node in ast.walk(fn):
                if isinstance(node, (ast.Import, ast.ImportFrom)):
                    out[node] = fn.name      # ast.walk is breadth-first: the innermost comes last
    return out


def upward_imports():
    found = []
    for rel, path in source_files():
        found.extend(upward_in(rel, parse(path)))
    return found


def test_imported_tops_resolves_relative_and_absolute_imports():
    def tops(rel, src):
        return imported_tops(rel, ast.parse(src).body[0])
    assert tops('outputs/report/page.py', 'from ...sensors import base') == ['sensors']
    assert tops('outputs/report/page.py', 'from .values import x') == ['outputs']
    assert tops('observer.py', 'from .runner import SensorRun') == ['runner']
    assert tops('observer.py', 'from . import results') == ['results']
    assert tops('emulator/node.py', 'import pepper_interface_tests.outputs.files') == ['outputs']
    assert tops('emulator/node.py', 'from pepper_interface_tests import cli') == ['cli']
    assert tops('emulator/node.py', 'import rospy') == []
    assert import_text(ast.parse('from ..outputs import files as f, diagnostics').body[0]) == \
        'from ..outputs import files as f, diagnostics'


def test_type_checking_and_function_level_imports_count():
    tree = ast.parse('from typing import TYPE_CHECKING\n'
                     'if TYPE_CHECKING:\n    from ..runner import SensorRun\n'
                     'def f():\n    from ..outputs import files\n')
    modules = [n.module for n in every_import(tree)]
    assert modules == ['typing', 'runner', 'outputs']


def test_an_upward_import_inside_a_function_is_named():
    """An import that runs only when a function is called still counts (issue 45: sources/
    identity.py imported rosapi inside read_live2)."""
    src = ('import threading\n'
           'from .naoqi_msgs import X\n'
           'def read_live2(graph):\n'
           '    try:\n'
           '        from .. import rosapi\n'
           '    except ImportError:\n'
           '        pass\n')
    found = upward_in('sources/identity.py', ast.parse(src))
    assert len(found) == 1, found
    assert found[0].startswith('sources/identity.py:5 `from .. import rosapi` (inside read_live2()) imports '
                               'rosapi, a later stage than sources')
    assert upward_in('rosapi.py', ast.parse('def f():\n    from .sources import live2\n')) == []


def test_nothing_imports_upward():
    found = upward_imports()
    assert not found, 'upward imports:\n' + '\n'.join(found)


# ------------------------------------------------------------------------- import circles

def module_name(rel):
    """'outputs/report/page.py' -> 'outputs.report.page'; a package is its '__init__'."""
    return rel[:-len('.py')].replace('/', '.')


def imported_modules(rel, node, modules):
    """The package's modules an import node names (a name that is a module, else the module or
    package it is taken from), among `modules` (module_name of every file)."""
    def known(dotted):
        if dotted in modules:
            return dotted
        return dotted + '.__init__' if dotted + '.__init__' in modules else None
    parts = rel[:-len('.py')].split('/')
    if isinstance(node, ast.Import):
        return [m for m in (known(a.name.split('.', 1)[1]) for a in node.names
                            if a.name.startswith('pepper_interface_tests.')) if m]
    if node.level == 0:
        if not (node.module or '').startswith('pepper_interface_tests'):
            return []
        base = node.module.split('.')[1:]
    else:
        base = parts[:-1][:len(parts) - node.level] if node.level > 1 else parts[:-1]
        base = base + (node.module.split('.') if node.module else [])
    out = []
    for a in node.names:
        m = known('.'.join(base + [a.name])) or known('.'.join(base))
        if m:
            out.append(m)
    return out


def import_graph():
    files = dict((module_name(rel), (rel, path)) for rel, path in source_files())
    graph = {}
    for name, (rel, path) in files.items():
        graph[name] = sorted({m for node in every_import(parse(path))
                              for m in imported_modules(rel, node, files) if m != name})
    return graph


def circles(graph):
    """Each set of modules that import one another in a circle (Tarjan's strongly connected
    components of more than one module), as a sorted list."""
    index, low, stack, on, found, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def test_circles_finds_a_circle_and_nothing_else():
    assert circles({'a': ['b'], 'b': ['c'], 'c': ['a'], 'd': ['a']}) == [['a', 'b', 'c']]
    assert circles({'a': ['b'], 'b': []}) == []


def test_imported_modules_resolves_packages_and_names():
    modules = {'sensors.__init__', 'sensors.base', 'plan.model', 'observer'}
    def mods(rel, src):
        return imported_modules(rel, ast.parse(src).body[0], modules)
    assert mods('sensors/window.py', 'from .base import Check') == ['sensors.base']
    assert mods('sensors/window.py', 'from . import base') == ['sensors.base']
    assert mods('outputs/terminal.py', 'from ..observer import RunObserver') == ['observer']
    assert mods('outputs/report/page.py', 'from ...sensors import families') == ['sensors.__init__']
    assert mods('cli.py', 'from .plan.model import TestPlan') == ['plan.model']


def test_no_import_circle():
    found = circles(import_graph())
    assert not found, ('modules that import one another in a circle (move the shared type into a '
                       'leaf module both can import):\n' + '\n'.join(' -> '.join(c) for c in found))
