"""The `home` invariant of the closed-loop follower (issue 28; docs/safety.md, "home"):
whatever moves the robot on the way (a takeover, a push, a bad resume), the follower
reports the route finished only with the robot within ``finish_tolerance`` of the route's
end, and a robot left farther than ``route_max_offset`` from the route fails instead
of driving across space it has not driven. Also the paper modes after a moving pause,
and the owner's record of the pauses (core/pause.PauseLog)."""
import math
from types import SimpleNamespace

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from blind_navigation.core import outcome
from blind_navigation.core.back_travel import BACK_TRAVEL_DEFAULTS
from blind_navigation.core.geometry import OdomState, Pose2D, distance
from blind_navigation.core.goal import make_goal
from blind_navigation.core.landmark import Landmark
from blind_navigation.core.pause import PauseLog
from blind_navigation.core.route import build_route
from blind_navigation.core.route_follower import RouteFollower

from unicycle import DT, Unicycle

TOLERANCE = BACK_TRAVEL_DEFAULTS['finish_tolerance']
OFFSET = BACK_TRAVEL_DEFAULTS['route_max_offset']

LANDMARK = st.builds(Landmark, v=st.floats(0.05, 0.5), w=st.floats(-1.0, 1.0),
                     d=st.floats(0.05, 0.8), T=st.sampled_from([1.0, 2.0]),
                     psi=st.floats(-math.pi, math.pi))
#: (steps driven before the push, push dx, dy (m, within 5 m), new yaw)
PUSH = st.tuples(st.integers(0, 400), st.floats(-5.0, 5.0), st.floats(-5.0, 5.0),
                 st.floats(-math.pi, math.pi))


def _drive_with_push(route, push, limit=20000):
    """A follower (stop_lead 0: the unicycle stops at once) on ``route``; after ``push[0]``
    steps the robot is put elsewhere (a pause that moved it). Returns (robot, follower)."""
    before, dx, dy, yaw = push
    robot = Unicycle(route.x[0], route.y[0], route.direction(0) if route.vertices > 1 else 0.0)
    follower = RouteFollower(route, SimpleNamespace(stop_lead=0.0))
    follower.start(robot.odom)
    for step in range(limit):
        if step == before:
            robot.base.true_pose = Pose2D(robot.x + dx, robot.y + dy, yaw)   # put there, standing
            follower.pause_ended()
        v, w = follower.step(robot.odom)
        if follower.done or follower.failed:
            break
        robot.move(v, w, DT)
    return robot, follower


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(LANDMARK, min_size=1, max_size=8), PUSH)
def test_finished_only_within_the_home_tolerance_of_the_routes_end(landmarks, push):
    route = build_route(landmarks, (0.0, 0.0))
    robot, follower = _drive_with_push(route, push)
    off = distance(robot.x, robot.y, route.x[-1], route.y[-1])
    if follower.done:
        assert off <= TOLERANCE + 1e-9, 'finished %.3f m from the start (%s)' % (off, push)
    assert follower.done or follower.failed, 'neither finished nor failed'
    if follower.failed:
        assert follower.reason and follower.code in (outcome.OFF_ROUTE, outcome.NOT_HOME, outcome.TIMEOUT), follower.reason


def test_pushed_past_the_end_fails_naming_the_offset():
    route = build_route([Landmark(0.2, 0.0, 1.0, 2.0, 0.0)] * 2, (0.0, 0.0))
    # the return drives from (2, 0) towards (0, 0); pushed on to (-2.5, 0) halfway
    end = (route.x[-1], route.y[-1])
    robot, follower = _drive_with_push(route, (200, -2.5 - 1.2, 0.0, math.pi))
    assert follower.failed and not follower.done, follower.reason
    assert 'off the route' in follower.reason and follower.code == outcome.OFF_ROUTE, follower.reason
    assert distance(robot.x, robot.y, *end) > 2.0


def test_a_small_push_is_rejoined_and_the_return_comes_home():
    route = build_route([Landmark(0.2, 0.0, 1.0, 2.0, 0.0)] * 2, (0.0, 0.0))
    robot, follower = _drive_with_push(route, (100, 0.0, 0.25, math.pi))
    assert follower.done, follower.reason
    assert distance(robot.x, robot.y, route.x[-1], route.y[-1]) <= TOLERANCE
    assert follower.displaced > 0.2, 'the push counted as driven'


def test_a_finished_start_far_from_the_end_fails():
    route = build_route([Landmark(0.2, 0.0, 1.0, 2.0, 0.0)], (0.0, 0.0))
    follower = RouteFollower(route, SimpleNamespace(stop_lead=0.0))
    follower.start(OdomState(3.0, 0.0, 0.0, 0.0, 0.0, 0.0), section=len(route.sections))
    assert follower.failed and not follower.done, follower.reason
    assert follower.code == outcome.NOT_HOME


def test_a_replay_moved_while_paused_fails_and_does_not_count_the_move():
    for mode in ('time', 'distance'):
        goal = make_goal(mode, Landmark(0.2, 0.0, 0.4, 2.0, 0.0))
        goal.start(OdomState(0.0, 0.0, 0.0, 0.0, 0.0, 0.0))
        goal.step(OdomState(0.01, 0.0, 0.0, 0.2, 0.0, 0.05))
        goal.resumed(30.0)
        goal.step(OdomState(1.5, 0.0, 0.0, 0.0, 0.0, 30.1))
        assert goal.failed and 'moved 1.49 m' in goal.reason, (mode, goal.reason)
        assert goal.code == outcome.OFF_ROUTE
        assert goal.travelled < 0.02


def test_a_replay_not_moved_while_paused_goes_on():
    controller = make_goal('time', Landmark(0.2, 0.0, 0.4, 2.0, 0.0))
    controller.start(OdomState(0.0, 0.0, 0.0, 0.0, 0.0, 0.0))
    controller.pause_ended()
    controller.step(OdomState(0.001, 0.0, 0.0, 0.0, 0.0, 1.0))
    assert not controller.failed and controller.displaced == 0.001


def test_the_pause_log_names_takeovers_their_motion_and_contacts():
    log, here = PauseLog(contact_wait=2.0), [[0.0, 0.0]]
    assert log.describe(0.0) == ''
    log.update(1.0, True, False, lambda: here[0])
    here[0] = [3.0, 4.0]
    log.update(50.0, True, False, lambda: here[0])
    log.update(91.0, False, False, lambda: here[0])
    for t in (100.0, 100.5, 101.0):             # one contact bouncing
        log.update(t, False, True, lambda: here[0])
        log.update(t + 0.1, False, False, lambda: here[0])
    log.update(110.0, False, True, lambda: here[0])   # another, after contact_wait
    log.update(111.0, False, False, lambda: here[0])
    assert log.describe(120.0) == ('1 operator takeover (90.0 s, moved the robot 5.00 m); '
                                   '2 bumper contacts (2.1 s)'), log.describe(120.0)
