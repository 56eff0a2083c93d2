"""The one-process layer's process-wide params reach every role that reads them.

blind_navigation.launch's one-process node sets a few params once for the whole
process (``~straight_rate``, ``~standstill_time``): several roles read them, and
they must agree. A hosted role reads its own ``~<role>/name`` unless its schema
lists the name as shared (core/role_params.py, ros/layer.Layer.params); a role
that forgets would silently keep its default while the launch arg changes the
others. Checked here from the launch file and the schemas (no master, no rospy).
"""
import os
import xml.etree.ElementTree as ElementTree

from blind_navigation.core.role_params import SCHEMAS, SHARED

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))

#: The one-process node's own params (nodes/mission_owner.py), not a role's.
NODE_PARAMS = {'recorder', 'auto_detect', 'correct_heading'}


def process_wide_params():
    """Names the one-process node of blind_navigation.launch sets without a role prefix."""
    root = ElementTree.parse(os.path.join(REPO, 'launch', 'blind_navigation.launch')).getroot()
    node = next(n for n in root.iter('node') if n.get('name') == 'blind_navigation')
    return {p.get('name') for p in node.iter('param') if '/' not in p.get('name')} - NODE_PARAMS


def test_the_launch_sets_process_wide_params():
    assert process_wide_params() >= {'straight_rate', 'standstill_time'}, process_wide_params()


def test_every_role_reading_a_process_wide_param_declares_it_shared():
    assert process_wide_params() <= set(SHARED), process_wide_params()
    missing = ['%s reads %s but not as shared' % (schema.role, param.name)
               for schema in SCHEMAS for param in schema.params
               if param.name in process_wide_params() and param.name not in schema.shared]
    assert not missing, missing
