"""The product (core/, ros/, nodes/, names.py) uses only rospy's public API and no
interpreter tricks, and its modules import each other without a circle (issue 30,
items 3 and 4). Each check is also run on a sample that must fail it."""
import io
import os
import re
import tokenize

import pytest

from test_layers import imports_in
from test_sizes import PACKAGE, product_files, read

#: What the product must not contain (in code: comments and strings are not read).
FORBIDDEN = {
    'rospy.core': r'\brospy\s*\.\s*core\b|\bfrom\s+rospy\s+import\s+core\b',
    'rospy.impl': r'\brospy\s*\.\s*impl\b|\bfrom\s+rospy\s+import\s+impl\b',
    '_shutdown_threads': r'\b_shutdown_threads\b',
    'RegManager': r'\bRegManager\b',
    'get_param_server_cache': r'\bget_param_server_cache\b',
    'sys.modules[...] =': r'\bsys\s*\.\s*modules\s*\[[^\]]*\]\s*=(?!=)',
    'sys.modules.setdefault': r'\bsys\s*\.\s*modules\s*\.\s*setdefault\b',
    'del sys.modules[...]': r'\bdel\s+sys\s*\.\s*modules\b',
}


def code_only(source):
    """``source`` without its comments and string literals, one line per logical line."""
    kept, line = [], []
    skip = (tokenize.COMMENT, tokenize.STRING, tokenize.NL, tokenize.INDENT, tokenize.DEDENT)
    for token in tokenize.generate_tokens(io.StringIO(source).readline):
        if token.type == tokenize.NEWLINE:
            kept.append(' '.join(line))
            line = []
        elif token.type not in skip:
            line.append(token.string)
    return '\n'.join(kept + [' '.join(line)])


def forbidden_in(source):
    """The names of :data:`FORBIDDEN` found in ``source``'s code."""
    code = code_only(source)
    return sorted(name for name, pattern in FORBIDDEN.items() if re.search(pattern, code))


def module_name(relative):
    """'ros/common.py' -> 'blind_navigation.ros.common' (a package: its __init__'s name)."""
    parts = relative[:-len('.py')].split('/')
    return '.'.join(['blind_navigation'] + (parts[:-1] if parts[-1] == '__init__' else parts))


def imported(module, source, modules):
    """The modules of ``modules`` (names) that ``source`` of ``module`` imports, anywhere in it."""
    package = module if module + '.__init__' in modules else module.rpartition('.')[0]
    return {name for name in imports_in(source, package) if name in modules and name != module}


def import_graph(sources):
    """{module: modules it imports} of ``sources`` ({relative path: text})."""
    names = {module_name(relative): relative for relative in sources}
    modules = set(names) | {name + '.__init__' for name, rel in names.items()
                            if rel.endswith('__init__.py')}
    return {name: imported(name, sources[rel], modules) for name, rel in names.items()}


def circles(graph):
    """The import circles of ``graph``: each a sorted list of the modules in one."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []

    def visit(node):        # Tarjan's strongly connected components
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for other in graph.get(node, ()):
            if other not in index:
                visit(other)
                low[node] = min(low[node], low[other])
            elif other in on_stack:
                low[node] = min(low[node], index[other])
        if low[node] == index[node]:
            component = []
            while True:
                other = stack.pop()
                on_stack.discard(other)
                component.append(other)
                if other == node:
                    break
            if len(component) > 1:
                found.append(sorted(component))
    for node in sorted(graph):
        if node not in index:
            visit(node)
    return found


@pytest.mark.parametrize('relative', product_files())
def test_no_private_rospy_api_nor_interpreter_trick(relative):
    assert forbidden_in(read(relative)) == [], relative


def test_the_private_api_check_finds_what_the_product_had():
    old = ('from rospy.impl.paramserver import get_param_server_cache\n'
           'rospy.on_shutdown(lambda: rospy.core._shutdown_threads.clear())\n'
           'from rospy.impl.registration import RegManager\n'
           "sys.modules['numpy'] = None\n"
           "sys.modules.setdefault('numpy', None)\n"
           "del sys.modules['numpy']\n"
           'x = rospy.core.is_shutdown_requested()  # in code\n')
    assert forbidden_in(old) == sorted(FORBIDDEN)
    said = '"""rospy.core._shutdown_threads, RegManager"""\n# sys.modules["x"] = None\n'
    assert forbidden_in(said + "ok = sys.modules['numpy'] == None\n") == []


def test_no_import_circle_in_the_product():
    sources = {relative: read(relative) for relative in product_files()}
    assert circles(import_graph(sources)) == []


def test_the_circle_check_finds_the_circle_the_product_had():
    sources = {'ros/common.py': 'from . import subscription_watchdog, wiring\n',
               'ros/subscription_watchdog.py': 'from . import wiring\n',
               'ros/wiring.py': 'import rospy\nfrom . import faults\n',
               'ros/faults.py': 'from . import common, diagnostics as diag\n',
               'ros/diagnostics.py': 'from .clock import every\n', 'ros/clock.py': '',
               'core/a.py': 'def f():\n    from blind_navigation.core.b import g\n',
               'core/b.py': 'from ..core import a\n'}
    assert circles(import_graph(sources)) == [
        ['blind_navigation.core.a', 'blind_navigation.core.b'],
        ['blind_navigation.ros.common', 'blind_navigation.ros.faults',
         'blind_navigation.ros.subscription_watchdog', 'blind_navigation.ros.wiring']]


def test_the_graph_reads_the_product():
    graph = import_graph({relative: read(relative) for relative in product_files()})
    assert 'blind_navigation.ros.faults' in graph['blind_navigation.ros.common']
    assert os.path.isdir(PACKAGE)
