"""ros/faults.py's wiring checks without a master: the one type comparison, the connection-header
check (accepted once per connection, refused with one FATAL line per topic, every
fault listener told), the master's topic types; ros/kobuki_msgs_compat with a
kobuki_msgs on the path that has no generated classes."""
import importlib
import sys
import types

import pytest
import rospy
from nav_msgs.msg import Odometry

from blind_navigation.ros import faults as registry, kobuki_msgs_compat
from blind_navigation.ros.vision_monitor import ODOM_INFO

ODOMETRY = 'nav_msgs/Odometry'


@pytest.fixture
def fatal(monkeypatch):
    """A fresh process fault registry (ros/faults.py); the FATAL lines logged."""
    monkeypatch.setattr(registry, '_faults', {})
    monkeypatch.setattr(registry, '_listeners', [])
    lines = []
    monkeypatch.setattr(rospy, 'logfatal', lambda text, *args: lines.append(text % args))
    return lines


def header(msg_type, md5sum):
    return {'type': msg_type, 'md5sum': md5sum, 'callerid': '/publisher'}


def test_the_type_and_its_md5_sum_must_match():
    expected = registry.Expected.of(Odometry)
    assert expected.mismatch(ODOMETRY, Odometry._md5sum) is None
    assert expected.mismatch(ODOMETRY) is None               # the master knows no MD5 sum
    assert expected.mismatch('geometry_msgs/Twist', 'x') == 'geometry_msgs/Twist'
    assert 'another version' in expected.mismatch(ODOMETRY, '0' * 32)
    assert expected.mismatch('', None) == 'a message without a type'


def test_odom_info_of_either_rtabmap_package_any_version():
    assert ODOM_INFO.mismatch('rtabmap_msgs/OdomInfo', 'a' * 32) is None
    assert ODOM_INFO.mismatch('rtabmap_ros/OdomInfo', 'b' * 32) is None
    assert ODOM_INFO.mismatch('nav_msgs/Odometry', Odometry._md5sum) == ODOMETRY


def test_a_wrong_connection_is_refused_with_one_fatal_line_per_topic(fatal):
    faults = []
    registry.on_fault(faults.append)
    expected = registry.Expected.of(Odometry)
    right = header(ODOMETRY, Odometry._md5sum)
    assert expected.accepts('/odom', right) and expected.accepts('/odom', right)
    assert fatal == [] and not registry.faulty() and faults == []
    wrong = header('geometry_msgs/Twist', '9f195f881246fdfa2798d1d3eebca84a')
    for _ in range(3):
        assert not expected.accepts('/odom', wrong)
    assert len(fatal) == 1
    assert all(text in fatal[0] for text in ('/odom', ODOMETRY, 'geometry_msgs/Twist', 'nothing moves'))
    assert registry.faulty() and len(faults) == 1
    assert '/odom carries geometry_msgs/Twist, expected nav_msgs/Odometry' in faults[0]
    late = []
    registry.on_fault(late.append)                # a listener registered later hears of it at once
    assert late == faults


def test_the_masters_topic_types(fatal):
    expected = {'/odom': registry.Expected.of(Odometry), '/rtabmap/odom_info_lite': ODOM_INFO}
    registry.check_types([['/odom', ODOMETRY], ['/rtabmap/odom_info_lite', 'rtabmap_msgs/OdomInfo'],
                        ['/other', 'std_msgs/String']], expected)
    assert fatal == []
    registry.check_types([['/odom', ODOMETRY], ['/rtabmap/odom_info_lite', 'std_msgs/String']], expected)
    registry.check_types([['/rtabmap/odom_info_lite', 'std_msgs/String']], expected)
    assert len(fatal) == 1 and 'rtabmap_msgs/OdomInfo or rtabmap_ros/OdomInfo' in fatal[0]


def test_a_kobuki_msgs_without_its_classes_counts_as_absent(monkeypatch):
    package = types.ModuleType('kobuki_msgs')
    package.msg = types.ModuleType('kobuki_msgs.msg')      # a source checkout, nothing generated
    monkeypatch.setitem(sys.modules, 'kobuki_msgs', package)
    monkeypatch.setitem(sys.modules, 'kobuki_msgs.msg', package.msg)
    try:
        compat = importlib.reload(kobuki_msgs_compat)
        assert compat.BumperEvent._type == 'kobuki_msgs/BumperEvent'
        assert compat.BumperEvent._md5sum == 'ffe360cd50f14f9251d9844083e72ac5'
    finally:
        monkeypatch.undo()
        importlib.reload(kobuki_msgs_compat)


def test_a_failing_listener_does_not_keep_the_others_from_hearing(fatal, monkeypatch):
    errors, heard = [], []
    monkeypatch.setattr(rospy, 'logerr', lambda text, *args: errors.append(text % args))

    def broken(_fault):
        raise RuntimeError('broken listener')
    registry.on_fault(broken)
    registry.on_fault(heard.append)
    registry.refuse('/mobile_base/events/cliff', registry.Expected(('kobuki_msgs/CliffEvent',)), 'std_msgs/String')
    assert len(fatal) == 1 and len(heard) == 1
    assert errors and 'RuntimeError: broken listener' in errors[0]


def test_sensor_state_is_kobuki_msgs_own_and_another_type_is_refused(fatal):
    """kobuki_msgs 0.7.0's SensorState (the MD5 sum its generated code carries), so a real
    Kobuki's mobile_base/sensors/core connects; a Twist there is refused (battery_low)."""
    state = kobuki_msgs_compat.SensorState
    assert (state._type, state._md5sum) == ('kobuki_msgs/SensorState', '430a4bfd78449c8740bfef32b26613a6')
    assert state().DOCKING_CHARGING == 6 and state(battery=161).battery == 161
    expected = registry.Expected.of(state)
    assert expected.accepts('mobile_base/sensors/core', header(state._type, state._md5sum))
    assert not expected.accepts('mobile_base/sensors/core', header('geometry_msgs/Twist', '*'))
    assert len(fatal) == 1 and 'expected kobuki_msgs/SensorState' in fatal[0]
