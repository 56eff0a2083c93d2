"""The launch files' args as `roslaunch --ros-args` lists them: none reads as required
unless it is, a default that stands for a node's default agrees with the role's
schema (core/role_params.py), and every arg a launch file sets a param from is one
of the schema's (no launch arg for a constant)."""
import ast
import glob
import os
import xml.etree.ElementTree as ElementTree

import pytest
import yaml
from roslaunch.arg_dump import get_args
from roslaunch.loader import convert_value

from blind_navigation.core import role_params
from blind_navigation.core.role_params import (BACK_TRAVEL_SERVER, CALIBRATE_GYRO, HEADING_CORRECTION,
                                               LANDMARK_SAVING, SAMPLING_PUBLISHER)
from blind_navigation.ros.common import ros_home_file

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
LAUNCH_FILES = sorted(glob.glob(os.path.join(REPO, 'launch', '*.launch')))

#: (launch file, arg) -> (role schema, param) whose default the arg repeats
NODE_DEFAULTS = {}
for _launch in ('blind_navigation', 'recording', 'bench'):
    NODE_DEFAULTS[(_launch, 'deadband')] = (SAMPLING_PUBLISHER, 'deadband')
for _launch in ('blind_navigation', 'recording'):
    NODE_DEFAULTS[(_launch, 'straight_rate')] = (SAMPLING_PUBLISHER, 'straight_rate')
    NODE_DEFAULTS[(_launch, 'curved_rate')] = (SAMPLING_PUBLISHER, 'curved_rate')
NODE_DEFAULTS.update({
    ('blind_navigation', 'standstill_time'): (HEADING_CORRECTION, 'standstill_time'),
    ('blind_navigation', 'stop_lead'): (BACK_TRAVEL_SERVER, 'stop_lead'),
    ('recording', 'fsync'): (LANDMARK_SAVING, 'fsync'),
    ('recording', 'min_subscribers'): (SAMPLING_PUBLISHER, 'min_subscribers'),
    ('calibrate_gyro', 'turns'): (CALIBRATE_GYRO, 'turns'),
    ('calibrate_gyro', 'max_w'): (CALIBRATE_GYRO, 'max_w'),
})
LANDMARK = ('landmark_saving', 'LANDMARK_FILE')
CALIBRATION = ('heading_correction', 'CALIBRATION_FILE')
#: (launch file, arg) -> (role module, constant): the file under $ROS_HOME the node takes
#: when the param is empty
FILE_DEFAULTS = {('blind_navigation', 'landmark_file'): LANDMARK,
                 ('recording', 'landmark_file'): LANDMARK,
                 ('paper', 'landmark_file'): LANDMARK,
                 ('blind_navigation', 'gyro_calibration_file'): CALIBRATION,
                 ('demo', 'gyro_calibration_file'): CALIBRATION,
                 ('bench', 'gyro_calibration_file'): CALIBRATION,
                 ('cost', 'gyro_calibration_file'): CALIBRATION,
                 ('calibrate_gyro', 'calibration_file'): CALIBRATION}


def name_of(path):
    return os.path.basename(path)[:-len('.launch')]


def declared_without_default(path):
    """The args a user must set: declared with neither a default nor a value."""
    return {tag.get('name') for tag in ElementTree.parse(path).getroot().iter('arg')
            if tag.get('default') is None and tag.get('value') is None}


def module_constant(module, name):
    """A role module's ``NAME = os.path.join(...)``, read as text (the unit tests have
    no built messages to import the role with)."""
    with open(os.path.join(REPO, 'blind_navigation', 'ros', module + '.py')) as stream:
        tree = ast.parse(stream.read())
    for node in tree.body:
        if isinstance(node, ast.Assign) and [t.id for t in node.targets] == [name]:
            return eval(compile(ast.Expression(node.value), module, 'eval'), {'os': os})  # noqa: S307
    raise AssertionError('%s.py has no %s' % (module, name))


def launch_defaults(name):
    """{arg: (doc, default)} as `roslaunch --ros-args` computes it (includes resolved)."""
    return get_args([os.path.join(REPO, 'launch', name + '.launch')])


@pytest.mark.parametrize('path', LAUNCH_FILES, ids=name_of)
def test_only_args_without_default_read_as_required(path):
    listed = {name for name, (_, default) in get_args([path]).items() if not default}
    assert listed == declared_without_default(path), (
        '%s: roslaunch --ros-args lists %s as required (an empty default reads so: give the '
        'real default or a documented sentinel such as none)' % (path, sorted(listed)))


@pytest.mark.parametrize('launch, arg', sorted(NODE_DEFAULTS))
def test_a_numeric_default_is_the_nodes(launch, arg):
    schema, param = NODE_DEFAULTS[(launch, arg)]
    node_default = schema[param].default
    text = launch_defaults(launch)[arg][1]
    value = convert_value(text, 'auto')     # as a <param value="$(arg ...)"> sets it
    assert value == node_default and type(value) is type(node_default), (
        '%s.launch %s default %r differs from the %s schema: %s = %r'
        % (launch, arg, text, schema.role, param, node_default))


@pytest.mark.parametrize('launch, arg', sorted(FILE_DEFAULTS))
@pytest.mark.parametrize('env', ['ROS_HOME', 'HOME'])
def test_a_file_default_is_the_nodes(launch, arg, env, tmp_path, monkeypatch):
    monkeypatch.delenv('ROS_HOME', raising=False)
    monkeypatch.setenv(env, str(tmp_path))
    default = launch_defaults(launch)[arg][1]
    node_file = os.path.abspath(ros_home_file(module_constant(*FILE_DEFAULTS[(launch, arg)])))
    # the node reads the param as abspath(expanduser(param))
    assert os.path.abspath(os.path.expanduser(default)) == node_file, (
        '%s.launch %s default %r is not the file the node uses when it is empty'
        % (launch, arg, default))


#: node type -> the schema of the role it hosts (the one-process node: by ``<role>/`` prefix)
ROLE_NODES = {'%s.py' % (s.role if s.role != 'landmark_saver' else name): s
              for s in role_params.SCHEMAS for name in ('landmark_saver', 'record_server')}
#: params of the one-process node itself (nodes/mission_owner.py, ros/layer.py)
NODE_PARAMS = {'recorder', 'auto_detect', 'correct_heading', 'mission_owner', 'diagnostic_period'}
SCHEMA_OF = {s.role: s for s in role_params.SCHEMAS}
SCHEMA_OF['record_server'] = role_params.LANDMARK_SAVING


def node_params(path):
    """[(node type, param name)] set inside each blind_navigation node of ``path``."""
    out = []
    for node in ElementTree.parse(path).getroot().iter('node'):
        if node.get('pkg') != 'blind_navigation':
            continue
        names = [tag.get('name') for tag in node.iter('param')]
        for tag in node.iter('rosparam'):
            if not tag.get('param') and (tag.text or '').strip():
                names += list(yaml.safe_load(tag.text))
        out += [(node.get('type'), name) for name in names]
    root = ElementTree.parse(path).getroot()
    nested = {id(tag) for kind in ('node', 'test') for parent in root.iter(kind) for tag in parent.iter()}
    for tag in root.iter('param'):      # a rig's ``$(arg roles)<role>/name`` for the whole layer
        role, _, name = tag.get('name').replace('$(arg roles)', '').rpartition('/')
        if id(tag) not in nested and role in SCHEMA_OF and name not in NODE_PARAMS:
            out.append(('mission_owner.py', role + '/' + name))
    return out


@pytest.mark.parametrize('path', LAUNCH_FILES + sorted(
    glob.glob(os.path.join(REPO, 'test', 'rostest', '*.test'))
    + glob.glob(os.path.join(REPO, 'test', 'rostest', '*.launch'))
    + glob.glob(os.path.join(REPO, 'test', 'lanes', '*.test'))), ids=os.path.basename)
def test_every_role_param_a_file_sets_is_one_a_user_can_set(path):
    ignored = []
    for node_type, name in node_params(path):
        if node_type == 'mission_owner.py':
            role, _, param = name.rpartition('/')
            schema = SCHEMA_OF.get(role) if role else None
            if not role and name in NODE_PARAMS:
                continue
            if schema is None:      # a shared param at the node's top level
                if any(name in s.shared for s in role_params.SCHEMAS):
                    continue
                ignored.append(name)
                continue
        elif node_type in ROLE_NODES:
            schema, param = ROLE_NODES[node_type], name
            if param in NODE_PARAMS:
                continue
        else:
            continue
        if param not in {p.name for p in schema.params}:
            ignored.append(name)
    assert not ignored, ('%s sets %s, which no role reads (a constant now, or a typo: '
                         'docs/params.md lists what a user can set)' % (path, ignored))
