"""Pruning of the return route (core/pruning.py) and its drift model
(core/pruning.LoopDrift): loops, doubled-back stretches and a pass by the start are
cut at a junction within the radius, only through recorded points; a loop
whose drift the radius cannot tolerate is refused and reported; the route keeps
one section per landmark and survives its plain form; a follower drives the
pruned route home; the drift of an out-and-back matches its closed form; the
search's cost grows linearly with the path."""
import math
from types import SimpleNamespace

import pytest

from blind_navigation.core.pruning import PRUNE_DEFAULTS, LoopDrift, prune_route
from blind_navigation.core.route import Route, build_route

from unicycle import follow_route, record

V = 0.2


def circle(radius, turn):
    """(v, w, s) of a full circle of ``radius`` turning ``turn`` (+1 left, -1 right)."""
    return (V, turn * V / radius, 2.0 * math.pi * radius / V)


FIGURE_EIGHT = [(V, 0.0, 5.0), circle(0.6, 1), circle(0.6, -1), (V, 0.0, 5.0)]
# into a 2 m dead end, a pause, backed out all the way, on to the right
DEAD_END = [(V, 0.0, 5.0), (0.0, 0.8, math.pi / 1.6), (V, 0.0, 10.0), (0.0, 0.0, 1.0),
            (-0.1, 0.0, 20.0), (0.0, -0.8, math.pi / 1.6), (V, 0.0, 7.5)]
# round a 1.5 m square from the start, back at the start, then 1 m away from it
PATROL = [(V, 0.0, 7.5), (0.0, 0.8, math.pi / 1.6)] * 4 + [(0.0, -0.8, math.pi / 1.6), (V, 0.0, 5.0)]
NO_DRIFT = SimpleNamespace(wheel_error_per_m=0.0, gyro_noise_density=0.0, uncorrected_bias_std=0.0,
                           uncorrected_scale_std=0.0)


def pruned(profile, params=None):
    landmarks, end = record(profile, events=True)
    route = build_route(landmarks, (end.x, end.y))
    return landmarks, end, route, prune_route(route, landmarks, None, params)


def drive_home(route, end):
    robot, follower = follow_route(route, (end.x, end.y, end.yaw + math.pi))
    assert follower.done, follower.reason
    return robot, follower


def on_route(route, x, y):
    """(distance along ``route``, distance from it) of the route point nearest (x, y)."""
    best = (math.hypot(route.x[0] - x, route.y[0] - y), 0.0)
    for a in range(route.vertices - 1):
        dx, dy = route.x[a + 1] - route.x[a], route.y[a + 1] - route.y[a]
        length_sq = dx * dx + dy * dy
        share = 0.0 if length_sq == 0 else max(0.0, min(1.0, ((x - route.x[a]) * dx + (y - route.y[a]) * dy)
                                                             / length_sq))
        off = math.hypot(route.x[a] + share * dx - x, route.y[a] + share * dy - y)
        if off < best[0]:
            best = (off, route.s[a] + share * (route.s[a + 1] - route.s[a]))
    return best[1], best[0]


@pytest.mark.parametrize('profile, shortest', [(FIGURE_EIGHT, 2.0), (DEAD_END, 2.5), (PATROL, 2.0)],
                         ids=['figure eight', 'dead end backed out of', 'patrol past the start'])
def test_loops_are_cut_at_a_junction_through_recorded_points_only(profile, shortest):
    landmarks, end, route, result = pruned(profile)
    assert result.cuts and result.route.length < route.length - shortest
    new = result.route
    assert (new.x[0], new.y[0]) == (route.x[0], route.y[0])
    assert (new.x[-1], new.y[-1]) == (route.x[-1], route.y[-1])      # the start, exactly
    previous = None
    for x, y in zip(new.x, new.y):      # every vertex is on the recorded path, in return order
        along, off = on_route(route, x, y)
        assert off < 1e-9
        if previous is not None:
            assert along > previous[0]
            if along - previous[0] > 0.5:     # a junction: the chord joins two passes
                chord = math.hypot(x - previous[1], y - previous[2])
                assert chord <= PRUNE_DEFAULTS['prune_radius']
                assert along - previous[0] >= PRUNE_DEFAULTS['prune_min_loop']
        previous = (along, x, y)
    assert len(new.sections) == len(landmarks)
    marks = [new.section_end(i) for i in range(len(new.sections))]
    assert marks == sorted(marks)


def test_sections_inside_a_cut_end_at_its_junction_which_is_a_corner():
    _, _, route, result = pruned(DEAD_END)
    new = result.route
    junctions = set()
    for cut in result.cuts:
        junction = [v for v in range(new.vertices) if (new.x[v], new.y[v]) == cut.later_xy][0]
        junctions.add(junction)
        assert new.corner[junction]
    inside = [i for i, section in enumerate(route.sections)
              if any(c.later < section.end_vertex < c.earlier for c in result.cuts)]
    assert inside
    for index in inside:
        assert new.sections[index].end_vertex in junctions
        assert new.sections[index].nominal_time == 0.0


def test_passing_the_start_again_the_return_goes_home_from_there():
    _, _, route, result = pruned(PATROL)
    last = result.cuts[-1]
    assert last.earlier >= route.vertices - 3      # to the start (or within its first points)
    assert result.route.length < 1.2               # the metre away from the start, back


@pytest.mark.parametrize('profile', [FIGURE_EIGHT, DEAD_END, PATROL], ids=['eight', 'dead end', 'patrol'])
def test_a_follower_drives_the_pruned_route_home_along_it(profile):
    _, end, route, result = pruned(profile)
    robot, follower = drive_home(result.route, end)
    assert math.hypot(robot.x - route.x[-1], robot.y - route.y[-1]) < 0.02
    assert follower.travelled == pytest.approx(result.route.length, rel=0.05)


def test_the_pruned_route_survives_its_plain_form():
    _, _, _, result = pruned(DEAD_END)
    again = Route.from_lists(result.route.to_lists())
    assert again.to_lists() == result.route.to_lists()
    assert [again.section_end(i) for i in range(len(again.sections))] == \
        [result.route.section_end(i) for i in range(len(result.route.sections))]


def test_a_loop_whose_drift_the_radius_cannot_tolerate_is_refused_and_reported():
    _, _, _, free = pruned(FIGURE_EIGHT, NO_DRIFT)
    assert free.cuts and not free.refused
    wheels = SimpleNamespace(wheel_error_per_m=0.05)     # 5 % per metre: 0.19 m over one lobe
    _, _, route, result = pruned(FIGURE_EIGHT, wheels)
    assert not result.cuts and result.route is route
    assert result.refused
    worst = max(result.refused, key=lambda c: c.length)
    assert worst.gap + 2.0 * worst.sigma_total > PRUNE_DEFAULTS['prune_radius']
    text = '\n'.join(result.describe())
    assert 'refused a %.2f m' % worst.length in text and '> prune_radius 0.175 m' in text


def test_cuts_carry_the_drift_of_the_cuts_before():
    _, _, _, result = pruned(FIGURE_EIGHT)
    assert len(result.cuts) == 2                 # one lobe, then the other
    first, second = result.cuts
    assert first.sigma_total == pytest.approx(first.sigma)
    assert second.sigma_total > second.sigma
    assert 'cut a %.2f m' % first.length in result.describe()[0]


def test_drift_of_an_out_and_back_matches_its_closed_form():
    length, rate = 2.0, 0.5
    turn = math.pi / rate
    landmarks, end = record([(V, 0.0, length / V), (0.0, rate, turn), (V, 0.0, length / V)], events=True)
    route = build_route(landmarks, (end.x, end.y))
    u, w = 0, route.vertices - 1

    def sigma(**stds):
        params = SimpleNamespace(**dict(vars(NO_DRIFT), **stds))
        model = LoopDrift(route, landmarks, None, params)
        return model.sigma(model.loop(u, w)[1])
    # bias: |sum (t - t_w) dX| = L^2 / v + L x turn time; scale: pi L; wheels: k 2 L;
    # white noise: density^2 (2 L^3 / (3 v) + L^2 x turn time)
    assert sigma(uncorrected_bias_std=1.0) == pytest.approx(length ** 2 / V + length * turn, rel=0.03)
    assert sigma(uncorrected_scale_std=1.0) == pytest.approx(math.pi * length, rel=0.03)
    assert sigma(wheel_error_per_m=1.0) == pytest.approx(2.0 * length, rel=0.03)
    assert sigma(gyro_noise_density=1.0) == pytest.approx(
        math.sqrt(2.0 * length ** 3 / (3.0 * V) + length ** 2 * turn), rel=0.03)
    duration, _ = LoopDrift(route, landmarks).loop(u, w)
    assert duration == pytest.approx(2.0 * length / V + turn, rel=0.01)
    assert route.s[w] - route.s[u] == pytest.approx(2.0 * length, rel=0.01)
    assert math.hypot(route.x[u] - route.x[w], route.y[u] - route.y[w]) < 0.01


def test_the_correction_s_uncertainty_is_used_where_it_corrected():
    landmarks, end = record(FIGURE_EIGHT, events=True)
    route = build_route(landmarks, (end.x, end.y))
    corrected = SimpleNamespace(bias_std=1e-5, scale_std=1e-4)
    uncorrected = SimpleNamespace(bias_std=math.inf, scale_std=math.inf)
    tight, loose = LoopDrift(route, landmarks, corrected), LoopDrift(route, landmarks, uncorrected)
    assert (tight.bias_std, tight.scale_std) == (1e-5, 1e-4)
    assert (loose.bias_std, loose.scale_std) == (PRUNE_DEFAULTS['uncorrected_bias_std'],
                                                 PRUNE_DEFAULTS['uncorrected_scale_std'])


def test_bad_params_and_inputs_are_named():
    landmarks, end = record(FIGURE_EIGHT, events=True)
    route = build_route(landmarks, (end.x, end.y))
    with pytest.raises(ValueError, match='prune_radius'):
        prune_route(route, landmarks, params=SimpleNamespace(prune_radius=0.0))
    with pytest.raises(ValueError, match='wheel_error_per_m'):
        prune_route(route, landmarks, params=SimpleNamespace(wheel_error_per_m=-0.01))
    with pytest.raises(ValueError, match='landmarks for a route of'):
        prune_route(route, landmarks[1:])


def test_nothing_to_cut_leaves_the_route_as_it_is():
    landmarks, end = record([(V, 0.3, 8.0), (V, 0.0, 10.0)], events=True)
    route = build_route(landmarks, (end.x, end.y))
    result = prune_route(route, landmarks)
    assert result.route is route and not result.cuts and not result.refused
    empty = build_route([], (0.0, 0.0))
    assert prune_route(empty, []).route is empty


def test_the_search_costs_the_same_per_vertex_on_a_four_times_longer_path():
    def examined(rounds):
        # ``rounds`` 5 m corridors 1 m apart, each driven out and back: every place is
        # passed twice however long the path
        profile = []
        for _ in range(rounds):
            profile += [(0.0, 0.8, math.pi / 1.6), (V, 0.0, 25.0), (0.0, 0.8, math.pi / 0.8),
                        (V, 0.0, 25.0), (0.0, 0.8, math.pi / 1.6), (V, 0.0, 5.0)]
        landmarks, end = record(profile)
        route = build_route(landmarks, (end.x, end.y))
        result = prune_route(route, landmarks, None, SimpleNamespace(wheel_error_per_m=1.0))
        return result.examined / float(route.vertices)
    assert examined(8) < 1.5 * examined(2)


@pytest.mark.parametrize('profile', [FIGURE_EIGHT, DEAD_END], ids=['eight', 'dead end'])
def test_a_return_resumed_at_any_goal_follows_the_same_pruned_route_home(profile):
    _, end, route, result = pruned(profile)
    kept = Route.from_lists(result.route.to_lists())      # as the progress file keeps it
    inside = [i for i, section in enumerate(route.sections)
              if any(c.later < section.end_vertex < c.earlier for c in result.cuts)]
    for done in sorted({1, inside[0], inside[0] + 1, inside[-1] + 1, len(kept.sections) // 2}):
        vertex = kept.sections[done - 1].end_vertex
        start = (kept.x[vertex], kept.y[vertex], kept.direction(min(vertex, kept.vertices - 2)))
        robot, follower = follow_route(kept, start, section=done)
        assert follower.done, (done, follower.reason)
        assert math.hypot(robot.x - kept.x[-1], robot.y - kept.y[-1]) < 0.02
        assert follower.travelled <= kept.length - kept.s[vertex] + 0.05
