"""The house's import rules (docs/DESIGN.md), read from the code's own imports:

- the product (core/, ros/, nodes/, names.py) never imports the simulator
  (sim/) or the evaluation (evaluation/);
- core/ imports no ROS module (rospy, genpy, messages, actionlib, ...);
- a node executable (nodes/, sim/nodes/, evaluation/nodes/) never imports
  another node executable.
"""
import ast
import os

import pytest

PACKAGE = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..', 'blind_navigation'))
#: Modules that only exist as ROS packages: core/ must not import them.
ROS_MODULES = ('rospy', 'rosgraph', 'genpy', 'roslib', 'rospkg', 'actionlib', 'actionlib_msgs',
               'std_msgs', 'geometry_msgs', 'nav_msgs', 'sensor_msgs', 'diagnostic_updater',
               'diagnostic_msgs', 'tf', 'tf2_ros', 'rosbag', 'blind_navigation.msg',
               'blind_navigation.srv')
NODE_DIRS = ('nodes', os.path.join('sim', 'nodes'), os.path.join('evaluation', 'nodes'))


def python_files(*parts):
    top = os.path.join(PACKAGE, *parts)
    if top.endswith('.py'):
        return [top]
    return sorted(os.path.join(root, name) for root, _, names in os.walk(top)
                  for name in names if name.endswith('.py'))


def module_name(path):
    relative = os.path.relpath(path, os.path.dirname(PACKAGE))[:-len('.py')]
    return relative.replace(os.sep, '.').replace('.__init__', '')


def imports(path, package=None):
    """Absolute names of the modules ``path`` imports (relative imports resolved in
    ``package``, by default the file's own)."""
    if package is None:
        package = module_name(path).rsplit('.', 1)[0] if not path.endswith('__init__.py') \
            else module_name(path)
    return imports_in(open(path).read(), package)


def imports_in(source, package):
    """Absolute names of the modules ``source`` imports, anywhere in it (relative imports
    resolved in ``package``)."""
    found = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ''
            if node.level:
                parent = package.split('.')
                parent = parent[:len(parent) - node.level + 1]
                base = '.'.join(parent + ([base] if base else []))
            found.add(base)
            found.update('%s.%s' % (base, alias.name) for alias in node.names)
    return found


def forbidden_imports(path, forbidden, package=None):
    return sorted(name for name in imports(path, package)
                  if any(name == f or name.startswith(f + '.') for f in forbidden))


def offending(paths, forbidden):
    """{file: [forbidden modules it imports]} for the ``paths`` that import any."""
    found = {os.path.relpath(path, PACKAGE): forbidden_imports(path, forbidden) for path in paths}
    return {path: names for path, names in found.items() if names}


PRODUCT = python_files('core') + python_files('ros') + python_files('nodes') + \
    python_files('names.py') + python_files('__init__.py')


def test_the_files_are_found():
    assert len(python_files('core')) > 10 and len(python_files('ros')) > 10
    assert any(path.endswith('mission_owner.py') for path in PRODUCT)


def test_the_product_never_imports_the_simulator_or_the_evaluation():
    assert offending(PRODUCT, ('blind_navigation.sim', 'blind_navigation.evaluation')) == {}


def test_core_imports_no_ros_module():
    assert offending(python_files('core'), ROS_MODULES) == {}


@pytest.mark.parametrize('directory', NODE_DIRS)
def test_a_node_never_imports_another_node(directory):
    nodes = [module_name(path) for directory_ in NODE_DIRS for path in python_files(directory_)]
    assert offending(python_files(directory), nodes) == {}


def test_the_check_sees_a_forbidden_import(tmp_path):
    """The rules are not vacuous: a core module importing the simulator and rospy is caught."""
    probe = tmp_path / 'probe.py'
    probe.write_text('from ..sim.kobuki import SimulatedKobuki\nimport rospy\n')
    package = 'blind_navigation.core'
    assert forbidden_imports(str(probe), ('blind_navigation.sim',), package) == [
        'blind_navigation.sim.kobuki', 'blind_navigation.sim.kobuki.SimulatedKobuki']
    assert forbidden_imports(str(probe), ROS_MODULES, package) == ['rospy']
