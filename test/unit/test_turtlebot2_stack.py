"""The TurtleBot2 source stack written down: turtlebot2_noetic.rosinstall (wstool's
format, read by PyYAML) pins kobuki, yujin_ocs, turtlebot and kobuki_msgs at commits;
launch/kobuki_safety_controller.launch loads Kobuki's safety controller the way
turtlebot_bringup's include does, onto the names the layer and the mux use."""
import os
import re

import roslaunch.config
import yaml

from blind_navigation import names

ROOT = os.path.join(os.path.dirname(__file__), '..', '..')
ROSINSTALL = os.path.join(ROOT, 'turtlebot2_noetic.rosinstall')
SAFETY_LAUNCH = os.path.join(ROOT, 'launch', 'kobuki_safety_controller.launch')
REPOSITORIES = {'kobuki': 'https://github.com/yujinrobot/kobuki.git',
                'yujin_ocs': 'https://github.com/yujinrobot/yujin_ocs.git',
                'turtlebot': 'https://github.com/turtlebot/turtlebot.git',
                'kobuki_msgs': 'https://github.com/yujinrobot/kobuki_msgs.git'}


def entries():
    with open(ROSINSTALL) as stream:
        data = yaml.safe_load(stream)
    assert isinstance(data, list), 'a rosinstall file is a list of entries'
    return data


def test_the_stack_is_pinned_at_commits():
    found = {}
    for entry in entries():
        assert list(entry) == ['git'], entry
        repo = entry['git']
        assert set(repo) == {'local-name', 'uri', 'version'}, repo
        assert re.fullmatch(r'[0-9a-f]{40}', str(repo['version'])), \
            '%s: version must be a 40-hex commit, not %r' % (repo['local-name'], repo['version'])
        found[repo['local-name']] = repo['uri']
    assert found == REPOSITORIES


def test_the_safety_controller_launch_matches_the_layers_names():
    config = roslaunch.config.load_config_default([SAFETY_LAUNCH], None, verbose=False)
    (node,) = config.nodes
    assert (node.package, node.type) == ('nodelet', 'nodelet')
    assert node.args == 'load kobuki_safety_controller/SafetyControllerNodelet mobile_base_nodelet_manager'
    remaps = dict(node.remap_args)
    assert remaps.pop('navigation_safety_controller/cmd_vel') == 'cmd_vel_mux/input/safety_controller'
    assert remaps == {'navigation_safety_controller/events/' + kind: topic
                      for kind, topic in names.SAFETY_EVENTS.items()}
