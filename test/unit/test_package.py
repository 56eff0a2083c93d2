"""The package's metadata against its code: package.xml validates with catkin_pkg
and declares exactly what the layer imports (exec) and what only the simulator,
the evaluation and the tests import (test); CHANGELOG.rst parses as a REP-132
changelog; the launch files honour $ROS_HOME."""
import ast
import importlib.util
import io
import os
import re
import sys
import sysconfig

import docutils.core
import pytest
from catkin_pkg.changelog import get_changelog_from_path
from catkin_pkg.package import parse_package

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
PACKAGE = 'blind_navigation'
#: the product: what a robot that only runs the layer executes
PRODUCT = ('blind_navigation/core', 'blind_navigation/ros', 'blind_navigation/nodes',
           'blind_navigation/names.py', 'blind_navigation/__init__.py')
#: the test rig: simulator, evaluation (demo, bench), unit tests and rostests
RIG = ('blind_navigation/sim', 'blind_navigation/evaluation', 'test')
#: the rosdep key of a Python module whose key is not its own name
PYTHON_KEYS = {'numpy': 'python3-numpy', 'yaml': 'python3-yaml', 'rospkg': 'python3-rospkg',
               'matplotlib': 'python3-matplotlib', 'psutil': 'python3-psutil',
               'pytest': 'python3-pytest', 'catkin_pkg': 'python3-catkin-pkg',
               'hypothesis': 'python3-hypothesis', 'docutils': 'python3-docutils'}
#: declared run dependencies nothing imports, each with its reason
NOT_IMPORTED = {'message_runtime': 'the generated msg/srv/action classes',
                'roslaunch': 'the launch files',
                'yaml-cpp': 'tools/landmark_info.cpp'}
#: rig imports that package.xml cannot declare, each with where it is installed from
NOT_DECLARED = {'mujoco': 'PyPI, pinned, into $BN_WS/venvs/sim by scripts/install_deps.sh '
                          '(the physics base, sim/mujoco_kobuki.py: a test and bench dependency only)'}
#: where the conditions of package.xml are evaluated: Noetic with Python 3
CONDITIONS = {'ROS_PYTHON_VERSION': '3', 'ROS_DISTRO': 'noetic'}


def is_stdlib(module):
    """Built in, frozen, or found in the interpreter's standard library directory
    (sys.stdlib_module_names is Python 3.10+)."""
    if module in sys.builtin_module_names:
        return True
    spec = importlib.util.find_spec(module)
    origin = (spec.origin or '') if spec else ''
    return origin == 'frozen' or (origin.startswith(sysconfig.get_paths()['stdlib'])
                                  and 'packages' not in origin)


def python_files(paths):
    for path in paths:
        path = os.path.join(REPO, path)
        if path.endswith('.py'):
            yield path
        for folder, _, names in os.walk(path):
            yield from (os.path.join(folder, n) for n in sorted(names) if n.endswith('.py'))


def third_party_imports(paths):
    """{top-level module: [file, ...]} of every absolute import that is neither the
    standard library, this package, nor a helper module of test/."""
    found = {}
    local = {os.path.basename(p)[:-3] for p in python_files(['test'])}  # test helpers on sys.path
    for path in python_files(paths):
        tree = ast.parse(open(path).read(), path)
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                modules = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and node.level == 0:
                modules = [node.module]
            else:
                continue
            for module in modules:
                top = module.split('.')[0]
                if top == PACKAGE or top in local or is_stdlib(top):
                    continue
                found.setdefault(top, []).append(os.path.relpath(path, REPO))
    return found


def rosdep_key(module):
    return PYTHON_KEYS.get(module, module)


@pytest.fixture(scope='module')
def package():
    package = parse_package(os.path.join(REPO, 'package.xml'))
    package.evaluate_conditions(CONDITIONS)
    return package


def active(dependencies):
    return {d.name for d in dependencies if d.evaluated_condition}


def test_package_xml_validates(package):
    package.validate()
    assert package.name == PACKAGE


def test_every_import_of_the_layer_is_a_run_dependency(package):
    run = active(package.exec_depends)
    missing = {m: files for m, files in third_party_imports(PRODUCT).items() if rosdep_key(m) not in run}
    assert not missing, 'imported by the layer but not an exec_depend/depend: %s' % missing


def test_every_run_dependency_is_imported_by_the_layer(package):
    imported = {rosdep_key(m) for m in third_party_imports(PRODUCT)}
    unused = active(package.exec_depends) - imported - set(NOT_IMPORTED)
    assert not unused, 'exec_depends the layer never imports: %s' % sorted(unused)


def test_the_rig_needs_only_declared_dependencies(package):
    declared = active(package.exec_depends) | active(package.test_depends)
    missing = {m: files for m, files in third_party_imports(RIG).items()
               if rosdep_key(m) not in declared and m not in NOT_DECLARED}
    assert not missing, 'imported by sim/, evaluation/ or test/ but not declared: %s' % missing


def test_every_test_dependency_is_used_by_the_rig_and_not_by_the_layer(package):
    rig = {rosdep_key(m) for m in third_party_imports(RIG)}
    layer = {rosdep_key(m) for m in third_party_imports(PRODUCT)}
    tests = active(package.test_depends)
    assert not tests - rig, 'test_depends nothing in the rig imports: %s' % sorted(tests - rig)
    assert not tests & layer, 'the layer imports test_depends: %s' % sorted(tests & layer)


def test_changelog_parses_as_rep132_with_the_package_version(package):
    path = os.path.join(REPO, 'CHANGELOG.rst')
    messages = io.StringIO()
    docutils.core.publish_doctree(open(path).read(), settings_overrides={
        'report_level': 1, 'halt_level': 5, 'warning_stream': messages})
    assert messages.getvalue() == '', 'CHANGELOG.rst: %s' % messages.getvalue()
    versions = [version for version, _, _ in get_changelog_from_path(path, PACKAGE).foreach_version()]
    assert versions, 'CHANGELOG.rst: no section titled "X.Y.Z (date)"'
    assert versions[0] == package.version, \
        'CHANGELOG.rst: newest version %s, package.xml %s' % (versions[0], package.version)


def test_launch_files_honour_ros_home():
    """$ROS_HOME as rospkg.get_ros_home() reads it: never $HOME directly (the launch
    would fail without HOME) and no other default than ~/.ros (the nodes expand ~)."""
    wrong = re.compile(r"\$\(env HOME\)|\$\(optenv HOME|env\(\s*['\"]HOME['\"]|optenv ROS_HOME (?!~/\.ros\))")
    offenders = []
    for root, _, names in os.walk(os.path.join(REPO, 'launch')):
        for name in names:
            path = os.path.join(root, name)
            offenders += ['%s:%d' % (os.path.relpath(path, REPO), number)
                          for number, line in enumerate(open(path), 1) if wrong.search(line)]
    assert not offenders, 'not $ROS_HOME (default ~/.ros): %s' % offenders
