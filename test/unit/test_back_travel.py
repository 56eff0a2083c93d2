"""Back-travel controllers and the pi rotation on an exact unicycle: the turn is
mirrored, each mode retraces arcs and S-curves to the start, limits hold."""
import math
from types import SimpleNamespace

import pytest

from blind_navigation.core.back_travel import (ReturnRoute, make_controller, replay_command)
from blind_navigation.core.geometry import OdomState, distance
from blind_navigation.core.landmark import Landmark
from blind_navigation.core.rotation import Rotation

from unicycle import DT, Unicycle, record, run_controllers

LEFT_ARC = [(0.1, 0.2, 10.0)]
RIGHT_ARC = [(0.1, -0.2, 10.0)]
S_CURVE = [(0.1, 0.0, 4.0), (0.1, 0.25, 8.0), (0.1, -0.25, 8.0), (0.1, 0.0, 4.0)]
PATHS = {'left arc': LEFT_ARC, 'right arc': RIGHT_ARC, 'S-curve': S_CURVE}


def turn_around(end):
    """A unicycle at ``end``, turned by pi with the Rotation controller."""
    robot = Unicycle(end.x, end.y, end.yaw)
    rotation = Rotation()
    rotation.start(robot.odom)
    for _ in range(5000):
        _, w = rotation.step(robot.odom)
        if rotation.done:
            break
        robot.move(0.0, w, DT)
    assert rotation.done and not rotation.failed
    return robot


def go_home(landmarks, end, mode, params=None):
    robot = turn_around(end)
    route = ReturnRoute((end.x, end.y))
    run_controllers(robot, [make_controller(mode, lm, params, route) for lm in reversed(landmarks)])
    return robot


def test_replay_mirrors_the_turn_and_keeps_v():
    curved = Landmark(0.09, 0.1, 0.09, 1.0, 0.3)
    assert replay_command(curved, 2.0) == (0.09, -0.1)
    straight = Landmark(0.09, 0.02, 0.18, 2.0, 0.3)
    assert replay_command(straight, 2.0) == (0.09, 0.0)


@pytest.mark.parametrize('name', sorted(PATHS))
@pytest.mark.parametrize('mode', ['time', 'distance'])
def test_paper_modes_retrace_all_curved_recordings(name, mode):
    # Every landmark sampled at the curved rate: the paper's modes replay (v, -w)
    # exactly, so only the 20 ms control step separates the end from the start.
    landmarks, end = record(PATHS[name], straight_period=1.0, curved_period=1.0)
    params = SimpleNamespace(straight_period=2.0)
    robot = go_home(landmarks, end, mode, params)
    assert distance(robot.x, robot.y, 0.0, 0.0) < 0.03, (robot.x, robot.y)


def test_replaying_w_unmirrored_misses_the_start():
    # The check above can fail: replaying +w on a left arc ends far away.
    landmarks, end = record(LEFT_ARC, straight_period=1.0, curved_period=1.0)
    wrong = [lm._replace(w=-lm.w) for lm in landmarks]
    robot = go_home(wrong, end, 'time', SimpleNamespace(straight_period=2.0))
    assert distance(robot.x, robot.y, 0.0, 0.0) > 0.5


@pytest.mark.parametrize('name', sorted(PATHS))
def test_closed_loop_retraces_two_rate_recordings(name):
    landmarks, end = record(PATHS[name])
    robot = go_home(landmarks, end, 'closed_loop')
    assert distance(robot.x, robot.y, 0.0, 0.0) < 0.02, (robot.x, robot.y)


def test_closed_loop_corrects_a_poor_turn():
    # Turned by pi + 0.2 rad: the paper's modes would drift off; closed loop recovers.
    landmarks, end = record(S_CURVE)
    robot = Unicycle(end.x, end.y, end.yaw + math.pi + 0.2)
    route = ReturnRoute((end.x, end.y))
    run_controllers(robot, [make_controller('closed_loop', lm, None, route)
                            for lm in reversed(landmarks)])
    assert distance(robot.x, robot.y, 0.0, 0.0) < 0.03


def test_closed_loop_retraces_a_path_recorded_with_pauses():
    # The robot stood still for 6 ticks before vision was lost and for 5 ticks
    # mid-path (zero-length landmarks): the route search must look past them.
    landmarks, end = record(S_CURVE)
    standing = lambda lm: Landmark(0.0, 0.0, 0.0, 2.0, lm.psi)
    half = len(landmarks) // 2
    paused = (landmarks[:half] + [standing(landmarks[half - 1])] * 5 + landmarks[half:]
              + [standing(landmarks[-1])] * 6)
    robot = go_home(paused, end, 'closed_loop')
    assert distance(robot.x, robot.y, 0.0, 0.0) < 0.02, (robot.x, robot.y)


def test_time_mode_ends_after_T_and_distance_mode_after_d():
    landmark = Landmark(0.1, 0.0, 0.15, 2.0, 0.0)
    for mode, expected in (('time', 0.2), ('distance', 0.15)):
        robot = Unicycle()
        controller, = run_controllers(robot, [make_controller(mode, landmark)])
        assert controller.travelled == pytest.approx(expected, abs=0.1 * DT + 1e-9)


def test_commands_are_clamped_and_allowance_fails_a_stalled_goal():
    params = SimpleNamespace(max_v=0.05, max_w=0.1, timeout_factor=1.0, timeout_margin=1.0)
    controller = make_controller('distance', Landmark(0.3, 0.5, 1.0, 1.0, 0.0), params)
    controller.start(OdomState(0, 0, 0, 0, 0, 0.0))
    assert controller.step(OdomState(0, 0, 0, 0, 0, 0.1)) == (0.05, -0.1)
    # The robot never moves: after T*factor + margin the goal fails and commands stop.
    assert controller.step(OdomState(0, 0, 0, 0, 0, 5.0)) == (0.0, 0.0)
    assert controller.failed and not controller.done


def test_unknown_mode_is_refused():
    with pytest.raises(ValueError, match='unknown back-travel mode'):
        make_controller('teleport', Landmark(0.1, 0, 0.1, 1, 0), None)


@pytest.mark.parametrize('start_yaw', [0.0, 2.5, -3.0])
def test_rotation_turns_pi_within_tolerance_across_the_seam(start_yaw):
    robot = turn_around(OdomState(0, 0, start_yaw, 0, 0, 0))
    turned = (robot.yaw - start_yaw) % (2 * math.pi)
    assert turned == pytest.approx(math.pi, abs=Rotation().tolerance)


def test_rotation_decelerates_and_fails_when_the_robot_does_not_turn():
    rotation = Rotation(SimpleNamespace(time_allowance=2.0))
    rotation.start(OdomState(0, 0, 0, 0, 0, 0.0))
    far = abs(rotation.step(OdomState(0, 0, 0.0, 0, 0, 0.1))[1])
    near = abs(rotation.step(OdomState(0, 0, math.pi - 0.05, 0, 0, 0.2))[1])
    assert far == pytest.approx(rotation.max_w) and near < far
    assert rotation.step(OdomState(0, 0, math.pi - 0.05, 0, 0, 3.0)) == (0.0, 0.0)
    assert rotation.failed and not rotation.done
