"""The closed-loop follower on a base with kobuki_driver's acceleration limiter and a
lagging motor (sim/kobuki.py, exact otherwise): it brakes to a stop within the
limiter's deceleration, so the robot stops at the corners and at the route's end
where the follower planned (issue 29; docs/back_travel.md, "The route follower")."""
from types import SimpleNamespace

import pytest

from blind_navigation.core.back_travel import BACK_TRAVEL_DEFAULTS
from blind_navigation.core.geometry import OdomState, Pose2D, distance
from blind_navigation.core.goal import make_goal
from blind_navigation.core.route import build_route
from blind_navigation.core.route_follower import RouteFollower
from blind_navigation.sim.kobuki import ACCEL_LIMITS, SimulatedKobuki

from test_back_travel import CORNERS, FAST, turn_around
from unicycle import DT, IDEAL, record

LAG = 0.25          # s, the motor's time constant (the paper profile's)
PATHS = {'corners': CORNERS, 'fast': FAST, 'straight': [(0.5, 0.0, 6.0)]}


def _robot(end):
    """The base at ``end`` (turned by pi), with the limiter and the lag."""
    turned = turn_around(end)
    profile = dict(IDEAL, acceleration_limiter=True, motor_time_constant=LAG)
    return SimulatedKobuki(profile, start=Pose2D(turned.x, turned.y, turned.yaw))


def _odom(base):
    pose, (v, w) = base.true_pose, base.true_twist
    return OdomState(pose.x, pose.y, pose.yaw, v, w, base.t)


def _drive(profile):
    """(route, base, follower, commands) of the route of ``profile`` driven home."""
    landmarks, end = record(profile, events=True)
    route = build_route(landmarks, (end.x, end.y))
    base = _robot(end)
    follower, commands = RouteFollower(route, SimpleNamespace(stop_lead=LAG)), []
    for index in range(len(route.sections)):
        goal = make_goal('closed_loop', None, None, follower, index)
        goal.start(_odom(base))
        while not goal.done and not goal.failed:
            v, w = goal.step(_odom(base))
            if goal.done or goal.failed:
                break
            commands.append((follower.mode, v))
            base.command(v, w)
            base.step(DT)
            assert len(commands) < 100000, 'the follower did not finish'
    base.command(0.0, 0.0)
    base.step(3.0)
    return route, base, follower, commands


def test_the_follower_knows_the_kobukis_limits():
    assert BACK_TRAVEL_DEFAULTS['brake_decel'] <= ACCEL_LIMITS['v_down']


@pytest.mark.parametrize('name', sorted(PATHS))
def test_the_robot_stops_where_the_follower_planned_despite_the_limiter(name):
    route, base, follower, commands = _drive(PATHS[name])
    assert follower.done, follower.reason
    # the stop: within a few centimetres of the route's end, not a coast past it
    assert distance(base.true_pose.x, base.true_pose.y, route.x[-1], route.y[-1]) < 0.03


def test_braking_on_a_straight_is_within_the_limiter():
    # the base then follows the command: no coast the follower did not plan
    commands = _drive(PATHS['straight'])[3]
    slowing = [a[1] - b[1] for a, b in zip(commands, commands[1:]) if a[0] == b[0] == 'driving']
    assert 0.0 < max(slowing) <= ACCEL_LIMITS['v_down'] * DT + 1e-9
