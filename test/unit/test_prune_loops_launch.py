"""blind_navigation.launch's ``prune_loops`` arg (INTERFACE.md), loaded by roslaunch's
own loader (no master): the client's REQUIRED ``prune_loops`` is set in both node
layouts, true by default (the better measured: evaluation/loops.py), and false
whenever the control is time or distance, which replay every landmark open loop
and cannot prune."""
import os

import pytest
import roslaunch.config

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
LAUNCH = os.path.join(REPO, 'launch', 'blind_navigation.launch')


@pytest.fixture(autouse=True)
def package_path(monkeypatch):
    """$(find blind_navigation) resolves to this repo (the paper layout includes recording.launch)."""
    monkeypatch.setenv('ROS_PACKAGE_PATH', os.pathsep.join(
        [REPO] + [p for p in os.environ.get('ROS_PACKAGE_PATH', '').split(os.pathsep) if p]))


def client_prune_loops(*args):
    config = roslaunch.config.load_config_default([(LAUNCH, list(args))], None, verbose=False)
    values = {key: param.value for key, param in config.params.items() if key.endswith('/prune_loops')}
    assert len(values) == 1, values
    (key, value), = values.items()
    assert key.endswith('back_travel_client/prune_loops')
    return value


@pytest.mark.parametrize('layout', [[], ['one_process:=false']], ids=['one process', 'paper layout'])
def test_the_client_prunes_by_default_in_closed_loop(layout):
    assert client_prune_loops(*layout) is True
    assert client_prune_loops('prune_loops:=false', *layout) is False


@pytest.mark.parametrize('control', ['time', 'distance'])
def test_time_and_distance_cannot_prune(control):
    assert client_prune_loops('control:=%s' % control, 'prune_loops:=true') is False
    assert client_prune_loops('control:=%s' % control, 'prune_loops:=true', 'one_process:=false') is False


def test_the_arg_is_documented():
    config = roslaunch.config.load_config_default([(LAUNCH, [])], None, verbose=False)
    assert config is not None
    with open(LAUNCH) as stream:
        text = stream.read()
    line = [l for l in text.splitlines() if 'name="prune_loops"' in l and '<arg' in l][0]
    assert 'doc="' in line and 'cannot prune' in line
