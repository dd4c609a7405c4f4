"""The package's source files, parsed: what the codebase gates (test_codebase.py) and the family
registry's tests (sensors/test_families.py) walk."""
import ast
import functools
import os

PACKAGE = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
                       'src', 'pepper_interface_tests')


def source_files():
    for folder, dirs, files in os.walk(PACKAGE):
        dirs[:] = sorted(d for d in dirs if d != '__pycache__')
        for f in sorted(files):
            if f.endswith('.py'):
                path = os.path.join(folder, f)
                yield os.path.relpath(path, PACKAGE).replace(os.sep, '/'), path


@functools.lru_cache(maxsize=None)
def parse(path):
    """The module's tree, read once for every gate (the trees are not changed)."""
    with open(path, encoding='utf-8') as f:
        return ast.parse(f.read(), path, type_comments=True)
