"""A Python lane (scripts/python_lane.sh VERSION, its venv from requirements/pyXY.txt):
the interpreter and the pinned numpy and PyYAML are the lane's, no extension module
built for another Python is loaded, and the plain-Python harness runs every control
mode with and without loop pruning on a Table VI mission, a loop mission and a
real-like path (paper noise); the default return (closed_loop, pruning on) comes home
within 2 % of the path on loops_figure_eight and table6_test3 (issue 21).
Skipped outside a lane (no BN_LANE)."""
import math
import os
import re
import sys

import numpy
import pytest
import yaml

from blind_navigation.sim.command_series import load_trajectory
from blind_navigation.sim.harness import run_mission, run_modes

#: the lane's name (py38, py312, py313: scripts/python_lane.sh) and its pinned requirements
LANE = os.environ.get('BN_LANE', '')
REQUIREMENTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'requirements',
                            LANE + '.txt')
if not LANE:
    pytest.skip('not in a Python lane (scripts/python_lane.sh sets BN_LANE)', allow_module_level=True)

#: label: (control mode, prune_loops)
MODES = {'time': ('time', False), 'time+prune': ('time', True),
         'distance': ('distance', False), 'distance+prune': ('distance', True),
         'closed_loop': ('closed_loop', False), 'closed_loop+prune': ('closed_loop', True)}
#: the issue's bound for the default return: within 2 % of the path
DEFAULT_SHARE = 0.02
#: a pruned figure eight drives less than 60 % of the unpruned route (as its rostest of issue 29 did)
PRUNED_SHARE = 0.6


def pinned(name):
    """The version requirements/LANE.txt pins ``name`` to."""
    with open(REQUIREMENTS) as text:
        found = re.findall(r'^%s==(\S+)' % re.escape(name), text.read(), re.MULTILINE | re.IGNORECASE)
    assert len(found) == 1, '%s pins %s %d times' % (REQUIREMENTS, name, len(found))
    return found[0]


def test_the_lane_runs_its_python_with_its_distributions_libraries():
    assert LANE == 'py%d%d' % sys.version_info[:2], (LANE, sys.version)
    assert (numpy.__version__, yaml.__version__) == (pinned('numpy'), pinned('PyYAML')), \
        (numpy.__version__, numpy.__file__, yaml.__version__, yaml.__file__)


def test_no_extension_module_of_another_python_is_loaded():
    import actionlib  # noqa: F401 (what the nodes import: Debian's pure-Python ROS libraries)
    import rosbag  # noqa: F401
    import rosgraph.network
    import roslaunch  # noqa: F401 (rostest's; from 3.12 on its distutils is setuptools' shim)
    import rospy  # noqa: F401
    import blind_navigation.ros.layer  # noqa: F401
    import blind_navigation.evaluation.bench  # noqa: F401
    rosgraph.network.get_local_addresses()  # netifaces
    own = 'cpython-%d%d' % sys.version_info[:2]
    foreign = sorted('%s: %s' % (name, module.__file__) for name, module in list(sys.modules.items())
                     if (getattr(module, '__file__', None) or '').endswith('.so')
                     and own not in os.path.basename(module.__file__)
                     and '.abi3.' not in os.path.basename(module.__file__))
    assert not foreign, foreign


@pytest.mark.parametrize('mission', ['table6_test3', 'loops_figure_eight', 'tuc_lecture_hall_loop'])
def test_every_mode_with_and_without_pruning(mission):
    source = load_trajectory(mission) if mission.startswith('tuc_') else mission
    results = run_modes(source, 'paper', tuple(MODES), 0,
                        settings_of=lambda label: {'prune_loops': MODES[label][1]},
                        run_mode=lambda label: MODES[label][0])
    for label, result in results.items():
        assert result.status == 'home', (label, result.reason)
        assert math.isfinite(result.position_error) and result.return_length > 0, label
    for mode in ('time', 'distance'):  # pruning cuts the closed_loop route only
        assert results[mode + '+prune'].position_error == results[mode].position_error, mode
    for label in ('closed_loop', 'closed_loop+prune'):
        result = results[label]
        assert result.position_error < DEFAULT_SHARE * result.distance, (label, result.position_error)
    pruned = results['closed_loop+prune']
    if mission == 'loops_figure_eight':
        assert pruned.pruning.cuts
        assert pruned.route_length < PRUNED_SHARE * results['closed_loop'].route_length
    else:
        assert pruned.route_length == results['closed_loop'].route_length


@pytest.mark.parametrize('seed', [0, 1, 2])
@pytest.mark.parametrize('mission', ['loops_figure_eight', 'table6_test3'])
def test_the_default_return_comes_home_within_2_percent(mission, seed):
    result = run_mission(mission, 'paper', 'closed_loop', seed, prune_loops=True, floor=False)
    assert result.status == 'home', result.reason
    assert result.position_error < DEFAULT_SHARE * result.distance, \
        '%s seed %d: %.3f m of %.2f m' % (mission, seed, result.position_error, result.distance)
