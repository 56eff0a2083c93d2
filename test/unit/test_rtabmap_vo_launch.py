"""launch/rtabmap_vo.launch, loaded by roslaunch's own loader (no master, no RTAB-Map
needed): RTAB-Map's rgbd_odometry in its own namespace and frame, publishing the
topics the layer reads by default (names.VO_ODOM, names.VO_ODOM_INFO) and no TF, so
nothing clashes with the Kobuki's odom -> base_footprint."""
import os
import xml.etree.ElementTree as ET

import pytest
import roslaunch.config

from blind_navigation import names

LAUNCH_DIR = os.path.join(os.path.dirname(__file__), '..', '..', 'launch')
RTABMAP_VO = os.path.join(LAUNCH_DIR, 'rtabmap_vo.launch')
KOBUKI_ODOM_FRAME = 'odom'


def load(*args):
    config = roslaunch.config.load_config_default([(RTABMAP_VO, list(args))], None, verbose=False)
    (node,) = config.nodes
    params = {key[len(node.namespace + node.name) + 1:]: value.value for key, value in config.params.items()
              if key.startswith(node.namespace + node.name + '/')}
    return node, params


def test_the_node_publishes_the_layers_default_vo_topics():
    node, _ = load()
    assert (node.package, node.type) == ('rtabmap_odom', 'rgbd_odometry')
    assert node.namespace + 'odom' == '/' + names.VO_ODOM
    assert node.namespace + 'odom_info_lite' == '/' + names.VO_ODOM_INFO


def test_no_tf_and_a_frame_of_its_own():
    _, params = load()
    assert params['publish_tf'] is False
    assert params['odom_frame_id'] != KOBUKI_ODOM_FRAME
    assert params['frame_id'] == 'base_footprint'


def test_lost_frames_are_published_as_null_poses():
    _, params = load()
    assert params['publish_null_when_lost'] is True


def test_the_namespace_and_camera_topics_follow_the_args():
    node, params = load('namespace:=robot1/rtabmap', 'rgb_topic:=/robot1/camera/rgb/image_rect_color',
                        'odom_pkg:=rtabmap_ros', 'vo_frame_id:=robot1/vo_odom')
    assert node.namespace == '/robot1/rtabmap/'
    assert node.package == 'rtabmap_ros'
    assert ['rgb/image', '/robot1/camera/rgb/image_rect_color'] in node.remap_args
    assert params['odom_frame_id'] == 'robot1/vo_odom'


@pytest.mark.parametrize('launch_file', sorted(f for f in os.listdir(LAUNCH_DIR) if f.endswith('.launch')))
def test_every_argument_a_user_can_set_is_documented(launch_file):
    root = ET.parse(os.path.join(LAUNCH_DIR, launch_file)).getroot()
    undocumented = [arg.get('name') for arg in root.iter('arg')
                    if arg.get('value') is None and not (arg.get('doc') or '').strip()]
    assert not undocumented, '%s: args without doc=: %s' % (launch_file, undocumented)


def test_the_sync_queue_under_its_new_name_and_the_old_one_only_for_old_releases():
    _, params = load()
    assert params['sync_queue_size'] == 10 and 'queue_size' not in params
    _, params = load('odom_pkg:=rtabmap_ros')
    assert params['sync_queue_size'] == params['queue_size'] == 10
    _, params = load('legacy_queue_size:=true', 'queue_size:=5')
    assert params['sync_queue_size'] == params['queue_size'] == 5
