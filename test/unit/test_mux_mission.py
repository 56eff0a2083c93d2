"""Unit tests of the yocs-style cmd_vel mux rules and of scripted missions."""
import math

import pytest

from blind_navigation.sim.mission import load_mission, mission_from_dict
from blind_navigation.sim.mux import IDLE, TURTLEBOT_INPUTS, CmdVelMux, inputs_from_list

SAFETY, TELEOP, SWITCH, NAVI = range(4)


def test_higher_priority_takes_over_lower_is_ignored_until_timeout():
    mux = CmdVelMux(TURTLEBOT_INPUTS)
    assert mux.active_name == IDLE
    assert mux.offer(NAVI, 0.0) == (True, 'Navigation')
    assert mux.offer(TELEOP, 0.1) == (True, 'Teleoperation')
    assert mux.offer(NAVI, 0.2) == (False, None)
    assert mux.offer(TELEOP, 0.3) == (True, None)
    assert mux.expire(1.3) is None            # exactly the timeout: still held
    assert mux.expire(1.31) == IDLE
    assert mux.offer(NAVI, 1.4) == (True, 'Navigation')


def test_a_clock_that_moved_back_times_the_holder_out_from_then():
    mux = CmdVelMux(TURTLEBOT_INPUTS)
    mux.offer(TELEOP, 60.0)
    assert mux.expire(0.1) is None and mux.active_name == 'Teleoperation'   # restarted: from 0.1 on
    assert mux.expire(1.1) is None            # the teleop timeout (1 s) from then
    assert mux.expire(1.11) == IDLE


def test_safety_controller_short_timeout():
    mux = CmdVelMux(TURTLEBOT_INPUTS)
    mux.offer(TELEOP, 0.0)
    assert mux.offer(SAFETY, 0.05) == (True, 'Safe reactive controller')
    assert mux.offer(TELEOP, 0.1) == (False, None)
    assert mux.expire(0.26) == IDLE
    assert mux.offer(TELEOP, 0.3) == (True, 'Teleoperation')


def test_bad_mux_inputs_rejected():
    with pytest.raises(ValueError, match='subscribers.0.'):
        inputs_from_list([{'name': 'a'}])
    with pytest.raises(ValueError, match='unique'):
        inputs_from_list([dict(name='a', topic='a', timeout=1, priority=1),
                          dict(name='b', topic='b', timeout=1, priority=1)])


def test_segments_play_back_to_back():
    mission = mission_from_dict({'segments': [{'v': 0.1, 'distance': 0.5},
                                              {'v': 0.1, 'w': 0.2, 'angle': 0.4},
                                              {'duration': 1.0}]})
    assert mission.duration == pytest.approx(5.0 + 2.0 + 1.0)
    assert mission.command_at(0.0) == (0.1, 0.0)
    assert mission.command_at(6.0) == (0.1, 0.2)
    assert mission.command_at(7.5) == (0.0, 0.0)
    assert mission.command_at(8.0) is None
    assert mission.nominal_length() == pytest.approx(0.7)


def test_waypoints_turn_then_drive():
    mission = mission_from_dict({'waypoints': {'v': 0.1, 'w': 0.5, 'points': [[1, 0], [1, 1]]}})
    assert mission.segments[0] == pytest.approx((0.1, 0.0, 10.0))
    assert mission.segments[1] == pytest.approx((0.0, 0.5, math.pi / 2 / 0.5))
    assert mission.segments[2] == pytest.approx((0.1, 0.0, 10.0))


def test_bad_missions_name_the_problem():
    with pytest.raises(ValueError, match='segments.0.: give exactly one'):
        mission_from_dict({'segments': [{'v': 0.1, 'distance': 1, 'duration': 2}]}, 'm')
    with pytest.raises(ValueError, match='cannot be covered'):
        mission_from_dict({'segments': [{'w': 0.1, 'distance': 1}]}, 'm')
    with pytest.raises(ValueError, match='either segments or waypoints'):
        mission_from_dict({}, 'm')


@pytest.mark.parametrize('name', ['table3_test%d' % i for i in range(1, 6)]
                         + ['table5_test%d' % i for i in range(1, 4)]
                         + ['table6_test%d' % i for i in range(1, 7)])
def test_shipped_missions_load(name):
    mission = load_mission(name)
    assert 2.5 < mission.nominal_length() < 13.5
