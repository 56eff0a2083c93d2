"""Property tests (hypothesis) of the pruned return: whatever valid landmarks a
recording holds (any landmarks; and paths of random pieces that come back:
circles, out-and-backs reversing or turning round), pruning (with no drift, so
that it cuts wherever passes meet, and with the defaults) gives a route through
points of the recorded path only, in order, whose chords join passes within
the radius, with one section per landmark in order; it survives its plain form
and a follower drives it home without aborting."""
import math
from types import SimpleNamespace

from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from blind_navigation.core.geometry import distance
from blind_navigation.core.pruning import PRUNE_DEFAULTS, prune_route
from blind_navigation.core.route import Route, build_route

from test_pruning import on_route
from test_route_properties import ANCHOR, BACK_AT_THE_START, LANDMARK
from unicycle import follow_route, record

CUT_ANYWHERE = SimpleNamespace(wheel_error_per_m=0.0, gyro_noise_density=0.0, uncorrected_bias_std=0.0,
                               uncorrected_scale_std=0.0, prune_radius=0.3, prune_min_loop=0.3)


SPEED, SECONDS = st.floats(0.05, 0.4), st.floats(0.5, 8.0)
PIECE = st.one_of(
    st.builds(lambda v, t: [(v, 0.0, t)], SPEED, SECONDS),
    st.builds(lambda v, w, t: [(v, w, t)], SPEED, st.floats(-1.0, 1.0), SECONDS),
    st.builds(lambda w, t: [(0.0, w, t)], st.floats(-1.5, 1.5), st.floats(0.2, 4.0)),
    st.builds(lambda v, t: [(v, 0.0, t), (0.0, 0.0, 0.5), (-v, 0.0, t)], SPEED, SECONDS),   # backed out
    st.builds(lambda v, t, turn: [(v, 0.0, t), (0.0, turn, math.pi / abs(turn)), (v, 0.0, t)],
              SPEED, SECONDS, st.sampled_from([-0.8, 0.8])),                               # out and back
    st.builds(lambda v, radius, side: [(v, side * v / radius, 2.0 * math.pi * radius / v)],
              SPEED, st.floats(0.3, 1.5), st.sampled_from([-1.0, 1.0])))                 # a full circle
LOOPS = st.lists(PIECE, min_size=1, max_size=5).map(lambda pieces: [p for piece in pieces for p in piece])
DEFAULTS = None


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(LOOPS, st.sampled_from([CUT_ANYWHERE, DEFAULTS]))
def test_pruned_paths_that_come_back_run_through_the_recorded_path_in_order(profile, params):
    landmarks, end = record(profile, events=True)
    check_pruned(landmarks, (end.x, end.y), params)


@settings(max_examples=120, deadline=None)
@given(st.lists(LANDMARK, max_size=40), ANCHOR)
@example(*BACK_AT_THE_START)
def test_any_pruned_route_runs_through_the_recorded_path_in_order(landmarks, anchor):
    check_pruned(landmarks, anchor, CUT_ANYWHERE)


def check_pruned(landmarks, anchor, params):
    route = build_route(landmarks, anchor)
    result = prune_route(route, landmarks, None, params)
    radius = getattr(params, 'prune_radius', PRUNE_DEFAULTS['prune_radius'])
    min_loop = getattr(params, 'prune_min_loop', PRUNE_DEFAULTS['prune_min_loop'])
    new = result.route
    n = len(landmarks)
    assert len(new.sections) == n and new.length <= route.length + 1e-9
    marks = [new.section_end(i) for i in range(n)]
    assert marks == sorted(marks)
    assert (new.x[0], new.y[0]) == (route.x[0], route.y[0]) or result.cuts[0].gap < 0.01
    assert (new.x[-1], new.y[-1]) == (route.x[-1], route.y[-1])
    previous = None
    for x, y in zip(new.x, new.y):
        along, off = on_route(route, x, y)
        assert off < 1e-6
        if previous is not None:
            assert distance(x, y, previous[1], previous[2]) <= max(radius, along - previous[0] + 1e-6)
        previous = (along, x, y)
    for cut in result.cuts:
        assert cut.gap <= radius and cut.length >= min_loop
    again = Route.from_lists(new.to_lists())
    assert again.x == new.x and [again.section_end(i) for i in range(n)] == marks


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(LOOPS, st.floats(-math.pi, math.pi))
def test_no_pruned_route_makes_the_follower_abort(profile, yaw):
    landmarks, end = record(profile, events=True)
    anchor = (end.x, end.y)
    route = prune_route(build_route(landmarks, anchor), landmarks, None, CUT_ANYWHERE).route
    robot, follower = follow_route(route, (anchor[0], anchor[1], yaw), dt=0.05, limit=40000)
    assert follower.done and not follower.failed, follower.reason
    assert all(follower.section_finished(i) for i in range(len(landmarks)))
    assert distance(robot.x, robot.y, route.x[-1], route.y[-1]) < 0.05
