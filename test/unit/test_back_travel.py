"""Back travel on an exact unicycle: the paper's modes replay the mirrored
commands; the closed-loop RouteFollower drives the whole route home (arcs,
S-curves, turns in place, reversed stretches, pauses), forward only, turning in
place at corners, never faster than recorded, goal by goal as the server does
(core/goal.make_goal); it fails only when the robot stops making progress, and
time it was held for stale odometry does not count. Also the pi rotation."""
import math
from types import SimpleNamespace

import pytest

from blind_navigation.core.back_travel import replay_command
from blind_navigation.core.route_follower import RouteFollower, section_limits
from blind_navigation.core.geometry import OdomState, distance
from blind_navigation.core.goal import make_goal
from blind_navigation.core.landmark import Landmark
from blind_navigation.core.rotation import Rotation
from blind_navigation.core.route import build_route

from unicycle import DT, Unicycle, record, run_controllers

LEFT_ARC = [(0.1, 0.2, 10.0)]
RIGHT_ARC = [(0.1, -0.2, 10.0)]
S_CURVE = [(0.1, 0.0, 4.0), (0.1, 0.25, 8.0), (0.1, -0.25, 8.0), (0.1, 0.0, 4.0)]
CORNERS = [(0.2, 0.0, 5.0), (0.0, 0.6, math.pi / 1.2), (0.2, 0.0, 5.0), (0.0, -0.6, math.pi / 1.2),
           (0.3, 0.0, 3.0)]
REVERSING = [(0.2, 0.05, 6.0), (0.0, 0.0, 2.0), (-0.15, 0.1, 4.0), (0.0, 0.0, 2.0), (0.2, 0.0, 4.0)]
PAUSED = [(0.15, 0.1, 4.0), (0.0, 0.0, 6.0), (0.15, -0.1, 4.0), (0.0, 0.0, 5.0)]
FAST = [(0.7, 0.0, 3.3), (0.7, 0.5, 3.5), (0.5, 0.0, 1.3), (0.5, -1.0, 1.9)]
PATHS = {'left arc': LEFT_ARC, 'right arc': RIGHT_ARC, 'S-curve': S_CURVE}
FOLLOWED = dict(PATHS, corners=CORNERS, reversing=REVERSING, paused=PAUSED, fast=FAST)


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
    run_controllers(robot, [make_goal(mode, lm, params) for lm in reversed(landmarks)])
    return robot


def follow(robot, route, params=None, limit=200000, log=None, section=0):
    """Drive ``route`` goal by goal (core/goal.make_goal, as the server does) on
    ``robot``; returns the follower. ``log`` collects (section, v, w, x, y)."""
    follower = RouteFollower(route, params)
    steps = 0
    for index in range(section, len(route.sections)):
        goal = make_goal('closed_loop', None, params, follower, index)
        goal.start(robot.odom)
        while not goal.done and not goal.failed:
            v, w = goal.step(robot.odom)
            if goal.done or goal.failed:
                break
            if log is not None:
                log.append((follower.section, v, w, robot.x, robot.y))
            robot.move(v, w, DT)
            steps += 1
            assert steps < limit, 'the follower did not finish in %d steps' % limit
        if goal.failed:
            return follower
    return follower


#: The exact unicycle stops dead: no coasting to lead the stop by.
EXACT = SimpleNamespace(stop_lead=0.0)
#: Paths whose motion changes within a sampling period (a turn in place, a reversal):
#: recorded with the motion-event samples (core/motion_events); without them such a
#: period's chord is uncertain (test_route shows by how much).
WITH_EVENTS = ('corners', 'reversing', 'fast')


def home(profile, params=EXACT, log=None, events=False):
    landmarks, end = record(profile, events=events)
    route = build_route(landmarks, (end.x, end.y))
    robot = turn_around(end)
    follower = follow(robot, route, params, log=log)
    return robot, follower, route, landmarks


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


@pytest.mark.parametrize('name', sorted(FOLLOWED))
def test_route_follower_drives_home_forward_only(name):
    log = []
    robot, follower, route, _ = home(FOLLOWED[name], log=log, events=name in WITH_EVENTS)
    assert follower.done and not follower.failed, follower.reason
    assert distance(robot.x, robot.y, 0.0, 0.0) < 0.03, (robot.x, robot.y)
    assert min(v for _, v, _, _, _ in log) >= 0.0
    sections = [section for section, _, _, _, _ in log]
    assert sections == sorted(sections)


def test_route_follower_turns_in_place_at_corners():
    log = []
    robot, follower, route, _ = home(CORNERS, log=log, events=True)
    inner = [i for i in route.corners if 0 < i < route.vertices - 1]
    assert len(inner) == 2
    for corner in inner:
        near = [(v, w) for _, v, w, x, y in log
                if distance(x, y, route.x[corner], route.y[corner]) < 0.03]
        assert any(v == 0.0 and abs(w) > 0.1 for v, w in near)


def test_reversed_stretch_is_driven_facing_the_way_it_was_recorded():
    log = []
    robot, follower, route, landmarks = home(REVERSING, log=log, events=True)
    assert follower.done
    # While retracing the reversed stretch (x between 0.6 and 1.2 m from the recording's
    # end of the first leg) the robot drives forward, i.e. faces +x as when it backed up.
    cusp = max(range(route.vertices), key=lambda i: route.x[i])
    assert route.corner[cusp]


def test_route_follower_never_drives_faster_than_recorded():
    log = []
    robot, follower, route, _ = home(PAUSED + FAST, log=log, events=True)
    for section, v, w, _, _ in log:
        limit = follower.limits[min(section, len(follower.limits) - 1)]
        assert v <= limit.max_v + 1e-9 and abs(w) <= limit.max_w + 1e-9


def test_section_limits_follow_the_recording_with_a_creep_floor():
    _, _, route, landmarks = home(PAUSED)
    section = route.sections[0]
    slow = section_limits(section, 0.5, 1.0, 0.3, 0.02)
    assert slow.max_v == max(section.speed, 0.02)
    assert slow.max_w == pytest.approx(min(1.0, section.turn_rate + 0.3))


def test_route_follower_resumes_at_a_section():
    landmarks, end = record(CORNERS, events=True)
    route = build_route(landmarks, (end.x, end.y))
    middle = len(route.sections) // 2
    vertex = route.sections[middle - 1].end_vertex
    robot = Unicycle(route.x[vertex], route.y[vertex], route.direction(vertex))
    follower = follow(robot, route, EXACT, section=middle)
    assert follower.done
    assert distance(robot.x, robot.y, 0.0, 0.0) < 0.03


def test_a_route_without_motion_is_done_at_once():
    route = build_route([Landmark(0.0, 0.0, 0.0, 2.0, 0.5)] * 3, (1.0, 1.0))
    follower = RouteFollower(route)
    follower.start(OdomState(1.0, 1.0, 0.0, 0.0, 0.0, 0.0))
    assert follower.done and all(follower.section_finished(i) for i in range(3))


def _stuck(follower, start, seconds, step=DT):
    """Steps of a robot that does not move, from ``start`` s for ``seconds``."""
    t = start
    while t < start + seconds and not follower.failed:
        t += step
        follower.step(OdomState(0.0, 0.0, math.pi, 0.0, 0.0, t))
    return t


def _stuck_follower(**params):
    landmarks, end = record(LEFT_ARC)
    route = build_route(landmarks, (0.0, 0.0))
    follower = RouteFollower(route, SimpleNamespace(**params))
    follower.start(OdomState(0.0, 0.0, math.pi, 0.0, 0.0, 0.0))
    return follower


def test_route_follower_fails_only_when_it_stops_making_progress():
    follower = _stuck_follower(stall_timeout=5.0)
    _stuck(follower, 0.0, 4.9)
    assert not follower.failed
    _stuck(follower, 4.9, 1.0)
    assert follower.failed and 'no progress' in follower.reason


def test_time_held_for_stale_odometry_does_not_count():
    follower = _stuck_follower(stall_timeout=5.0)
    t = _stuck(follower, 0.0, 2.5)
    t = _stuck(follower, t + 10.0, 2.0)          # a 10 s hold between two control steps
    assert not follower.failed
    assert follower.watch.held == pytest.approx(10.0 + DT)
    _stuck(follower, t, 1.0)                     # 5 s without progress, the hold left out
    assert follower.failed


def test_a_slow_section_is_late_not_fatal():
    # The robot drives at a third of every command: sections take three times
    # their nominal time, more than the per-section factor 2 + 0.1 s.
    landmarks, end = record(S_CURVE)
    route = build_route(landmarks, (end.x, end.y))
    robot = turn_around(end)
    follower = RouteFollower(route, SimpleNamespace(timeout_factor=2.0, timeout_margin=0.1))
    follower.start(robot.odom)
    for _ in range(100000):
        v, w = follower.step(robot.odom)
        if follower.done or follower.failed:
            break
        robot.move(v / 3.0, w / 3.0, DT)
    assert follower.done and follower.late
    assert all(taken > nominal for _, taken, nominal in follower.late)


def test_time_mode_ends_after_T_and_distance_mode_after_d():
    landmark = Landmark(0.1, 0.0, 0.15, 2.0, 0.0)
    for mode, expected in (('time', 0.2), ('distance', 0.15)):
        robot = Unicycle()
        controller, = run_controllers(robot, [make_goal(mode, landmark)])
        assert controller.travelled == pytest.approx(expected, abs=0.1 * DT + 1e-9)


def test_commands_are_clamped_and_allowance_fails_a_stalled_goal():
    params = SimpleNamespace(max_v=0.05, max_w=0.1, timeout_factor=1.0, timeout_margin=1.0)
    controller = make_goal('distance', Landmark(0.3, 0.5, 1.0, 1.0, 0.0), params)
    controller.start(OdomState(0, 0, 0, 0, 0, 0.0))
    assert controller.step(OdomState(0, 0, 0, 0, 0, 0.1)) == (0.05, -0.1)
    # The robot never moves: after T*factor + margin the goal fails and commands stop.
    assert controller.step(OdomState(0, 0, 0, 0, 0, 5.0)) == (0.0, 0.0)
    assert controller.failed and not controller.done


def test_unknown_mode_is_refused_and_closed_loop_needs_the_follower():
    with pytest.raises(ValueError, match='unknown back-travel mode'):
        make_goal('teleport', Landmark(0.1, 0, 0.1, 1, 0), None)
    with pytest.raises(ValueError, match='needs the return route follower'):
        make_goal('closed_loop', Landmark(0.1, 0, 0.1, 1, 0), None)


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
