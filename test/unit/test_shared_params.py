"""The one-process layer's process-wide params reach every role that reads them.

blind_navigation.launch's one-process node sets a few params once for the whole
process (``~straight_rate``, ``~standstill_time``): several roles read them, and
they must agree. A hosted role reads its own ``~<role>/name`` unless it lists the
name in ``shared=`` (ros/layer.Layer.params); a role that forgets would silently
keep its default while the launch arg changes the others. Checked here from the
launch file and the role modules as text (no master, no rospy).
"""
import ast
import importlib.util
import os
import xml.etree.ElementTree as ElementTree

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
SPEC = importlib.util.spec_from_file_location('param_table', os.path.join(REPO, 'scripts', 'param_table.py'))
param_table = importlib.util.module_from_spec(SPEC)
SPEC.loader.exec_module(param_table)

#: The one-process node's own params (nodes/blind_navigation_node.py), not a role's.
NODE_PARAMS = {'recorder', 'auto_detect', 'correct_heading'}


def process_wide_params():
    """Names the one-process node of blind_navigation.launch sets without a role prefix."""
    root = ElementTree.parse(os.path.join(REPO, 'launch', 'blind_navigation.launch')).getroot()
    node = next(n for n in root.iter('node') if n.get('type') == 'blind_navigation_node.py')
    return {p.get('name') for p in node.iter('param') if '/' not in p.get('name')} - NODE_PARAMS


def shared_names(module):
    """The names a role module passes as ``shared=`` to Layer.params."""
    path = os.path.join(REPO, 'blind_navigation', 'ros', module + '.py')
    tree = ast.parse(open(path).read(), path)
    names = set()
    for call in (n for n in ast.walk(tree) if isinstance(n, ast.Call)):
        for keyword in call.keywords:
            if keyword.arg == 'shared':
                names.update(ast.literal_eval(keyword.value))
    return names


def test_the_launch_sets_process_wide_params():
    assert process_wide_params() >= {'straight_rate', 'standstill_time'}, process_wide_params()


def test_every_role_reading_a_process_wide_param_declares_it_shared():
    missing = []
    for role, module, class_name in param_table.ROLES:
        defaults = param_table.role_defaults(module, class_name)[0]
        for name in process_wide_params() & set(defaults):
            if name not in shared_names(module):
                missing.append('%s reads %s but not as shared (ros/%s.py)' % (role, name, module))
    assert not missing, missing
