"""rviz/blind_navigation.rviz: an RViz 1 config (the layout RViz 1.13/1.14 saves) that
shows the layer's topics by their names in names.py, relative (an RViz started in a
robot's namespace, launch/rviz.launch, shows that robot's), in the odometry frame, top
down. RViz itself is not needed: the file is checked as data."""
import os

import roslaunch.config
import yaml

from blind_navigation import names

CONFIG = os.path.join(os.path.dirname(__file__), '..', '..', 'rviz', 'blind_navigation.rviz')
LAUNCH_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..', 'launch'))
#: the properties RViz saves for these display classes (rviz's odometry_display.cpp,
#: path_display.cpp, grid_display.cpp); a missing one silently takes RViz's default
SAVED_KEYS = {
    'rviz/Grid': {'Alpha', 'Cell Size', 'Class', 'Color', 'Enabled', 'Line Style', 'Name',
                  'Normal Cell Count', 'Offset', 'Plane', 'Plane Cell Count', 'Reference Frame', 'Value'},
    'rviz/Odometry': {'Angle Tolerance', 'Class', 'Covariance', 'Enabled', 'Keep', 'Name',
                      'Position Tolerance', 'Queue Size', 'Shape', 'Topic', 'Unreliable', 'Value'},
    'rviz/Path': {'Alpha', 'Buffer Length', 'Class', 'Color', 'Enabled', 'Head Diameter', 'Head Length',
                  'Length', 'Line Style', 'Line Width', 'Name', 'Offset', 'Pose Color', 'Pose Style',
                  'Queue Size', 'Radius', 'Shaft Diameter', 'Shaft Length', 'Topic', 'Unreliable', 'Value'},
}
#: what a user must see: wheel odometry, the recorded path, the return driven and planned
SHOWN = {names.ODOM, names.RECORDED_PATH, names.RETURN_PATH, names.RETURN_ROUTE}
KNOWN_TOPICS = {value for key, value in vars(names).items() if key.isupper() and isinstance(value, str)}


def load():
    with open(CONFIG) as stream:
        return yaml.safe_load(stream)


def displays():
    return load()['Visualization Manager']['Displays']


def test_the_config_has_rviz_sections():
    config = load()
    assert {'Panels', 'Visualization Manager', 'Window Geometry'} <= set(config)
    manager = config['Visualization Manager']
    assert manager['Global Options']['Fixed Frame'] == 'odom'
    assert manager['Views']['Current']['Class'] == 'rviz/TopDownOrtho'


def test_every_display_has_the_keys_rviz_saves():
    for display in displays():
        expected = SAVED_KEYS.get(display['Class'], {'Class', 'Enabled', 'Name', 'Value'})
        assert expected <= set(display), '%s lacks %s' % (display['Name'], expected - set(display))
        assert display['Enabled'] == display['Value'], display['Name']


def test_enabled_displays_show_the_layer_topics_by_their_relative_names():
    topics = {display['Topic'] for display in displays() if 'Topic' in display}
    absolute = sorted(topic for topic in topics if topic.startswith('/'))
    assert not absolute, 'absolute topics do not follow a <group ns=...>: %s' % absolute
    assert topics <= KNOWN_TOPICS, topics - KNOWN_TOPICS
    shown = {display['Topic'] for display in displays() if display['Enabled'] and 'Topic' in display}
    assert SHOWN <= shown, 'not shown: %s' % (SHOWN - shown)
    assert any(d['Class'] == 'rviz/Grid' and d['Enabled'] for d in displays())


def test_no_topic_anywhere_in_the_file_is_absolute():
    with open(CONFIG) as stream:
        lines = [line.strip() for line in stream if line.strip().startswith('Topic:')]
    assert lines and not [line for line in lines if line.split(':', 1)[1].strip().startswith('/')]


def launched_rviz(tmp_path, include_args=''):
    """The RViz node of a launch file that includes rviz.launch (by blind_navigation.launch
    or directly) inside <group ns="robot1">, loaded by roslaunch's own loader."""
    launch = tmp_path / 'robot1.launch'
    launch.write_text('<launch><group ns="robot1"><include file="%s">%s</include></group></launch>'
                      % (os.path.join(LAUNCH_DIR, 'blind_navigation.launch'), include_args))
    config = roslaunch.config.load_config_default([str(launch)], None, verbose=False)
    return [node for node in config.nodes if node.package == 'rviz']


def test_rviz_starts_in_the_robots_namespace_only_when_asked(tmp_path):
    assert launched_rviz(tmp_path) == []
    (node,) = launched_rviz(tmp_path, '<arg name="rviz" value="true"/>'
                                      '<arg name="odom_topic" value="wheel_odom"/>')
    assert node.namespace == '/robot1/'
    assert node.args.endswith('rviz/blind_navigation.rviz -f odom')
    # the layer's remaps reach RViz too: it shows what the layer reads
    assert ['odom', 'wheel_odom'] in node.remap_args


def test_display_names_are_unique():
    labels = [display['Name'] for display in displays()]
    assert len(labels) == len(set(labels))
