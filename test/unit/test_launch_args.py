"""The launch files' args as `roslaunch --ros-args` lists them: none reads as required
unless it is, and a default that stands for a node's default agrees with it."""
import ast
import glob
import importlib.util
import os
import xml.etree.ElementTree as ElementTree

import pytest
from roslaunch.arg_dump import get_args
from roslaunch.loader import convert_value

from blind_navigation.ros.common import ros_home_file

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
# scripts/param_table.py reads the roles' DEFAULTS as text (no built messages needed)
SPEC = importlib.util.spec_from_file_location('param_table', os.path.join(REPO, 'scripts', 'param_table.py'))
param_table = importlib.util.module_from_spec(SPEC)
SPEC.loader.exec_module(param_table)

LAUNCH_FILES = sorted(glob.glob(os.path.join(REPO, 'launch', '*.launch')))

#: (launch file, arg) -> (role module, role class, param) whose default the arg repeats
NODE_DEFAULTS = {}
for _launch in ('blind_navigation', 'recording', 'bench'):
    NODE_DEFAULTS[(_launch, 'deadband')] = ('sampling_publisher', 'SamplingPublisher', 'deadband')
for _launch in ('blind_navigation', 'recording'):
    NODE_DEFAULTS[(_launch, 'straight_rate')] = ('sampling_publisher', 'SamplingPublisher',
                                                 'straight_rate')
    NODE_DEFAULTS[(_launch, 'curved_rate')] = ('sampling_publisher', 'SamplingPublisher',
                                               'curved_rate')
NODE_DEFAULTS.update({
    ('blind_navigation', 'standstill_time'): ('heading_correction', 'HeadingCorrectionRole',
                                              'standstill_time'),
    ('blind_navigation', 'heading_budget'): ('heading_correction', 'HeadingCorrectionRole',
                                             'heading_budget'),
    ('blind_navigation', 'stop_lead'): ('back_travel_server', 'BackTravelServer', 'stop_lead'),
    ('recording', 'fsync'): ('landmark_saving', 'LandmarkSaving', 'fsync'),
    ('recording', 'min_subscribers'): ('sampling_publisher', 'SamplingPublisher',
                                       'min_subscribers'),
    ('calibrate_gyro', 'turns'): ('calibrate_gyro', 'CalibrateGyro', 'turns'),
    ('calibrate_gyro', 'max_w'): ('calibrate_gyro', 'CalibrateGyro', 'max_w'),
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
    module, class_name, param = NODE_DEFAULTS[(launch, arg)]
    node_default = param_table.role_defaults(module, class_name)[0][param]
    text = launch_defaults(launch)[arg][1]
    value = convert_value(text, 'auto')     # as a <param value="$(arg ...)"> sets it
    assert value == node_default and type(value) is type(node_default), (
        '%s.launch %s default %r differs from %s.%s %s = %r'
        % (launch, arg, text, module, class_name, param, node_default))


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
